"""The one operation table: every CasADi SX operation, its numpy, Python and C forms.

Each entry says how one instruction of an SX function is evaluated by every back end
of :mod:`designlab.sx`, with the semantics of CasADi's virtual machine (which calls
the C library): ``fmin``/``fmax`` return the other argument when one is NaN and the
first on ties (also ``+0``/``-0``); ``sign`` keeps ``-0`` and NaN; ``floor``/``ceil``
keep the sign of zero; comparisons and logic give 1.0/0.0 with NaN true as a
condition and false in every comparison; ``if_else_zero(c, y)`` is ``y`` unless
``c == 0``.

The forms are templates on the operands ``{0}`` and ``{1}`` (operand names, never
expressions, so an operand may appear twice):

* ``numpy``: arrays or numbers of any broadcastable shape (module ``_np``, the names
  in :data:`NAMESPACE`);
* ``python``: Python floats with :mod:`math` (module ``_m``); it may raise
  (``ValueError``, ``ArithmeticError``) where IEEE-754 gives NaN or an infinity, and
  the evaluator then recomputes with the numpy form (see :mod:`designlab.sx.pycode`);
* ``c``: vectors of four doubles (``v4``, GCC/Clang vector extensions), helpers in
  :data:`designlab.sx.lanes.PRELUDE`; every operation rounded as the virtual machine
  rounds it (no contraction to fused multiply-add).

``None`` means the back end has no translation of the operation.

Examples
--------
>>> import casadi as ca
>>> OPS[ca.OP_FMIN].name, OPS[ca.OP_FMIN].arity
('fmin', 2)
>>> OPS[ca.OP_FMIN].python.format("a", "b")
'(a if (a <= b or b != b) else b)'
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

__all__ = ["NAMESPACE", "OPS", "STRUCTURAL", "Op"]


@dataclass(frozen=True)
class Op:
    """One SX operation in every back end.

    Attributes
    ----------
    code
        CasADi's operation code (``casadi.OP_*``).
    name
        Its name (``casadi.OP_<NAME>`` in lower case).
    arity
        Operands (1 or 2).
    numpy, python, c
        Templates of the numpy, scalar-Python and four-lane C forms (``None``: none).
    """

    code: int
    name: str
    arity: int
    numpy: str | None
    python: str | None
    c: str | None


def _lib1(name: str, np_name: str | None = None) -> tuple[str, str, str]:
    """numpy, math and lane-wise C forms of a C-library function of one argument."""
    return f"_np.{np_name or name}({{0}})", f"_m.{name}({{0}})", f"v{name}({{0}})"


_MIN = "({0} if ({0} <= {1} or {1} != {1}) else {1})"
_MAX = "({0} if ({0} >= {1} or {1} != {1}) else {1})"
_ROWS: list[tuple[int, int, str | None, str | None, str | None]] = [
    # code, arity, numpy, python, c
    (ca.OP_ASSIGN, 1, "{0}", "{0}", "{0}"),
    (ca.OP_ADD, 2, "({0} + {1})", "({0} + {1})", "{0} + {1}"),
    (ca.OP_SUB, 2, "({0} - {1})", "({0} - {1})", "{0} - {1}"),
    (ca.OP_MUL, 2, "({0} * {1})", "({0} * {1})", "{0} * {1}"),
    (ca.OP_DIV, 2, "({0} / {1})", "({0} / {1})", "{0} / {1}"),
    (ca.OP_NEG, 1, "(-{0})", "(-{0})", "-{0}"),
    (ca.OP_SQ, 1, "({0} * {0})", "({0} * {0})", "{0} * {0}"),
    (ca.OP_TWICE, 1, "(2.0 * {0})", "(2.0 * {0})", "{0} + {0}"),  # 2 x, exactly
    (ca.OP_INV, 1, "(1.0 / {0})", "(1.0 / {0})", "ONE / {0}"),
    (ca.OP_POW, 2, "_np.power({0}, {1})", "_m.pow({0}, {1})", "vpow({0}, {1})"),
    (ca.OP_CONSTPOW, 2, "_np.power({0}, {1})", "_m.pow({0}, {1})", "vpow({0}, {1})"),
    (ca.OP_FMIN, 2, "_np.where(({0} <= {1}) | ({1} != {1}), {0}, {1})", _MIN, "vmin({0}, {1})"),
    (ca.OP_FMAX, 2, "_np.where(({0} >= {1}) | ({1} != {1}), {0}, {1})", _MAX, "vmax({0}, {1})"),
    (ca.OP_LT, 2, "(({0} < {1}) + 0.0)", "float({0} < {1})", "b2d({0} < {1})"),
    (ca.OP_LE, 2, "(({0} <= {1}) + 0.0)", "float({0} <= {1})", "b2d({0} <= {1})"),
    (ca.OP_EQ, 2, "(({0} == {1}) + 0.0)", "float({0} == {1})", "b2d({0} == {1})"),
    (ca.OP_NE, 2, "(({0} != {1}) + 0.0)", "float({0} != {1})", "b2d({0} != {1})"),
    (ca.OP_NOT, 1, "(({0} == 0) + 0.0)", "float({0} == 0)", "b2d({0} == ZERO)"),
    (
        ca.OP_AND,
        2,
        "((({0} != 0) & ({1} != 0)) + 0.0)",
        "float({0} != 0 and {1} != 0)",
        "b2d(({0} != ZERO) & ({1} != ZERO))",
    ),
    (
        ca.OP_OR,
        2,
        "((({0} != 0) | ({1} != 0)) + 0.0)",
        "float({0} != 0 or {1} != 0)",
        "b2d(({0} != ZERO) | ({1} != ZERO))",
    ),
    (
        ca.OP_IF_ELSE_ZERO,
        2,
        "_np.where({0} != 0, {1}, 0.0)",
        "({1} if {0} != 0 else 0.0)",
        "(v4)(({0} != ZERO) & (m4)({1}))",
    ),
    (ca.OP_FABS, 1, "_np.abs({0})", "abs({0})", "(v4)((m4)({0}) & ABS)"),
    (
        ca.OP_SIGN,
        1,
        "_np.copysign(_np.sign({0}), {0})",  # keeps -0 (numpy's sign gives +0)
        "(-1.0 if {0} < 0 else (1.0 if {0} > 0 else {0}))",
        "vsign({0})",
    ),
    (ca.OP_FLOOR, 1, "_np.floor({0})", "_m.copysign(float(_m.floor({0})), {0})", "vfloor({0})"),
    (ca.OP_CEIL, 1, "_np.ceil({0})", "_m.copysign(float(_m.ceil({0})), {0})", "vceil({0})"),
    (ca.OP_SQRT, 1, *_lib1("sqrt")),
    (ca.OP_EXP, 1, *_lib1("exp")),
    (ca.OP_LOG, 1, *_lib1("log")),
    (ca.OP_SIN, 1, *_lib1("sin")),
    (ca.OP_COS, 1, *_lib1("cos")),
    (ca.OP_TAN, 1, *_lib1("tan")),
    (ca.OP_ASIN, 1, *_lib1("asin", "arcsin")),
    (ca.OP_ACOS, 1, *_lib1("acos", "arccos")),
    (ca.OP_ATAN, 1, *_lib1("atan", "arctan")),
    (ca.OP_SINH, 1, *_lib1("sinh")),
    (ca.OP_COSH, 1, *_lib1("cosh")),
    (ca.OP_TANH, 1, *_lib1("tanh")),
    (ca.OP_ASINH, 1, *_lib1("asinh", "arcsinh")),
    (ca.OP_ACOSH, 1, *_lib1("acosh", "arccosh")),
    (ca.OP_ATANH, 1, *_lib1("atanh", "arctanh")),
    (ca.OP_ERF, 1, "_erf({0})", "_m.erf({0})", "verf({0})"),
    (ca.OP_EXPM1, 1, *_lib1("expm1")),
    (ca.OP_LOG1P, 1, *_lib1("log1p")),
    (ca.OP_ATAN2, 2, "_np.arctan2({0}, {1})", "_m.atan2({0}, {1})", "vatan2({0}, {1})"),
    (ca.OP_FMOD, 2, "_np.fmod({0}, {1})", "_m.fmod({0}, {1})", "vfmod({0}, {1})"),
    (ca.OP_COPYSIGN, 2, "_np.copysign({0}, {1})", "_m.copysign({0}, {1})", "vcopysign({0}, {1})"),
    (ca.OP_HYPOT, 2, "_np.hypot({0}, {1})", "_m.hypot({0}, {1})", "vhypot({0}, {1})"),
    (ca.OP_REMAINDER, 2, "_remainder({0}, {1})", "_m.remainder({0}, {1})", "vremainder({0}, {1})"),
]
_NAMES = {getattr(ca, n): n[3:].lower() for n in dir(ca) if n.startswith("OP_")}

#: CasADi operation code -> :class:`Op`, for every operation some back end evaluates.
OPS: dict[int, Op] = {row[0]: Op(row[0], _NAMES[row[0]], *row[1:]) for row in _ROWS}


def _remainder_ieee(x: float, y: float) -> float:
    """C's ``remainder``: NaN where :func:`math.remainder` refuses (x infinite, y zero)."""
    try:
        return math.remainder(x, y)
    except ValueError:
        return math.nan


#: Names the numpy and Python forms use (numpy has no erf and no IEEE remainder).
NAMESPACE: dict[str, object] = {
    "_np": np,
    "_m": math,
    "_erf": np.vectorize(math.erf, otypes=[float]),
    "_remainder": np.vectorize(_remainder_ieee, otypes=[float]),
}

#: Instructions that move data instead of computing (each back end writes them itself).
STRUCTURAL = frozenset({ca.OP_INPUT, ca.OP_OUTPUT, ca.OP_CONST})
