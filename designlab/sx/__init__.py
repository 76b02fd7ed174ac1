"""The one symbolic back end: every way designlab evaluates a CasADi SX function.

Models are written once with CasADi symbols. This package evaluates their SX
functions four ways, all from one operation table (:data:`OPS`: each SX operation's
numpy, Python and C forms, with the semantics of CasADi's virtual machine on NaN,
infinities and signed zeros):

* :func:`vectorize` / :func:`evaluate_batch`: numpy replay of the instruction list
  on whole columns of designs (:mod:`designlab.sx.replay`);
* :func:`compile_sx`: the instruction list as one Python function, on floats with
  :mod:`math` or on numpy arrays (:mod:`designlab.sx.pycode`);
* :func:`compile_lanes`: C on vectors of four doubles, compiled by the system C
  compiler and equal to the virtual machine to the bit (:mod:`designlab.sx.lanes`);
  cached on disk by source, compiler, flags and CPU (:mod:`designlab.sx.cache`,
  :func:`cache_dir`, :func:`clear_cache`); without a compiler,
  :func:`try_compile_lanes` returns ``None`` and the caller uses CasADi's own
  evaluation (same results), said once in the log.

The compiler runs as an argument list (``$CC``, which may carry options), never
through a shell (:mod:`designlab.sx.compiler`).

Examples
--------
>>> import casadi as ca, math
>>> x = ca.SX.sym("x")
>>> f = ca.Function("f", [x], [ca.fmin(x, 1.0)])
>>> compile_sx(f)(math.nan), float(f(math.nan))          # CasADi's fmin: the other one
((1.0,), 1.0)
>>> float(vectorize(f)([math.nan])[0][0, 0])
1.0
"""

from designlab.sx.cache import ENV, cache_dir, clear_cache
from designlab.sx.compiler import CompilerError, compiler_missing_reason
from designlab.sx.lanes import LANES, CompiledLanes, LaneCall, compile_lanes, try_compile_lanes
from designlab.sx.ops import OPS, Op
from designlab.sx.program import UnsupportedOperation, read_program, with_cse
from designlab.sx.pycode import compile_sx
from designlab.sx.replay import evaluate_batch, vectorize

__all__ = [
    "ENV",
    "LANES",
    "OPS",
    "CompiledLanes",
    "CompilerError",
    "LaneCall",
    "Op",
    "UnsupportedOperation",
    "cache_dir",
    "clear_cache",
    "compile_lanes",
    "compile_sx",
    "compiler_missing_reason",
    "evaluate_batch",
    "read_program",
    "try_compile_lanes",
    "vectorize",
    "with_cse",
]
