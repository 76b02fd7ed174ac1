"""Compile CasADi SX functions of the tether follower to plain Python/numpy code.

The follower's physics (kinematics, tether sensor, control laws) is written
once with CasADi symbols. The closed loop runs thousands of small steps, where
calling a :class:`casadi.Function` per step (microseconds of overhead) or
replaying its instruction list (:func:`designlab.symbolic.vectorize`) would
dominate. :func:`compile_sx` turns the SX instruction list into the source of
one Python function, once, with every operation bound either to numpy (for a
batch of designs: arrays of any shape broadcast) or to :mod:`math` (for one
design: Python floats, about 0.1 us per operation).

Examples
--------
>>> import casadi as ca
>>> x = ca.SX.sym("x"); y = ca.SX.sym("y")
>>> f = ca.Function("f", [x, y], [ca.atan2(y, x), ca.fmax(x, 0) * y])
>>> g = compile_sx(f)
>>> [round(v, 4) for v in g(-1.0, 2.0)]
[2.0344, 0.0]
>>> import numpy as np
>>> gb = compile_sx(f, batch=True)
>>> np.round(gb(np.array([1.0, -1.0]), 2.0)[1], 3)
array([2., 0.])
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import casadi as ca
import numpy as np

__all__ = ["compile_sx"]

# operation -> (numpy template, scalar template); {0}, {1} are the operands.
_OPS: dict[int, tuple[str, str]] = {
    ca.OP_ADD: ("({0} + {1})", "({0} + {1})"),
    ca.OP_SUB: ("({0} - {1})", "({0} - {1})"),
    ca.OP_MUL: ("({0} * {1})", "({0} * {1})"),
    ca.OP_DIV: ("({0} / {1})", "({0} / {1})"),
    ca.OP_POW: ("({0} ** {1})", "({0} ** {1})"),
    ca.OP_CONSTPOW: ("({0} ** {1})", "({0} ** {1})"),
    ca.OP_FMIN: ("_np.minimum({0}, {1})", "min({0}, {1})"),
    ca.OP_FMAX: ("_np.maximum({0}, {1})", "max({0}, {1})"),
    ca.OP_LT: ("({0} < {1})", "float({0} < {1})"),
    ca.OP_LE: ("({0} <= {1})", "float({0} <= {1})"),
    ca.OP_EQ: ("({0} == {1})", "float({0} == {1})"),
    ca.OP_NE: ("({0} != {1})", "float({0} != {1})"),
    ca.OP_AND: ("(({0} != 0) & ({1} != 0))", "float(({0} != 0) and ({1} != 0))"),
    ca.OP_OR: ("(({0} != 0) | ({1} != 0))", "float(({0} != 0) or ({1} != 0))"),
    ca.OP_IF_ELSE_ZERO: ("_np.where({0}, {1}, 0.0)", "({1} if {0} else 0.0)"),
    ca.OP_ATAN2: ("_np.arctan2({0}, {1})", "_m.atan2({0}, {1})"),
    ca.OP_COPYSIGN: ("_np.copysign({0}, {1})", "_m.copysign({0}, {1})"),
    ca.OP_FMOD: ("_np.fmod({0}, {1})", "_m.fmod({0}, {1})"),
    ca.OP_NEG: ("(-{0})", "(-{0})"),
    ca.OP_SQ: ("({0} * {0})", "({0} * {0})"),
    ca.OP_TWICE: ("(2.0 * {0})", "(2.0 * {0})"),
    ca.OP_INV: ("(1.0 / {0})", "(1.0 / {0})"),
    ca.OP_SQRT: ("_np.sqrt({0})", "_m.sqrt({0})"),
    ca.OP_EXP: ("_np.exp({0})", "_m.exp({0})"),
    ca.OP_LOG: ("_np.log({0})", "_m.log({0})"),
    ca.OP_SIN: ("_np.sin({0})", "_m.sin({0})"),
    ca.OP_COS: ("_np.cos({0})", "_m.cos({0})"),
    ca.OP_TAN: ("_np.tan({0})", "_m.tan({0})"),
    ca.OP_ATAN: ("_np.arctan({0})", "_m.atan({0})"),
    ca.OP_FABS: ("_np.abs({0})", "abs({0})"),
    ca.OP_SIGN: ("_np.sign({0})", "_sign({0})"),
    ca.OP_FLOOR: ("_np.floor({0})", "float(_m.floor({0}))"),
    ca.OP_CEIL: ("_np.ceil({0})", "float(_m.ceil({0}))"),
    ca.OP_NOT: ("({0} == 0)", "float({0} == 0)"),
    ca.OP_ASSIGN: ("{0}", "{0}"),
}


def _sign(a: float) -> float:
    return (a > 0) - (a < 0) + 0.0


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
        uses an operation without a Python equivalent.
    """
    if not f.is_a("SXFunction"):
        raise TypeError(f"compile_sx needs an SX function, got {f.class_name()}")
    for i in range(f.n_in()):
        if f.sparsity_in(i).numel() != 1:
            raise TypeError(f"input {f.name_in(i)} of {f.name()} is not scalar")
    for i in range(f.n_out()):
        if f.sparsity_out(i).numel() != 1:
            raise TypeError(f"output {f.name_out(i)} of {f.name()} is not scalar")
    col = 0 if batch else 1
    lines = [f"def _f({', '.join(f'i{k}' for k in range(f.n_in()))}):"]
    outputs = ["0.0"] * f.n_out()
    for k in range(f.n_instructions()):
        op = f.instruction_id(k)
        ins = list(f.instruction_input(k))
        outs = list(f.instruction_output(k))
        if op == ca.OP_INPUT:
            lines.append(f"    w{outs[0]} = i{ins[0]}")
        elif op == ca.OP_OUTPUT:
            lines.append(f"    o{outs[0]} = w{ins[0]}")
            outputs[outs[0]] = f"o{outs[0]}"
        elif op == ca.OP_CONST:
            lines.append(f"    w{outs[0]} = {float(f.instruction_constant(k))!r}")
        elif op in _OPS:
            args = [f"w{i}" for i in ins]
            lines.append(f"    w{outs[0]} = " + _OPS[op][col].format(*args))
        else:
            raise TypeError(f"operation {op} of {f.name()} has no Python equivalent")
    # SX outputs that are plain constants never reach OP_OUTPUT as a work variable
    lines.append(f"    return ({', '.join(outputs)},)")
    source = "\n".join(lines).replace("inf", "_inf")
    namespace: dict[str, Any] = {"_np": np, "_m": math, "_sign": _sign, "_inf": math.inf}
    exec(compile(source, f"<compile_sx {f.name()}>", "exec"), namespace)
    fn: Callable[..., tuple[Any, ...]] = namespace["_f"]
    return fn
