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

import itertools
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


class _MpFirstLobe:
    """First zero of a_h (output 1) and maxima of a response ``value(o, t, d)`` at the
    working precision of ``self.mp``, from a grid and bracketed solves."""

    mp: object
    rate: object  # the fastest pole's modulus (1/s)

    def first_zero(self, t_hi: float, samples: int = 4000) -> float:
        """First zero of a_h in ``(0, t_hi]``: a grid of at least ``samples`` cells, none wider
        than a twelfth of the fastest resolved pole's period, and a bracketed solve of the
        first sign change. A cell with a_h > 0 at both ends whose slope goes from - to + holds
        a minimum, solved for: a dip below zero between two samples ends the lobe there."""
        mp = self.mp
        fast = self.rate
        n = max(samples, int(float(t_hi * fast) * 2.0) + 1)
        ts = [mp.mpf(t_hi) * k / n for k in range(1, n + 1)]
        prev, dprev = mp.mpf(0), self.value(1, 0, 1)
        for t in ts:
            y, dy = self.value(1, t), self.value(1, t, 1)
            end = t
            if y >= 0 and dprev < 0 < dy:  # a minimum inside: a dip between the samples?
                scale = max(abs(dprev), abs(dy))
                low = mp.findroot(
                    lambda s, k=scale: self.value(1, s, 1) / k, (prev, t), solver="anderson"
                )
                if self.value(1, low) < 0:
                    y, end = self.value(1, low), low
            if y < 0:  # scaled: findroot's tolerance is absolute, and a slow tail's a_h tiny
                scale = max(abs(self.value(1, prev)), abs(y))
                root = mp.findroot(
                    lambda s, k=scale: self.value(1, s) / k, (prev, end), solver="anderson"
                )
                return float(root)
            prev, dprev = t, dy
        return float("nan")

    def maximum(self, o: int, t_end: float, samples: int = 4000) -> float:
        """Maximum of output ``o`` over ``[0, t_end]``: the ends and every zero of y' from +
        to - on a grid as :meth:`first_zero`'s, each solved to ``dps`` digits."""
        mp = self.mp
        fast = self.rate
        n = max(samples, int(float(t_end * fast) * 2.0) + 1)
        ts = [mp.mpf(t_end) * k / n for k in range(n + 1)]
        best = max(self.value(o, ts[0]), self.value(o, ts[-1]))
        dprev = self.value(o, ts[0], 1)
        for a, b in itertools.pairwise(ts):
            db = self.value(o, b, 1)
            if dprev > 0 >= db:
                scale = max(abs(dprev), abs(db))  # as first_zero's
                t = mp.findroot(
                    lambda s, k=scale: self.value(o, s, 1) / k, (a, b), solver="anderson"
                )
                best = max(best, self.value(o, t))
            dprev = db
        return float(best)


class MpImpact(_MpFirstLobe):
    """The reduced model's exact ramp responses at ``dps`` digits (mpmath), for settling
    disagreements (the fuzz harness, benchmarks/fuzz_kernel.py, and its CI slice).

    The transfer functions of docs/impact.md, "The model", written out again here:
    ``D = s^4 + q1 s^3 + q2 s^2 + q3 s + q4`` (the correct q2), responses to the unit
    ramp ``N(s) / (s^2 D)`` expanded in partial fractions at the roots of ``D``
    (:func:`mpmath.polyroots` at ``dps`` digits) plus ``c0 t + c1`` from the double pole
    at 0. Outputs: 0 force, 1 head acceleration, 2 compression (v_c = 1 m/s).
    """

    def __init__(self, params, dps: int = 40) -> None:
        import mpmath

        self.mp = mp = mpmath.mp
        mp.dps = dps
        m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h = (mp.mpf(float(x)) for x in params)
        mm = m_r * m_h
        den = [mp.mpf(1), (c_r + c_c) / m_r + (c_c + c_h) / m_h,
               (k_r + k_c) / m_r + (k_h + k_c) / m_h + (c_c * c_r + c_c * c_h + c_r * c_h) / mm,
               (k_r * (c_c + c_h) + k_c * (c_r + c_h) + k_h * (c_c + c_r)) / mm,
               (k_r * k_h + k_c * k_h + k_r * k_c) / mm]  # fmt: skip
        zr = [mp.mpf(1), c_r / m_r, k_r / m_r]
        zh = [mp.mpf(1), c_h / m_h, k_h / m_h]
        zrzh = _mul(zr, zh)
        nums = [_mul([c_c, k_c], zrzh), [x / m_h for x in _mul([c_c, k_c], zr)] + [0, 0], zrzh]
        roots = mpmath.polyroots(den, maxsteps=400, extraprec=4 * dps)
        dden = [den[i] * (4 - i) for i in range(4)]
        self.poles = roots
        self.rate = max(abs(z) for z in roots)
        self.res = [[_horner(n, z) / (z * z * _horner(dden, z)) for z in roots] for n in nums]
        self.poly = []
        for n in nums:  # N / D = c0 + c1 s + ... at s = 0: the ramp's c0 t + c1
            n0, n1 = n[-1], n[-2]
            d0, d1 = den[-1], den[-2]
            self.poly.append((n0 / d0, (n1 * d0 - n0 * d1) / (d0 * d0)))

    def value(self, o: int, t, d: int = 0):  # type: ignore[no-untyped-def]
        """Derivative ``d`` of output ``o`` at ``t``."""
        mp = self.mp
        t = mp.mpf(t)
        c0, c1 = self.poly[o]
        base = c0 * t + c1 if d == 0 else (c0 if d == 1 else 0)
        return base + mp.re(
            sum(r * p**d * mp.exp(p * t) for r, p in zip(self.res[o], self.poles, strict=True))
        )


