"""Compile a CasADi SX function to machine code that evaluates four members at once.

A batch of simulations (say 64 gain sets) calls the same SX function once per member
and period. :func:`compile_lanes` writes the function's instruction list as C on
*vectors of four doubles* (GCC/Clang vector extensions) with the C forms of the one
operation table (:data:`designlab.sx.ops.OPS`), so one pass of the instructions
evaluates four members, and loads it with :mod:`ctypes`. Every operation is the one
CasADi's virtual machine performs, in the same order and with the same IEEE-754
rounding (no fused multiply-add, no reassociation; ``fmin``/``fmax`` with the C
library's results for ties and NaN; elementary functions called lane by lane from the
C library), so the results equal the virtual machine's to the last bit.

The compiled code is cached on disk (:mod:`designlab.sx.cache`): a second process or
run loads it instead of compiling. Without a working C compiler
:func:`compile_lanes` raises :class:`~designlab.sx.compiler.CompilerError` and
:func:`try_compile_lanes` returns ``None`` (the caller evaluates with CasADi, which
gives the same results), saying so once in the log.

Inputs marked *shared* are common to every member (one copy); the others, and every
output, are stored member after member, each member's nonzeros contiguous, which is the
layout of ``Function.map(n, "serial")`` with the same shared inputs.

Examples
--------
>>> import casadi as ca, numpy as np
>>> x, p = ca.SX.sym("x", 2), ca.SX.sym("p")
>>> f = ca.Function("f", [x, p], [ca.vertcat(ca.fmin(x[0], p) * x[1], ca.sin(x[1]) + p)])
>>> lanes = try_compile_lanes(f, shared=[1])      # None without a C compiler
>>> call = lanes.bind(n=5) if lanes else None     # five members, x member after member
>>> if call:
...     call.inp[0][:] = np.arange(10.0); call.inp[1][:] = 3.0; call()
>>> ref = f.map("m", "serial", 5, [1], [])(np.arange(10.0).reshape(5, 2).T, 3.0)
>>> call is None or bool((call.out[0] == np.asarray(ref).ravel(order="F")).all())
True
"""

from __future__ import annotations

import ctypes
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from designlab.sx.cache import cache_key, load_or_build, say_once
from designlab.sx.compiler import (
    FLAGS,
    CompilerError,
    build_shared_object,
    find_compiler,
    machine_identity,
)
from designlab.sx.ops import OPS
from designlab.sx.program import Instruction, Program, check_sx, read_program

__all__ = [
    "LANES",
    "PRELUDE",
    "CompiledLanes",
    "LaneCall",
    "compile_lanes",
    "lane_source",
    "try_compile_lanes",
]

#: Members evaluated together by one pass of the instructions.
LANES = 4

#: The vector type and the helpers the C forms of :data:`~designlab.sx.ops.OPS` use.
PRELUDE = r"""
#include <math.h>
typedef double v4 __attribute__((vector_size(32)));
typedef long long m4 __attribute__((vector_size(32)));
static const v4 ZERO = {0.0, 0.0, 0.0, 0.0};
static const v4 ONE = {1.0, 1.0, 1.0, 1.0};
static const m4 ABS = {0x7fffffffffffffffLL, 0x7fffffffffffffffLL,
                       0x7fffffffffffffffLL, 0x7fffffffffffffffLL};
static inline v4 sel(m4 m, v4 a, v4 b) { return (v4)((m & (m4)a) | (~m & (m4)b)); }
static inline v4 b2d(m4 m) { return (v4)(m & (m4)ONE); }
/* the C library's fmin/fmax results: ties return the first argument, a NaN the other */
static inline v4 vmin(v4 x, v4 y) { return sel((x <= y) | (y != y), x, y); }
static inline v4 vmax(v4 x, v4 y) { return sel((x >= y) | (y != y), x, y); }
static inline v4 vsign(v4 x) { return sel(x < ZERO, -ONE, sel(x > ZERO, ONE, x)); }
#define LANEWISE1(name, fn) static inline v4 name(v4 a) { v4 r; \
  for (int l = 0; l < 4; l++) r[l] = fn(a[l]); return r; }
#define LANEWISE2(name, fn) static inline v4 name(v4 a, v4 b) { v4 r; \
  for (int l = 0; l < 4; l++) r[l] = fn(a[l], b[l]); return r; }
LANEWISE1(vsqrt, sqrt) LANEWISE1(vexp, exp) LANEWISE1(vlog, log) LANEWISE1(vsin, sin)
LANEWISE1(vcos, cos) LANEWISE1(vtan, tan) LANEWISE1(vasin, asin) LANEWISE1(vacos, acos)
LANEWISE1(vatan, atan) LANEWISE1(vsinh, sinh) LANEWISE1(vcosh, cosh) LANEWISE1(vtanh, tanh)
LANEWISE1(vasinh, asinh) LANEWISE1(vacosh, acosh) LANEWISE1(vatanh, atanh)
LANEWISE1(vfloor, floor) LANEWISE1(vceil, ceil) LANEWISE1(verf, erf)
LANEWISE1(vexpm1, expm1) LANEWISE1(vlog1p, log1p)
LANEWISE2(vatan2, atan2) LANEWISE2(vpow, pow) LANEWISE2(vfmod, fmod)
LANEWISE2(vcopysign, copysign) LANEWISE2(vhypot, hypot) LANEWISE2(vremainder, remainder)
"""


