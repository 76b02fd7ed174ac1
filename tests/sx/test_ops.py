"""The one operation table against CasADi's virtual machine, in every evaluator.

For every operation of :data:`designlab.sx.OPS`, on every pair of special values
(signed zeros, infinities, NaN, subnormals, huge values, ties), the numpy replay
(:func:`vectorize`), the generated Python on floats and on arrays (:func:`compile_sx`)
and the four-lane machine code (:func:`compile_lanes`) give CasADi's virtual machine's
result to the bit (any NaN equals any NaN). Elementary functions in numpy may use the
CPU's own vector implementations, which are allowed 4 units in the last place but
must agree on every NaN, infinity and zero.
"""

from __future__ import annotations

import itertools
import math
import warnings

import casadi as ca
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from designlab.sx import (
    OPS,
    UnsupportedOperation,
    compile_lanes,
    compile_sx,
    compiler_missing_reason,
    vectorize,
)

SPECIAL = [0.0, -0.0, 1.0, -1.0, 0.5, -2.5, 3.0, math.inf, -math.inf, math.nan, 1e308, -1e308,
           5e-324, -1e-310, 1e-300, 710.0, 0.9999999999999999, 2.0]  # fmt: skip
PAIRS = list(itertools.product(SPECIAL, SPECIAL))
XS, YS = np.array([p[0] for p in PAIRS]), np.array([p[1] for p in PAIRS])
X, Y = ca.SX.sym("x"), ca.SX.sym("y")
# numpy's forms that may be the CPU's vector implementations (not the C library's)
LIBM = {"exp", "log", "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh",
        "asinh", "acosh", "atanh", "expm1", "log1p", "atan2", "hypot", "pow",
        "constpow"}  # fmt: skip