def full_joint_state_space(q, constrained: bool = False):  # type: ignore[no-untyped-def]
    """``A``, ``b1``, ``b0`` (x' = A x + b1 t + b0 under the unit ramp) of the full series
    joint at mpmath's current precision, and K_c, C_c.

    Written out here, x = [d_r, d_r', d_e, d_h, d_h'] (against a wall: the head's two
    states dropped), with the massless motor node C d_e' = K_m (d_r - d_e) + C_m d_r' -
    K_q d_e and the ramp input s_c = t, v_c = 1: an evaluator independent of the package's
    model. Parameters ordered M_r, C_mech, K_mech, K_c, C_c, M_h, C_h, K_h, C_cont, K_cont.
    """
    import mpmath

    mp = mpmath.mp
    m_r, c_m, k_m, k_c, c_c, m_h, c_h, k_h, c_q, k_q = (mp.mpf(float(x)) for x in q)
    c_s = c_m + c_q
    n = 3 if constrained else 5  # the head against a wall: its two states dropped
    a, b1, b0 = mp.zeros(n, n), mp.zeros(n, 1), mp.zeros(n, 1)
    node = (k_m / c_s, c_m / c_s, -(k_m + k_q) / c_s)  # d_e' on d_r, d_r', d_e
    f_t = (c_q * node[0], c_q * node[1], k_q + c_q * node[2])
    a[0, 1] = 1
    a[1, 0], a[1, 1], a[1, 2] = (-k_c - f_t[0]) / m_r, (-c_c - f_t[1]) / m_r, -f_t[2] / m_r
    a[2, 0], a[2, 1], a[2, 2] = node
    b1[1], b0[1] = -k_c / m_r, -c_c / m_r
    if not constrained:
        a[1, 3], a[1, 4], a[3, 4] = k_c / m_r, c_c / m_r, 1
        a[4, 0], a[4, 1] = k_c / m_h, c_c / m_h
        a[4, 3], a[4, 4] = -(k_c + k_h) / m_h, -(c_c + c_h) / m_h
        b1[4], b0[4] = k_c / m_h, c_c / m_h
    return a, b1, b0, k_c, c_c


