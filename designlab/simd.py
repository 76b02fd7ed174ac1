"""Compile a CasADi SX function to machine code that evaluates four members at once.

A batch of simulations (say 64 gain sets) calls the same SX function once per member
and period. CasADi's code generator writes scalar C; :func:`compile_lanes` writes the
function's instruction list as C on *vectors of four doubles* (GCC/Clang vector
extensions), so one pass of the instructions evaluates four members, and loads it
with :mod:`ctypes`. Every operation is the one CasADi's virtual machine performs, in
the same order and with the same IEEE-754 rounding (no fused multiply-add, no
reassociation; ``fmin``/``fmax`` with the C library's results for ties and NaN;
elementary functions called lane by lane from the C library), so the results equal
the virtual machine's to the last bit.

Inputs marked *shared* are common to every member (one copy); the others, and every
output, are stored member after member, each member's nonzeros contiguous, which is the
layout of ``Function.map(n, "serial")`` with the same shared inputs.

Examples
--------
>>> import casadi as ca, numpy as np
>>> x, p = ca.SX.sym("x", 2), ca.SX.sym("p")
>>> f = ca.Function("f", [x, p], [ca.vertcat(ca.fmin(x[0], p) * x[1], ca.sin(x[1]) + p)])
>>> lanes = compile_lanes(f, shared=[1])            # needs a C compiler
>>> call = lanes.bind(n=5)                         # five members, x member after member
>>> call.inp[0][:] = np.arange(10.0); call.inp[1][:] = 3.0
>>> call()
>>> ref = f.map("m", "serial", 5, [1], [])(np.arange(10.0).reshape(5, 2).T, 3.0)
>>> bool((call.out[0] == np.asarray(ref).ravel(order="F")).all())
True
"""

from __future__ import annotations

import ctypes
import math
import os
import shlex
import shutil
import subprocess
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass

import casadi as ca
import numpy as np
from numpy.typing import NDArray

__all__ = ["LANES", "CompiledLanes", "LaneCall", "UnsupportedOperation", "compile_lanes"]

#: Members evaluated together by one pass of the instructions.
LANES = 4

_PRELUDE = r"""
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
LANEWISE1(vfloor, floor) LANEWISE1(vceil, ceil) LANEWISE1(verf, erf)
LANEWISE1(vexpm1, expm1) LANEWISE1(vlog1p, log1p)
LANEWISE2(vatan2, atan2) LANEWISE2(vpow, pow) LANEWISE2(vfmod, fmod)
LANEWISE2(vcopysign, copysign) LANEWISE2(vhypot, hypot)
"""

_BINARY = {
    ca.OP_ADD: "{0} + {1}",
    ca.OP_SUB: "{0} - {1}",
    ca.OP_MUL: "{0} * {1}",
    ca.OP_DIV: "{0} / {1}",
    ca.OP_FMIN: "vmin({0}, {1})",
    ca.OP_FMAX: "vmax({0}, {1})",
    ca.OP_LT: "b2d({0} < {1})",
    ca.OP_LE: "b2d({0} <= {1})",
    ca.OP_EQ: "b2d({0} == {1})",
    ca.OP_NE: "b2d({0} != {1})",
    ca.OP_AND: "b2d(({0} != ZERO) & ({1} != ZERO))",
    ca.OP_OR: "b2d(({0} != ZERO) | ({1} != ZERO))",
    ca.OP_IF_ELSE_ZERO: "(v4)(({0} != ZERO) & (m4)({1}))",
    ca.OP_ATAN2: "vatan2({0}, {1})",
    ca.OP_POW: "vpow({0}, {1})",
    ca.OP_CONSTPOW: "vpow({0}, {1})",
    ca.OP_FMOD: "vfmod({0}, {1})",
    ca.OP_COPYSIGN: "vcopysign({0}, {1})",
    ca.OP_HYPOT: "vhypot({0}, {1})",
}
_UNARY = {
    ca.OP_ASSIGN: "{0}",
    ca.OP_NEG: "-{0}",
    ca.OP_SQ: "{0} * {0}",
    ca.OP_TWICE: "{0} + {0}",  # 2 x, exactly
    ca.OP_INV: "ONE / {0}",
    ca.OP_FABS: "(v4)((m4)({0}) & ABS)",
    ca.OP_SIGN: "vsign({0})",
    ca.OP_NOT: "b2d({0} == ZERO)",
    ca.OP_SQRT: "vsqrt({0})",
    ca.OP_EXP: "vexp({0})",
    ca.OP_LOG: "vlog({0})",
    ca.OP_SIN: "vsin({0})",
    ca.OP_COS: "vcos({0})",
    ca.OP_TAN: "vtan({0})",
    ca.OP_ASIN: "vasin({0})",
    ca.OP_ACOS: "vacos({0})",
    ca.OP_ATAN: "vatan({0})",
    ca.OP_SINH: "vsinh({0})",
    ca.OP_COSH: "vcosh({0})",
    ca.OP_TANH: "vtanh({0})",
    ca.OP_FLOOR: "vfloor({0})",
    ca.OP_CEIL: "vceil({0})",
    ca.OP_ERF: "verf({0})",
    ca.OP_EXPM1: "vexpm1({0})",
    ca.OP_LOG1P: "vlog1p({0})",
}
# -ffp-contract=off: no fused multiply-add (the virtual machine rounds every product);
# -fno-math-errno: errno is never read, which lets sqrt be inlined (same results)
_FLAGS = ["-O2", "-ffp-contract=off", "-fno-math-errno", "-fPIC", "-shared"]
_NATIVE = "-march=native"  # compiled where it runs: the widest vectors the CPU has


