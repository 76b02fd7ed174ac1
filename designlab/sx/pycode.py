"""Compile CasADi SX functions of scalars to plain Python (floats) or numpy code.

A closed loop of thousands of small steps (the tether follower's control periods)
would spend its time calling a :class:`casadi.Function` per step (microseconds of
overhead) or replaying its instruction list (:func:`designlab.sx.vectorize`).
:func:`compile_sx` turns the SX instruction list into the source of one Python
function, once, with every operation written in the Python or numpy form of the one
operation table (:data:`designlab.sx.ops.OPS`): on Python floats with :mod:`math`
(about 0.1 us per operation) or, with ``batch=True``, on numpy arrays of any
broadcastable shape.

The float form follows CasADi's virtual machine on NaN, infinities and signed zeros:
where :mod:`math` refuses a value IEEE-754 defines (``sqrt(-1)``, ``1/0``,
``exp(1000)``), the whole call is recomputed with the numpy forms on the same floats.

Examples
--------
>>> import casadi as ca
>>> x = ca.SX.sym("x"); y = ca.SX.sym("y")
>>> f = ca.Function("f", [x, y], [ca.atan2(y, x), ca.fmax(x, 0) * y])
>>> g = compile_sx(f)
>>> [round(v, 4) for v in g(-1.0, 2.0)]
[2.0344, 0.0]
>>> g(0.0, float("nan"))[1]            # fmax(0, 0) * NaN
nan
>>> import numpy as np
>>> gb = compile_sx(f, batch=True)
>>> np.round(gb(np.array([1.0, -1.0]), 2.0)[1], 3)
array([2., 0.])
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import cache
from typing import Any

import casadi as ca
import numpy as np

from designlab.sx.ops import NAMESPACE, OPS
from designlab.sx.program import Program, UnsupportedOperation, read_program

__all__ = ["compile_sx", "python_source"]


def _literal(value: float) -> str:
    """A Python expression of the constant (exact; NaN and infinities by name)."""
    if math.isnan(value):
        return "_nan"
    if math.isinf(value):
        return "_inf" if value > 0 else "(-_inf)"
    return repr(float(value))


def _body(prog: Program, form: str) -> list[str]:
    """Assignments of the program in the ``form`` (``"python"`` or ``"numpy"``) of OPS."""
    lines = []
    for ins in prog.instructions:
        if ins.op == ca.OP_INPUT:
            lines.append(f"w{ins.outs[0]} = i{ins.ins[0]}")
        elif ins.op == ca.OP_OUTPUT:
            lines.append(f"o{ins.outs[0]} = w{ins.ins[0]}")
        elif ins.op == ca.OP_CONST:
            lines.append(f"w{ins.outs[0]} = {_literal(ins.const)}")  # type: ignore[arg-type]
        else:
            template: str = getattr(OPS[ins.op], form)
            lines.append(f"w{ins.outs[0]} = " + template.format(*(f"w{i}" for i in ins.ins)))
    return lines


def python_source(prog: Program, form: str, name: str = "_f") -> str:
    """Source of ``def name(i0, i1, ...)`` returning the tuple of outputs.

    Parameters
    ----------
    prog
        A program of scalar inputs and outputs (:func:`~designlab.sx.program.read_program`).
    form
        ``"python"``: floats with :mod:`math`, recomputed by ``_exact`` (numpy forms)
        where :mod:`math` raises; ``"numpy"``: numpy forms throughout.
    name
        The function's name.
    """
    args = ", ".join(f"i{k}" for k in range(len(prog.nnz_in)))
    outputs = [f"o{k}" for k in range(len(prog.nnz_out))]
    reached = {ins.outs[0] for ins in prog.instructions if ins.op == ca.OP_OUTPUT}
    # an output that is a structural zero has no instruction
    ret = ", ".join(o if k in reached else "0.0" for k, o in enumerate(outputs))
    body = [*_body(prog, form), f"return ({ret},)"]
    if form == "numpy":
        return f"def {name}({args}):\n" + "".join(f"    {line}\n" for line in body)
    return (
        f"def {name}({args}):\n    try:\n"
        + "".join(f"        {line}\n" for line in body)
        + f"    except (ArithmeticError, ValueError):\n        return _exact({args})\n"
    )


def _load(source: str, filename: str, name: str, namespace: dict[str, Any]) -> Callable[..., Any]:
    exec(compile(source, filename, "exec"), namespace)
    fn: Callable[..., Any] = namespace[name]
    return fn


def _check_scalar(f: ca.Function) -> None:
    for i in range(f.n_in()):
        if f.sparsity_in(i).numel() != 1:
            raise UnsupportedOperation(f"input {f.name_in(i)} of {f.name()} is not scalar")
    for i in range(f.n_out()):
        if f.sparsity_out(i).numel() != 1:
            raise UnsupportedOperation(f"output {f.name_out(i)} of {f.name()} is not scalar")


def compile_sx(f: ca.Function, *, batch: bool = False) -> Callable[..., tuple[Any, ...]]:
    """Return a Python function evaluating the scalar-input SX function ``f``.

    Parameters
    ----------
    f
        A :class:`casadi.Function` of SX type whose inputs and outputs are all
        scalars (1 x 1).
    batch
        False: operations on Python floats (:mod:`math`); True: numpy
        operations, so every argument may be an array (broadcast).

    Returns
    -------
    callable
        ``g(*inputs) -> tuple(outputs)``.

    Raises
    ------
    TypeError
        If ``f`` is not an SX function, has a non-scalar input or output, or
        uses an operation without a Python equivalent
        (:class:`~designlab.sx.UnsupportedOperation`).
    """
    prog = read_program(f, "numpy")
    if not batch:
        read_program(f, "python")
    _check_scalar(f)
    namespace: dict[str, Any] = {**NAMESPACE, "_nan": math.nan, "_inf": math.inf}
    filename = f"<compile_sx {prog.name}>"
    if batch:
        return _load(python_source(prog, "numpy"), filename, "_f", namespace)

    @cache
    def numpy_form() -> Callable[..., Any]:  # built the first time math refuses a value
        return _load(python_source(prog, "numpy"), filename, "_f", dict(namespace))

    def ieee(*args: float) -> tuple[float, ...]:
        with np.errstate(all="ignore"):
            return tuple(float(v) for v in numpy_form()(*(np.float64(a) for a in args)))

    return _load(python_source(prog, "python"), filename, "_f", {**namespace, "_exact": ieee})