class MpFullJoint(_MpFirstLobe):
    """The full series joint's exact ramp responses at ``dps`` digits (mpmath), for the
    fuzz harness: the state space x = [d_r, d_r', d_e, d_h, d_h'] written out by hand
    (the massless motor node ``C d_e' = K_m (d_r - d_e) + C_m d_r' - K_q d_e``; Zeng
    2011, eq. 3.4.6; docs/impact_joint.md), its eigen-solution plus the particular
    solution ``alpha + beta t`` of the unit ramp. Parameters ordered M_r, C_mech,
    K_mech, K_c, C_c, M_h, C_h, K_h, C_cont, K_cont; outputs as :class:`MpImpact`.
    """

    def __init__(self, q, dps: int = 40, constrained: bool = False) -> None:
        import mpmath

        self.mp = mp = mpmath.mp
        mp.dps = dps
        a, b1, b0, k_c, c_c = full_joint_state_space(q, constrained)
        n = a.rows
        self.n = n
        inv = mp.inverse(a)
        self.beta = -(inv * b1)
        self.alpha = inv * (self.beta - b0)
        self.lam, self.vec = mp.eig(a)
        self.coef = mp.inverse(self.vec) * (-self.alpha)
        self.k_c, self.c_c = k_c, c_c
        # a real pole beyond 1e5 rad/s (a stiff motor node) decays within 1e-4 s and is
        # not resolved, as in designlab.impact.full_joint_model.grid_rate; mp.eig leaves it
        # an imaginary part of rounding size (1e-38), which does not make it oscillate
        self.rate = max(abs(z) for z in self.lam if abs(z) < 1e5 or abs(mp.im(z)) > 1e-20 * abs(z))

    def _state(self, i: int, t, d: int):  # type: ignore[no-untyped-def]
        """Derivative ``d`` of state ``i`` at ``t``."""
        mp = self.mp
        base = self.alpha[i] + self.beta[i] * t if d == 0 else (self.beta[i] if d == 1 else 0)
        return mp.re(base + sum(self.vec[i, k] * self.coef[k] * self.lam[k] ** d
                                * mp.exp(self.lam[k] * t) for k in range(self.n)))  # fmt: skip

    def value(self, o: int, t, d: int = 0):  # type: ignore[no-untyped-def]
        """Derivative ``d`` of output ``o`` at ``t`` (a_h is 0 when constrained)."""
        t = self.mp.mpf(t)
        if o == 1:
            return self._state(4, t, d + 1) if self.n == 5 else self.mp.mpf(0)

        def eps(e: int):  # type: ignore[no-untyped-def]
            ramp = t if e == 0 else (1 if e == 1 else 0)
            head = self._state(3, t, e) if self.n == 5 else 0
            return self._state(0, t, e) - head + ramp

        return eps(d) if o == 2 else self.k_c * eps(d) + self.c_c * eps(d + 1)


class MpConstrained(MpImpact):
    """The reduced model's constrained impact (the head against a wall; Zeng 2011, (3.6.1),
    (3.9.2)) at ``dps`` digits, for the fuzz harness: ``D = z_r + z_c`` (z_r = M_r s^2 + C_r
    s + K_r, z_c = C_c s + K_c), the force ``z_c z_r / (s^2 D)``, the compression ``z_r /
    (s^2 D)``, a_h 0; its two roots from :func:`mpmath.polyroots`. Parameters as
    :class:`MpImpact`'s (the head's ignored)."""

    def __init__(self, params, dps: int = 40) -> None:
        import mpmath

        self.mp = mp = mpmath.mp
        mp.dps = dps
        m_r, c_r, k_r, k_c, c_c = (mp.mpf(float(x)) for x in params[:5])
        den = [mp.mpf(1), (c_r + c_c) / m_r, (k_r + k_c) / m_r]
        zr = [mp.mpf(1), c_r / m_r, k_r / m_r]
        nums = [_mul([c_c, k_c], zr), [mp.mpf(0)], zr]
        roots = mpmath.polyroots(den, maxsteps=400, extraprec=4 * dps)
        dden = [2 * den[0], den[1]]
        self.poles = roots
        self.rate = max(abs(z) for z in roots)
        self.res = [[_horner(n, z) / (z * z * _horner(dden, z)) for z in roots] for n in nums]
        self.poly = []
        for n in nums:
            n0, n1 = n[-1], (n[-2] if len(n) > 1 else 0)
            self.poly.append((n0 / den[-1], (n1 * den[-1] - n0 * den[-2]) / den[-1] ** 2))


def _mul(a: list, b: list) -> list:
    """Product of two polynomials (descending coefficients)."""
    out = [0] * (len(a) + len(b) - 1)
    for i, x in enumerate(a):
        for j, y in enumerate(b):
            out[i + j] += x * y
    return out


def _horner(coeffs: list, x):  # type: ignore[no-untyped-def]
    acc = 0
    for a in coeffs:
        acc = acc * x + a
    return acc