#: What the generated source depends on besides the function: bump the number when
#: :func:`lane_source` changes (the prelude and the C forms are hashed in).
_GENERATOR = f"lanes 1 {PRELUDE} " + repr(sorted((k, op.c) for k, op in OPS.items()))


def _c_double(value: float) -> str:
    if math.isnan(value):
        return "NAN"
    if math.isinf(value):
        return "INFINITY" if value > 0 else "-INFINITY"
    return float(value).hex()  # exact


def _c_line(ins: Instruction, prog: Program, shared: frozenset[int]) -> str:
    """One instruction as a C statement on four lanes (members ``m0``-``m3``)."""
    if ins.op == ca.OP_CONST:
        c = _c_double(ins.const)  # type: ignore[arg-type]
        return f"w{ins.outs[0]} = (v4){{{c}, {c}, {c}, {c}}};"
    if ins.op == ca.OP_INPUT:
        i, nz = ins.ins
        if i in shared:
            return f"{{ double s = arg[{i}][{nz}]; w{ins.outs[0]} = (v4){{s, s, s, s}}; }}"
        n = prog.nnz_in[i]
        lanes = ", ".join(f"arg[{i}][m{lane} * {n} + {nz}]" for lane in range(LANES))
        return f"w{ins.outs[0]} = (v4){{{lanes}}};"
    if ins.op == ca.OP_OUTPUT:
        o, nz = ins.outs
        n = prog.nnz_out[o]
        return f"for (int l = 0; l < live; l++) res[{o}][(b + l) * {n} + {nz}] = w{ins.ins[0]}[l];"
    template: str = OPS[ins.op].c  # type: ignore[assignment]
    return f"w{ins.outs[0]} = {template.format(*(f'w{i}' for i in ins.ins))};"


def lane_source(prog: Program, shared: frozenset[int], name: str) -> str:
    """C source of ``prog`` on four lanes: ``void name(const double**, double**, int n)``.

    Parameters
    ----------
    prog
        From :func:`~designlab.sx.program.read_program` with the ``"c"`` back end.
    shared
        Indices of the inputs common to every member.
    name
        The C function's name.
    """
    body = [_c_line(ins, prog, shared) for ins in prog.instructions]
    decl = ", ".join(f"w{j}" for j in range(max(prog.n_work, 1)))
    members = " ".join(
        f"int m{lane} = b + {lane} < n ? b + {lane} : n - 1;" for lane in range(LANES)
    )
    return (
        PRELUDE
        + f"\nvoid {name}(const double** arg, double** res, int n) {{\n"
        + f"  v4 {decl};\n"
        + f"  for (int b = 0; b < n; b += {LANES}) {{\n"
        + f"    {members}\n"
        + f"    int live = n - b < {LANES} ? n - b : {LANES};\n    (void)live;\n    "
        + "\n    ".join(body)
        + "\n  }\n}\n"
    )


