"""An exact evaluator of the impact model written for the tests only.

It shares no code with designlab: the 4-state relative-coordinate system of
Zeng 2011, Sec. 3.5 (docs/impact.md, "The model") is written out here as a
numpy matrix, its ramp response is the eigen-solution of the homogeneous part
plus the affine particular solution ``x_p(t) = alpha + beta t``, the lobe end
is bracketed on a fine grid and solved with ``brentq``, and every maximum is
the best of the window ends and of each grid-local maximum refined by a bounded
scalar search on its neighbouring grid cells.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, minimize_scalar


@dataclass(frozen=True)
class ExactImpact:
    """First-lobe metrics of one design (SI units)."""

    t_imp: float
    a_max: float
    eps_max: float
    force_max: float
    hic15: float

    def value(self, name: str) -> float:
        return float(getattr(self, name))


class ExactModel:
    """Closed-form ramp response of one design.

    Parameters are ``M_r, C_r, K_r, K_c, C_c, M_h, C_h, K_h`` and the closing speed v.
    """

    def __init__(self, m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h, v):
        self.p = (m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h)
        self.v = v
        # x = [d_r, d_r', d_h, d_h'];  eps = d_r - d_h + v t;  f = K_c eps + C_c eps'
        a = np.array(
            [
                [0.0, 1.0, 0.0, 0.0],
                [-(k_r + k_c) / m_r, -(c_r + c_c) / m_r, k_c / m_r, c_c / m_r],
                [0.0, 0.0, 0.0, 1.0],
                [k_c / m_h, c_c / m_h, -(k_c + k_h) / m_h, -(c_c + c_h) / m_h],
            ]
        )
        # forcing: b1 * (v t) + b0 * v
        b1 = np.array([0.0, -k_c / m_r, 0.0, k_c / m_h])
        b0 = np.array([0.0, -c_c / m_r, 0.0, c_c / m_h])
        beta = -np.linalg.solve(a, b1 * v)
        alpha = np.linalg.solve(a, beta - b0 * v)
        lam, vec = np.linalg.eig(a)
        self.lam = lam
        self.vec = vec
        self.coef = np.linalg.solve(vec, -alpha.astype(complex))  # x(0) = 0
        self.alpha, self.beta, self.a = alpha, beta, a

    def states(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """States and their derivatives at times ``t`` ``(T,)``: two ``(4, T)`` arrays."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        e = np.exp(np.outer(self.lam, t))
        xh = np.real(self.vec @ (self.coef[:, None] * e))
        dxh = np.real(self.vec @ ((self.coef * self.lam)[:, None] * e))
        x = xh + self.alpha[:, None] + self.beta[:, None] * t[None, :]
        dx = dxh + self.beta[:, None]
        return x, dx

    def outputs(self, t: np.ndarray) -> dict[str, np.ndarray]:
        _, _, _, k_c, c_c, m_h, c_h, k_h = self.p
        t = np.atleast_1d(np.asarray(t, dtype=float))
        x, _ = self.states(t)
        eps = x[0] - x[2] + self.v * t
        deps = x[1] - x[3] + self.v
        f = k_c * eps + c_c * deps
        a_h = (f - c_h * x[3] - k_h * x[2]) / m_h
        return {"a_max": a_h, "eps_max": eps, "force_max": f, "head_velocity": x[3]}


def _refined_max(fun, t: np.ndarray, y: np.ndarray) -> float:
    """Max of ``fun`` on ``[t[0], t[-1]]`` from its samples ``y``, refined locally."""
    best = float(max(y[0], y[-1]))
    n = t.size
    inner = np.flatnonzero((y[1:-1] >= y[:-2]) & (y[1:-1] >= y[2:])) + 1
    # refine the largest few grid-local maxima (the others are far below)
    order = inner[np.argsort(y[inner])[::-1][:6]]
    for j in order:
        lo, hi = t[max(j - 1, 0)], t[min(j + 1, n - 1)]
        res = minimize_scalar(
            lambda s: -float(fun(np.array([s]))[0]),
            bounds=(lo, hi),
            method="bounded",
            options={"xatol": 1e-13 * max(hi, 1e-12)},
        )
        best = max(best, float(y[j]), float(-res.fun))
    return best


