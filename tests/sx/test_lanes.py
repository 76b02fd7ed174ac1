"""designlab.sx.compile_lanes: four-lane machine code equals CasADi's virtual machine to the bit.

The reference is CasADi's own evaluation of the same SX function, mapped over the
members (``Function.map(n, "serial")`` with the same shared inputs); values include
signed zeros, infinities, NaN, subnormals and ties, where fmin/fmax, sign and the
comparisons are most easily got wrong.
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import casadi as ca
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from designlab.sx import LANES, UnsupportedOperation, compile_lanes, compiler_missing_reason

pytestmark = pytest.mark.skipif(
    compiler_missing_reason() is not None, reason=f"needs a C compiler: {compiler_missing_reason()}"
)

SPECIAL = [0.0, -0.0, 1.0, -1.0, 2.5, np.inf, -np.inf, np.nan, 1e308, -1e308, 5e-324, 1e-310]


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    """Bit for bit, except that any NaN equals any NaN."""
    nan = np.isnan(a) & np.isnan(b)
    return bool(((a.view(np.int64) == b.view(np.int64)) | nan).all())


def _reference(f: ca.Function, n: int, x: np.ndarray, p: np.ndarray) -> list[np.ndarray]:
    g = f.map("ref", "serial", n, [1], [])
    out = g(x.reshape(n, -1).T, p)
    out = out if isinstance(out, (list, tuple)) else [out]
    return [np.asarray(ca.DM(o).full()).ravel(order="F") for o in out]


def _check(f: ca.Function, n: int, x: np.ndarray, p: np.ndarray) -> None:
    call = compile_lanes(f, shared=[1]).bind(n)
    call.inp[0][:] = x
    call.inp[1][:] = p
    call()
    for got, want in zip(call.out, _reference(f, n, x, p), strict=True):
        assert _same(got, want), (got, want)


X, P = ca.SX.sym("x", 3), ca.SX.sym("p", 2)
BINARY = [
    lambda a, b: a + b,
    lambda a, b: a - b,
    lambda a, b: a * b,
    lambda a, b: a / b,
    ca.fmin,
    ca.fmax,
    lambda a, b: a < b,
    lambda a, b: a <= b,
    lambda a, b: a == b,
    lambda a, b: a != b,
    ca.logic_and,
    ca.logic_or,
    lambda a, b: ca.if_else(a, b, 0.0),
    lambda a, b: ca.if_else(a > b, a, b),
    ca.atan2,
    ca.power,
    ca.fmod,
    ca.copysign,
    ca.hypot,
]
UNARY = [
    lambda a: -a,
    lambda a: a * a,
    lambda a: 2 * a,
    lambda a: 1 / a,
    ca.fabs,
    ca.sign,
    ca.logic_not,
    ca.sqrt,
    ca.exp,
    ca.log,
    ca.sin,
    ca.cos,
    ca.tan,
    ca.asin,
    ca.acos,
    ca.atan,
    ca.sinh,
    ca.cosh,
    ca.tanh,
    ca.floor,
    ca.ceil,
    ca.erf,
    ca.expm1,
    ca.log1p,
    lambda a: a**3,
]


def test_every_operation_on_the_special_values() -> None:
    leaves = [X[0], X[1], X[2], P[0], P[1]]
    outs = [op(leaves[i % 5], leaves[(i + 2) % 5]) for i, op in enumerate(BINARY)]
    outs += [op(leaves[i % 5]) for i, op in enumerate(UNARY)]
    f = ca.Function("every_op", [X, P], [ca.vertcat(*outs), X[0] * 3 + P[1]])
    vals = np.array(SPECIAL)
    n = 2 * len(vals) + 3  # not a multiple of the lanes: the last pass is partly empty
    x = np.resize(np.stack([vals, np.roll(vals, 1), np.roll(vals, 5)], axis=1), (n, 3)).ravel()
    for p in ([0.0, -0.0], [np.nan, 1.0], [-np.inf, 2.5], [1.0, 1.0]):
        _check(f, n, x, np.array(p))


def _tree(draw, depth: int) -> ca.SX:  # type: ignore[no-untyped-def]
    leaves = [X[0], X[1], X[2], P[0], P[1], ca.SX(draw(st.sampled_from([0.5, -2.0, 0.0, 3.0])))]
    if depth == 0 or draw(st.integers(0, 4)) == 0:
        return draw(st.sampled_from(leaves))
    if draw(st.booleans()):
        return draw(st.sampled_from(UNARY))(_tree(draw, depth - 1))
    return draw(st.sampled_from(BINARY))(_tree(draw, depth - 1), _tree(draw, depth - 1))


@st.composite
def functions(draw):  # type: ignore[no-untyped-def]
    outs = [_tree(draw, 5) for _ in range(draw(st.integers(1, 3)))]
    return ca.Function("random_expr", [X, P], [ca.vertcat(*outs)])


values = st.one_of(
    st.sampled_from(SPECIAL), st.floats(-10, 10), st.floats(allow_nan=True, allow_infinity=True)
)


@settings(max_examples=12, deadline=None)
@given(
    f=functions(),
    n=st.integers(1, 2 * LANES + 1),
    data=st.data(),
)
def test_random_expressions_equal_the_virtual_machine(f, n, data) -> None:  # type: ignore[no-untyped-def]
    x = np.array(data.draw(st.lists(values, min_size=3 * n, max_size=3 * n)))
    p = np.array(data.draw(st.lists(values, min_size=2, max_size=2)))
    _check(f, n, x, p)


def test_shared_inputs_are_read_once_and_members_in_order() -> None:
    f = ca.Function("lin", [X, P], [X * P[0] + P[1]])
    lanes = compile_lanes(f, shared=[1])
    call = lanes.bind(6)
    call.inp[0][:] = np.arange(18.0)
    call.inp[1][:] = [2.0, 1.0]
    call()
    np.testing.assert_array_equal(call.out[0], 2.0 * np.arange(18.0) + 1.0)
    with pytest.raises(ValueError, match="n = 0"):
        lanes.bind(0)
    with pytest.raises(ValueError, match=r"shared = \[5\] is not allowed: 'lin' has inputs 0-1"):
        compile_lanes(f, shared=[5])


def test_functions_it_cannot_translate_are_refused() -> None:
    m = ca.MX.sym("m", 2)
    with pytest.raises(UnsupportedOperation, match="not an SX function"):
        compile_lanes(ca.Function("mx", [m], [m * 2]))


def test_products_are_rounded_before_the_sum_no_fused_multiply_add() -> None:
    # (1 + 2^-30)(1 - 2^-30) - 1 is 0 with the product rounded, -2^-60 if fused
    f = ca.Function("fma", [X, P], [X[0] * X[1] + X[2]])
    a, b = 1.0 + 2.0**-30, 1.0 - 2.0**-30
    x = np.tile([a, b, -1.0], 5)
    _check(f, 5, x, np.zeros(2))
    call = compile_lanes(f, shared=[1]).bind(5)
    call.inp[0][:] = x
    call()
    assert (call.out[0] == 0.0).all()


def test_a_missing_or_broken_compiler_is_reported(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(tmp))  # nothing may be left behind
    f = ca.Function("lin2", [X, P], [X * P[0]])
    monkeypatch.setenv("CC", "/nonexistent/cc")
    with pytest.raises(RuntimeError, match="no C compiler found"):
        compile_lanes(f, shared=[1])
    cc = "cc" if shutil.which("cc") else "gcc"
    monkeypatch.setenv("CC", f"{cc} -Wl,--no-such-linker-option")
    with pytest.raises(RuntimeError, match="compiling 'lin2' failed"):
        compile_lanes(f, shared=[1])
    monkeypatch.setenv("CC", f"{cc} -O0")  # a compiler with options of its own
    call = compile_lanes(f, shared=[1]).bind(2)
    call.inp[0][:] = np.arange(6.0)
    call.inp[1][:] = [3.0, 0.0]
    call()
    np.testing.assert_array_equal(call.out[0], 3.0 * np.arange(6.0))
    assert list(tmp.iterdir()) == []