@dataclass(frozen=True)
class LaneCall:
    """A compiled function bound to arrays for ``n`` members (see :meth:`CompiledLanes.bind`).

    Attributes
    ----------
    n
        Members evaluated by one call.
    inp, out
        The flat input and output arrays (nonzeros, member after member; shared
        inputs once). Write the inputs in place, call, read the outputs.
    """

    n: int
    inp: list[NDArray[np.float64]]
    out: list[NDArray[np.float64]]
    _fn: ctypes._CFuncPtr
    _args: tuple[ctypes.Array, ctypes.Array, ctypes.c_int]

    def __call__(self) -> None:
        """Evaluate every member."""
        self._fn(*self._args)


class CompiledLanes:
    """A CasADi SX function compiled to evaluate four members per pass.

    Build with :func:`compile_lanes`.

    Parameters
    ----------
    f
        The SX function.
    shared
        Indices of the inputs common to every member.
    library, symbol
        The loaded shared object and the function's name in it.
    """

    def __init__(
        self, f: ca.Function, shared: frozenset[int], library: ctypes.CDLL, symbol: str
    ) -> None:
        self.f = f
        self.shared = shared
        self._lib = library  # kept: the function lives as long as its library is loaded
        self._fn = getattr(library, symbol)
        self._fn.restype = None

    def bind(self, n: int) -> LaneCall:
        """Arrays for ``n`` members and a call that evaluates them.

        Parameters
        ----------
        n
            Members (>= 1).
        """
        if n < 1:
            raise ValueError(f"n = {n} is not allowed: must be >= 1")
        f = self.f
        inp = [np.zeros(f.nnz_in(i) * (1 if i in self.shared else n)) for i in range(f.n_in())]
        out = [np.zeros(f.nnz_out(o) * n) for o in range(f.n_out())]
        ptr = ctypes.POINTER(ctypes.c_double)
        args = (ptr * len(inp))(*(a.ctypes.data_as(ptr) for a in inp))
        res = (ptr * len(out))(*(a.ctypes.data_as(ptr) for a in out))
        return LaneCall(n, inp, out, self._fn, (args, res, ctypes.c_int(n)))


def compile_lanes(f: ca.Function, shared: Sequence[int] = ()) -> CompiledLanes:
    """Compile the SX function ``f`` to evaluate four members per pass (cached on disk).

    Parameters
    ----------
    f
        A CasADi SX function (every input and output dense or sparse; no calls to
        other functions).
    shared
        Indices of the inputs common to every member.

    Returns
    -------
    CompiledLanes
        Its :meth:`~CompiledLanes.bind` gives arrays and a call for ``n`` members.

    Raises
    ------
    UnsupportedOperation
        When ``f`` uses an operation without a C translation.
    ValueError
        When ``shared`` names an input ``f`` does not have.
    CompilerError
        (a ``RuntimeError``) when no C compiler is found or the compilation fails.
    """
    check_sx(f)
    common = frozenset(int(i) for i in shared)
    if not common <= set(range(f.n_in())):
        raise ValueError(
            f"shared = {sorted(common)} is not allowed: {f.name()!r} has inputs 0-{f.n_in() - 1}"
        )
    name = "lanes_" + "".join(c if c.isalnum() else "_" for c in f.name())
    cc = find_compiler()
    # the key needs no source: CasADi's serialisation of f says what the source would be
    key = cache_key(
        f.serialize(), f"{sorted(common)} {name}", _GENERATOR, cc.identity, " ".join(FLAGS)
    )

    def build(out: Path) -> None:
        src = lane_source(read_program(f, "c"), common, name)
        build_shared_object(src, f.name(), cc, out)

    try:
        library = load_or_build(cache_key(key, machine_identity()), build)
    except OSError as exc:
        raise CompilerError(f"compiled {f.name()!r} does not load: {exc}") from None
    return CompiledLanes(f, common, library, name)


def try_compile_lanes(f: ca.Function, shared: Sequence[int] = ()) -> CompiledLanes | None:
    """:func:`compile_lanes`, or ``None`` where it cannot compile (said once in the log).

    The caller then evaluates ``f`` with CasADi, whose results the compiled code equals.

    Parameters
    ----------
    f, shared
        As in :func:`compile_lanes`.
    """
    try:
        return compile_lanes(f, shared)
    except CompilerError as exc:
        say_once(f"{exc}; CasADi's own evaluation is used instead (same results, slower)")
        return None