def exact_metrics(params, v: float, grid: int = 40001, with_hic: bool = True) -> ExactImpact:
    """Exact first-lobe metrics of one design (``params`` ordered M_r..K_h)."""
    model = ExactModel(*params, v)
    m_h = params[5]
    k_c, c_c = params[3], params[4]
    # lobe end: a_h(0+) = C_c v / M_h (> 0 when C_c > 0; otherwise a_h rises from 0)
    slow = np.min(np.abs(model.lam))
    horizon = 40.0 / slow + 1.0
    tt = np.linspace(0.0, min(horizon, 2.0), grid)
    a = model.outputs(tt)["a_max"]
    if c_c == 0:
        # a_h(0) = 0 and rises with slope K_c v / M_h: skip the first sample
        a[0] = 1.0
    neg = np.flatnonzero((a <= 0) & (tt > 0))
    assert neg.size, "lobe not closed within the horizon"
    k = int(neg[0])

    def ah(s: float) -> float:
        return float(model.outputs(np.array([s]))["a_max"][0])

    t_imp = brentq(ah, tt[k - 1], tt[k], xtol=1e-15, rtol=4 * np.finfo(float).eps)
    t = np.linspace(0.0, t_imp, grid)
    out = model.outputs(t)
    vals = {}
    for name in ("a_max", "eps_max", "force_max"):

        def fun(s: np.ndarray, name: str = name) -> np.ndarray:
            return model.outputs(s)[name]

        vals[name] = _refined_max(fun, t, out[name])
    del k_c, m_h
    return ExactImpact(t_imp, vals["a_max"], vals["eps_max"], vals["force_max"],
                       exact_hic(model, t_imp, 0.015) if with_hic else float("nan"))  # fmt: skip


def exact_hic(model: ExactModel, t_imp: float, window: float, grid: int = 1201) -> float:
    """HIC over ``[0, t_imp]`` (standard definition), exact velocity, refined optimum.

    HIC = max (t2 - t1)^-1.5 (v(t2) - v(t1))^2.5 / g^2.5 over t2 - t1 <= window.
    Nested one-dimensional searches: for a window length d, the best start t1
    (grid, then bounded scalar refinement); then the best d the same way.
    """
    g = 9.80665
    t = np.linspace(0.0, t_imp, grid)
    v = model.outputs(t)["head_velocity"]
    dt = t[1] - t[0]

    def vel(s: float) -> float:
        return float(model.outputs(np.array([s]))["head_velocity"][0])

    def best_start(d: float) -> tuple[float, float]:
        """max over t1 in [0, t_imp - d] of v(t1 + d) - v(t1), and where."""
        lag = d / dt
        t1 = np.linspace(0.0, t_imp - d, max(int(grid - lag), 3))
        dv = model.outputs(t1 + d)["head_velocity"] - model.outputs(t1)["head_velocity"]
        j = int(np.argmax(dv))
        lo, hi = t1[max(j - 1, 0)], t1[min(j + 1, t1.size - 1)]
        if hi <= lo:
            return float(dv[j]), float(t1[j])
        r = minimize_scalar(lambda s: -(vel(s + d) - vel(s)), bounds=(lo, hi),
                            method="bounded", options={"xatol": 1e-15})  # fmt: skip
        return (float(-r.fun), float(r.x)) if -r.fun > dv[j] else (float(dv[j]), float(t1[j]))

    def hic_of(d: float) -> float:
        dv, _ = best_start(d)
        return d**-1.5 * max(dv, 0.0) ** 2.5 / g**2.5

    d_max = min(window, t_imp)
    ds = np.linspace(d_max / 200, d_max, 200)
    vals = np.array([hic_of(d) for d in ds])
    j = int(np.argmax(vals))
    best = float(vals[j])
    lo, hi = ds[max(j - 1, 0)], ds[min(j + 1, ds.size - 1)]
    r = minimize_scalar(lambda d: -hic_of(d), bounds=(lo, hi), method="bounded",
                        options={"xatol": 1e-15})  # fmt: skip
    del v
    return max(best, float(-r.fun))