def _same(a: np.ndarray, b: np.ndarray, ulps: int = 0) -> np.ndarray:
    """Elementwise: equal bits, or both NaN, or (with ``ulps``) finite and that close."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    ia, ib = a.view(np.int64), b.view(np.int64)
    close = np.isfinite(a) & np.isfinite(b) & (np.sign(a) == np.sign(b)) & (a != 0) & (b != 0)
    return (ia == ib) | (np.isnan(a) & np.isnan(b)) | (close & (np.abs(ia - ib) <= ulps))


def _op_function(code: int) -> ca.Function:
    op = OPS[code]
    e = ca.SX.unary(code, X) if op.arity == 1 else ca.SX.binary(code, X, Y)
    return ca.Function(op.name, [X, Y], [e])


def _virtual_machine(f: ca.Function, xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    return np.array(f.map(xs.size)(xs, ys)).ravel()


@pytest.mark.parametrize("code", sorted(OPS), ids=[OPS[c].name for c in sorted(OPS)])
def test_every_operation_equals_the_virtual_machine_on_special_values(code: int) -> None:
    f = _op_function(code)
    want = _virtual_machine(f, XS, YS)
    ulps = 4 if OPS[code].name in LIBM else 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # numpy's warnings on NaN and inf
        got = {
            "replay": (vectorize(f)(XS[None, :], YS[None, :])[0].ravel(), ulps),
            "python": (np.array([compile_sx(f)(a, b)[0] for a, b in PAIRS]), 0),
            "numpy": (np.broadcast_to(compile_sx(f, batch=True)(XS, YS)[0], XS.shape), ulps),
        }
    if compiler_missing_reason() is None:
        call = compile_lanes(f).bind(XS.size)
        call.inp[0][:], call.inp[1][:] = XS, YS
        call()
        got["lanes"] = (call.out[0], 0)
    for name, (values, tol) in got.items():
        bad = np.flatnonzero(~_same(values, want, tol))
        assert not bad.size, [(name, PAIRS[i], want[i], values[i]) for i in bad[:5]]


def test_the_reported_disagreements_are_gone() -> None:
    f = ca.Function("f", [X, Y], [ca.fmin(X, Y), ca.fmax(X, Y), ca.SX(math.nan) * X, ca.sign(X)])
    assert [float(v) for v in f(math.nan, 1.0)][:2] == [1.0, 1.0]  # CasADi
    assert compile_sx(f)(math.nan, 1.0)[:2] == (1.0, 1.0)
    assert math.isnan(compile_sx(f)(1.0, 1.0)[2])  # a NaN constant compiles
    assert math.copysign(1.0, compile_sx(f)(-0.0, 1.0)[3]) == -1.0  # sign(-0) is -0
    out = vectorize(f)(np.array([[math.nan, 2.0]]), np.array([[1.0, math.nan]]))
    np.testing.assert_array_equal(np.vstack(out)[:2], [[1.0, 2.0], [1.0, 2.0]])


def test_math_errors_give_the_ieee_values_of_the_virtual_machine() -> None:
    f = ca.Function("f", [X, Y], [ca.sqrt(X) + 1 / Y, ca.exp(X) * Y, ca.log(Y)])
    g = compile_sx(f)
    for a, b in [(-1.0, 0.0), (1000.0, 0.0), (4.0, -0.0), (4.0, 2.0)]:
        assert _same(np.array(g(a, b)), np.array([float(v) for v in f(a, b)])).all(), (a, b)


def test_functions_that_cannot_be_translated_are_refused() -> None:
    m = ca.MX.sym("m")
    for build in (vectorize, compile_sx, compile_lanes):
        with pytest.raises(UnsupportedOperation, match="not an SX function"):
            build(ca.Function("mx", [m], [m * 2]))
    with pytest.raises(TypeError, match="not scalar"):
        compile_sx(ca.Function("v", [ca.SX.sym("v", 2)], [X * 0 + 1]))


EXACT_BINARY = [lambda a, b: a + b, lambda a, b: a - b, lambda a, b: a * b, lambda a, b: a / b,
                ca.fmin, ca.fmax, lambda a, b: a < b, lambda a, b: a == b, ca.logic_and,
                ca.logic_or, lambda a, b: ca.if_else(a, b, 0.0), ca.fmod, ca.copysign]  # fmt: skip
EXACT_UNARY = [lambda a: -a, lambda a: a * a, lambda a: 2 * a, lambda a: 1 / a, ca.fabs,
               ca.sign, ca.logic_not, ca.sqrt, ca.floor, ca.ceil]  # fmt: skip
LIBM_OPS = [ca.sin, ca.exp, ca.log, ca.atan, ca.tanh, ca.erf, ca.expm1]


def _tree(draw, depth: int, unary: list, binary: list) -> ca.SX:  # type: ignore[no-untyped-def]
    leaves = [X, Y, ca.SX(draw(st.sampled_from([0.5, -2.0, 0.0, -0.0, 3.0, math.nan])))]
    if depth == 0 or draw(st.integers(0, 4)) == 0:
        return draw(st.sampled_from(leaves))
    if draw(st.booleans()):
        return draw(st.sampled_from(unary))(_tree(draw, depth - 1, unary, binary))
    a, b = _tree(draw, depth - 1, unary, binary), _tree(draw, depth - 1, unary, binary)
    return draw(st.sampled_from(binary))(a, b)


VALUES = st.one_of(st.sampled_from(SPECIAL), st.floats(-10, 10), st.floats())


@settings(max_examples=40, deadline=None)
@given(data=st.data(), xs=st.lists(VALUES, min_size=6, max_size=6))
def test_random_expressions_equal_the_virtual_machine(data, xs) -> None:  # type: ignore[no-untyped-def]
    exact = data.draw(st.booleans())
    unary = EXACT_UNARY + ([] if exact else LIBM_OPS)
    e = ca.vertcat(*[_tree(data.draw, 5, unary, EXACT_BINARY) for _ in range(2)])
    f = ca.Function("r", [X, Y], [e[0], e[1]])
    a, b = np.array(xs[:3]), np.array(xs[3:])
    want = np.array([[float(v) for v in f(p, q)] for p, q in zip(a, b, strict=True)]).T
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        python = np.array([compile_sx(f)(p, q) for p, q in zip(a, b, strict=True)]).T
        batch = compile_sx(f, batch=True)(a, b)
        numpy = np.vstack([np.broadcast_to(v, a.shape) for v in batch])
        if exact:
            assert _same(python, want).all(), (python, want)
        else:
            # where math raises, the Python form recomputes the point with the numpy forms
            # (pycode's ``_exact``); numpy's own elementary functions may differ from the C
            # library in the last bits (SIMD builds, e.g. expm1 on AVX-512), so such a point
            # equals the numpy forms bit for bit instead
            assert (_same(python, want) | _same(python, numpy)).all(), (python, want, numpy)
        if exact:  # numpy's own elementary functions may differ in the last bits
            replay = np.vstack(vectorize(f)(a[None, :], b[None, :]))
            assert _same(numpy, want).all(), (numpy, want)
            assert _same(replay, want).all(), (replay, want)
