"""An SX function's instruction list, read once for every back end of :mod:`designlab.sx`.

Examples
--------
>>> import casadi as ca
>>> x = ca.SX.sym("x", 2)
>>> prog = read_program(ca.Function("f", [x], [ca.sin(x[0]) * x[1]]), "numpy")
>>> [OPS[i.op].name for i in prog.instructions if i.op in OPS]
['sin', 'mul']
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca

from designlab.sx.ops import OPS, STRUCTURAL

__all__ = [
    "Instruction",
    "Program",
    "UnsupportedOperation",
    "check_sx",
    "read_program",
    "with_cse",
]


class UnsupportedOperation(TypeError, ValueError):
    """The function is not an SX function, or uses an operation a back end does not translate.

    A ``TypeError`` (what :func:`designlab.sx.vectorize` and
    :func:`designlab.sx.compile_sx` always raised) and a ``ValueError`` (what
    :func:`designlab.sx.compile_lanes` raised).
    """


@dataclass(frozen=True)
class Instruction:
    """One instruction: ``outs = op(ins)``.

    Attributes
    ----------
    op
        CasADi's operation code.
    ins, outs
        Work-vector indices (``OP_INPUT``: ``ins`` is (input, nonzero);
        ``OP_OUTPUT``: ``outs`` is (output, nonzero)).
    const
        The value of an ``OP_CONST``, else ``None``.
    """

    op: int
    ins: tuple[int, ...]
    outs: tuple[int, ...]
    const: float | None = None


@dataclass(frozen=True)
class Program:
    """The instruction list of an SX function and the sizes its evaluators need.

    Attributes
    ----------
    name
        The function's name.
    instructions
        In evaluation order.
    n_work
        Size of the work vector.
    nnz_in, nnz_out
        Structural nonzeros of each input and output.
    """

    name: str
    instructions: tuple[Instruction, ...]
    n_work: int
    nnz_in: tuple[int, ...]
    nnz_out: tuple[int, ...]


def _instruction(f: ca.Function, k: int) -> Instruction:
    op = f.instruction_id(k)
    const = float(f.instruction_constant(k)) if op == ca.OP_CONST else None
    return Instruction(op, tuple(f.instruction_input(k)), tuple(f.instruction_output(k)), const)


def read_program(f: ca.Function, backend: str) -> Program:
    """Read the instruction list of ``f``, checking ``backend`` translates every operation.

    Parameters
    ----------
    f
        A CasADi SX function.
    backend
        ``"numpy"``, ``"python"`` or ``"c"``: the :class:`~designlab.sx.ops.Op` form required.

    Raises
    ------
    UnsupportedOperation
        If ``f`` is not an SX function or has an operation without that form (a call
        to another function, for example).
    """
    check_sx(f)
    instructions = tuple(_instruction(f, k) for k in range(f.n_instructions()))
    for ins in instructions:
        if ins.op not in STRUCTURAL and getattr(OPS.get(ins.op), backend, None) is None:
            raise UnsupportedOperation(
                f"operation {_op_name(ins.op)} of {f.name()!r} has no {backend} translation"
            )
    return Program(
        f.name(),
        instructions,
        int(f.sz_w()),
        tuple(f.nnz_in(i) for i in range(f.n_in())),
        tuple(f.nnz_out(i) for i in range(f.n_out())),
    )


def check_sx(f: object) -> None:
    """Raise :class:`UnsupportedOperation` unless ``f`` is a CasADi SX function.

    Parameters
    ----------
    f
        What should be a ``casadi.Function`` of SX type.
    """
    if not isinstance(f, ca.Function) or not f.is_a("SXFunction"):
        kind = f.class_name() if isinstance(f, ca.Function) else type(f).__name__
        raise UnsupportedOperation(f"{_name(f)!r} is not an SX function (it is {kind})")


def with_cse(f: ca.Function) -> ca.Function:
    """``f`` rebuilt with common subexpressions evaluated once (exact: same operands).

    Parameters
    ----------
    f
        A CasADi SX function.

    Examples
    --------
    >>> import casadi as ca
    >>> x = ca.SX.sym("x")
    >>> f = ca.Function("f", [x], [ca.sin(x) * (ca.sin(x) + 1)])
    >>> with_cse(f).n_instructions() < f.n_instructions()
    True
    """
    return ca.Function(
        f.name(), f.sx_in(), f.call(f.sx_in()), f.name_in(), f.name_out(), {"cse": True}
    )


def _name(f: object) -> str:
    return f.name() if isinstance(f, ca.Function) else repr(f)


def _op_name(op: int) -> str:
    known = {getattr(ca, n): n for n in dir(ca) if n.startswith("OP_")}
    return f"{op} ({known.get(op, 'unknown')})"