class UnsupportedOperation(ValueError):
    """The SX function uses an operation :func:`compile_lanes` does not translate."""


def _c_double(value: float) -> str:
    if math.isnan(value):
        return "NAN"
    if math.isinf(value):
        return "INFINITY" if value > 0 else "-INFINITY"
    return float(value).hex()  # exact


def _source(f: ca.Function, shared: frozenset[int], name: str) -> str:
    """C source of ``f`` on four lanes: ``void name(const double**, double**, int n)``."""
    nnz_in = [f.nnz_in(i) for i in range(f.n_in())]
    nnz_out = [f.nnz_out(i) for i in range(f.n_out())]
    body: list[str] = []
    for k in range(f.n_instructions()):
        op = f.instruction_id(k)
        ins, outs = f.instruction_input(k), f.instruction_output(k)
        if op == ca.OP_CONST:
            c = _c_double(f.instruction_constant(k))
            body.append(f"w{outs[0]} = (v4){{{c}, {c}, {c}, {c}}};")
        elif op == ca.OP_INPUT:
            i, nz = ins
            if i in shared:
                body.append(f"{{ double s = arg[{i}][{nz}]; w{outs[0]} = (v4){{s, s, s, s}}; }}")
            else:
                n = nnz_in[i]
                lanes = ", ".join(f"arg[{i}][m{lane} * {n} + {nz}]" for lane in range(LANES))
                body.append(f"w{outs[0]} = (v4){{{lanes}}};")
        elif op == ca.OP_OUTPUT:
            o, nz = outs
            n = nnz_out[o]
            body.append(
                f"for (int l = 0; l < live; l++) res[{o}][(b + l) * {n} + {nz}] = w{ins[0]}[l];"
            )
        elif op in _BINARY:
            body.append(f"w{outs[0]} = {_BINARY[op].format(f'w{ins[0]}', f'w{ins[1]}')};")
        elif op in _UNARY:
            body.append(f"w{outs[0]} = {_UNARY[op].format(f'w{ins[0]}')};")
        else:
            raise UnsupportedOperation(f"operation {op} of {f.name()!r} has no lane translation")
    decl = ", ".join(f"w{j}" for j in range(max(f.sz_w(), 1)))
    members = " ".join(
        f"int m{lane} = b + {lane} < n ? b + {lane} : n - 1;" for lane in range(LANES)
    )
    return (
        _PRELUDE
        + f"\nvoid {name}(const double** arg, double** res, int n) {{\n"
        + f"  v4 {decl};\n"
        + f"  for (int b = 0; b < n; b += {LANES}) {{\n"
        + f"    {members}\n"
        + f"    int live = n - b < {LANES} ? n - b : {LANES};\n    (void)live;\n    "
        + "\n    ".join(body)
        + "\n  }\n}\n"
    )


def _compiler() -> list[str]:
    """The C compiler's command: ``$CC`` (which may carry options), else ``cc`` or ``gcc``."""
    cc = shlex.split(os.environ.get("CC", "")) or [shutil.which("cc") or shutil.which("gcc") or ""]
    if not cc[0] or shutil.which(cc[0]) is None:
        raise RuntimeError(
            f"no C compiler found (CC = {os.environ.get('CC', '')!r}; set CC or install gcc)"
        )
    return cc


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
    """Compile the SX function ``f`` to evaluate four members per pass.

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
        When ``f`` uses an operation without a lane translation (the caller can fall
        back to CasADi's own code generator).
    ValueError
        When ``shared`` names an input ``f`` does not have.
    RuntimeError
        When no C compiler is found or the compilation fails.
    """
    if not f.is_a("SXFunction"):
        raise UnsupportedOperation(f"{f.name()!r} is not an SX function")
    common = frozenset(int(i) for i in shared)
    if not common <= set(range(f.n_in())):
        raise ValueError(
            f"shared = {sorted(common)} is not allowed: {f.name()!r} has inputs 0-{f.n_in() - 1}"
        )
    name = "lanes_" + "".join(c if c.isalnum() else "_" for c in f.name())
    src = _source(f, common, name)
    cc = _compiler()
    directory = tempfile.mkdtemp(prefix="designlab_lanes_")
    c_path, so_path = os.path.join(directory, name + ".c"), os.path.join(directory, name + ".so")
    with open(c_path, "w") as fh:
        fh.write(src)
    try:
        for flags in ([*_FLAGS, _NATIVE], _FLAGS):  # -march=native where the compiler takes it
            out = subprocess.run(
                [*cc, *flags, c_path, "-o", so_path, "-lm"], capture_output=True, text=True
            )
            if out.returncode == 0:
                break
        else:
            raise RuntimeError(f"compiling {f.name()!r} failed: {out.stderr}")
        library = ctypes.CDLL(so_path)
    finally:  # the loaded object stays mapped: no file outlives the call
        shutil.rmtree(directory, ignore_errors=True)
    return CompiledLanes(f, common, library, name)
