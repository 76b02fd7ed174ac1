"""A high-precision (mpmath) evaluator of the impact models, written for the tests only.

It shares no code with designlab. The reduced model (4 states, Zeng 2011, Sec. 3.5) and
the full series joint (5 states, (3.4.6) with a massless motor node; docs/impact_joint.md)
are written out here as state-space matrices. The ramp response with zero initial state is
``x(t) = V (c * exp(lambda t)) + alpha + beta t``: the eigen-decomposition of the
homogeneous part and the affine particular solution, all in ``mp.dps`` digits (50 by
default), so the cancellation between the slow modes and the ramp that defeats double
precision for extreme parameters costs nothing here.

The first lobe (docs/impact.md, "Metrics") is located on a grid that resolves every
oscillating mode (and the slowest real one); the grid is scanned in double precision
from the high-precision modal coefficients, with every sample whose sign or size is
within the double-precision rounding noise of its terms evaluated again at full
precision. The lobe end and the maxima are then polished at full precision (bisection
of a_h, and of the derivative of each output between grid neighbours).
"""

from __future__ import annotations

from dataclasses import dataclass

import mpmath as mp
import numpy as np

#: digits of the evaluation
DPS = 50

OUTPUTS = ("force", "head_acceleration", "compression", "head_velocity")


def _system(p, full: bool, constrained: bool = False):
    """``(A, b1, b0, C, e1, e0)``: ``x' = A x + (b1 t + b0) v``, ``y = C x + (e1 t + e0) v``.

    Rows of ``C``: force, head acceleration, compression, head velocity. ``constrained``:
    the head against a wall ((3.6.1), (3.9.4)): its states are held at zero (removed), and
    its acceleration and velocity are zero; the head's parameters are not used.
    """
    a, b1, b0, c, e1, e0, head = _free_system(p, full)
    if not constrained:
        return a, b1, b0, c, e1, e0
    keep = [j for j in range(a.rows) if j not in head]
    n = len(keep)
    a2, b12, b02, c2 = mp.zeros(n, n), mp.zeros(n, 1), mp.zeros(n, 1), mp.zeros(4, n)
    for i, ki in enumerate(keep):
        b12[i], b02[i] = b1[ki], b0[ki]
        for j, kj in enumerate(keep):
            a2[i, j] = a[ki, kj]
        for r in (0, 2):  # force and compression; the head's rows stay zero
            c2[r, i] = c[r, ki]
    for r in (1, 3):
        e1[r], e0[r] = 0, 0
    return a2, b12, b02, c2, e1, e0


def _free_system(p, full: bool):
    """:func:`_system` of the free head, and the indices of the head's two states."""
    if full:
        m_r, c_m, k_m, k_c, c_c, m_h, c_h, k_h, c_q, k_q = (mp.mpf(x) for x in p)
        # x = [d_r, d_r', d_e, d_h, d_h'];
        # d_e' = (K_m (d_r - d_e) + C_m d_r' - K_q d_e) / (C_m + C_q)
        cs = c_m + c_q
        de = [k_m / cs, c_m / cs, -(k_m + k_q) / cs, 0, 0]
        # f_t = K_q d_e + C_q d_e'
        ft = [c_q * de[0], c_q * de[1], k_q + c_q * de[2], 0, 0]
        fc = [k_c, c_c, 0, -k_c, -c_c]
        n = 5
        ir, ivr, ih, ivh = 0, 1, 3, 4
    else:
        m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h = (mp.mpf(x) for x in p)
        de = None
        ft = [k_r, c_r, 0, 0]
        fc = [k_c, c_c, -k_c, -c_c]
        n = 4
        ir, ivr, ih, ivh = 0, 1, 2, 3
    a = mp.zeros(n, n)
    a[ir, ivr] = 1
    a[ih, ivh] = 1
    if de is not None:
        for j in range(n):
            a[2, j] = de[j]
    for j in range(n):
        a[ivr, j] = (-fc[j] - ft[j]) / m_r
        a[ivh, j] = fc[j] / m_h
    a[ivh, ih] -= k_h / m_h
    a[ivh, ivh] -= c_h / m_h
    # contact force f_c = fc . x + K_c v t + C_c v
    b1, b0 = mp.zeros(n, 1), mp.zeros(n, 1)
    b1[ivr], b0[ivr] = -k_c / m_r, -c_c / m_r
    b1[ivh], b0[ivh] = k_c / m_h, c_c / m_h
    c = mp.zeros(4, n)
    e1, e0 = mp.zeros(4, 1), mp.zeros(4, 1)
    for j in range(n):
        c[0, j] = fc[j]
        c[1, j] = fc[j] / m_h
    c[1, ih] -= k_h / m_h
    c[1, ivh] -= c_h / m_h
    c[2, ir], c[2, ih] = 1, -1
    c[3, ivh] = 1
    e1[0], e0[0] = k_c, c_c
    e1[1], e0[1] = k_c / m_h, c_c / m_h
    e1[2] = 1
    return a, b1, b0, c, e1, e0, (ih, ivh)


@dataclass
class ModalOutput:
    """``y(t) = sum_k r_k exp(lam_k t) + p0 + p1 t`` at full precision (and in double)."""

    r: list
    lam: list
    p0: mp.mpf
    p1: mp.mpf

    def __post_init__(self) -> None:
        self.rd = np.array([complex(x) for x in self.r])
        self.ld = np.array([complex(x) for x in self.lam])
        self.p0d, self.p1d = float(self.p0), float(self.p1)

    def at(self, t, derivative: int = 0) -> mp.mpf:
        """The value (or a time derivative) at one time, full precision."""
        t = mp.mpf(t)
        s = mp.mpf(0)
        for r, lam in zip(self.r, self.lam, strict=True):
            s += r * lam**derivative * mp.exp(lam * t)
        s = mp.re(s)
        if derivative == 0:
            return s + self.p0 + self.p1 * t
        return s + self.p1 if derivative == 1 else s

    def grid(self, t: np.ndarray, derivative: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """Double-precision values on a grid and a bound of their rounding noise."""
        terms = (self.rd * self.ld**derivative)[None, :] * np.exp(np.outer(t, self.ld))
        y = terms.real.sum(axis=1)
        size = np.abs(terms).sum(axis=1)
        if derivative == 0:
            y = y + self.p0d + self.p1d * t
            size = size + abs(self.p0d) + np.abs(self.p1d * t)
        elif derivative == 1:
            y = y + self.p1d
            size = size + abs(self.p1d)
        return y, 1e-13 * size + 1e-300


class MpImpact:
    """The ramp response of one design at v_c = ``v`` (SI), full precision.

    ``params`` are ordered ``M_r, C_r, K_r, K_c, C_c, M_h, C_h, K_h`` (8) or
    ``M_r, C_mech, K_mech, K_c, C_c, M_h, C_h, K_h, C_cont, K_cont`` (10); ``constrained``:
    the head against a wall (its three columns are not used).
    """

    def __init__(self, params, v: float, dps: int = DPS, constrained: bool = False) -> None:
        self.dps = dps
        self.head_mass = float(params[5])
        self.constrained = constrained
        self._maxima: dict[tuple[str, float], tuple[float, float]] = {}
        with mp.workdps(dps):
            a, b1, b0, c, e1, e0 = _system(params, len(params) == 10, constrained)
            v = mp.mpf(v)
            beta = -(mp.lu_solve(a, b1 * v))
            alpha = mp.lu_solve(a, beta - b0 * v)
            lam, vec = mp.eig(a)
            coef = mp.lu_solve(vec, -alpha)
            self.lam = list(lam)
            self.outputs = {}
            for i, name in enumerate(OUTPUTS):
                row = c[i, :]
                r = [(row * vec[:, k])[0] * coef[k] for k in range(len(lam))]
                p0 = (row * alpha)[0] + e0[i] * v
                p1 = (row * beta)[0] + e1[i] * v
                self.outputs[name] = ModalOutput(r, list(lam), p0, p1)
            # x(0) = 0: every output starts at its feed-through value e0 v
            for i, name in enumerate(OUTPUTS):
                y0 = self.outputs[name].at(0)
                scale = sum(abs(x) for x in self.outputs[name].r) + abs(e0[i] * v) + 1
                assert abs(y0 - e0[i] * v) <= mp.mpf(10) ** (10 - dps) * scale, name

    def value(self, name: str, t: float, derivative: int = 0) -> float:
        with mp.workdps(self.dps):
            return float(self.outputs[name].at(t, derivative))

    def _signs(self, name: str, t: np.ndarray, derivative: int = 0) -> np.ndarray:
        """Values on a grid, exact where double precision cannot tell the sign."""
        out = self.outputs[name]
        y, noise = out.grid(t, derivative)
        unsure = np.flatnonzero(~(np.abs(y) > noise))
        with mp.workdps(self.dps):
            for j in unsure:
                y[j] = float(out.at(t[j], derivative))
        return y

    def _bisect(self, name: str, lo: float, hi: float, derivative: int) -> float:
        """The sign change of an output (or derivative) in ``[lo, hi]`` to full double precision."""
        out = self.outputs[name]
        with mp.workdps(self.dps):
            a, b = mp.mpf(lo), mp.mpf(hi)
            fa = out.at(a, derivative)
            for _ in range(200):
                mid = (a + b) / 2
                if float(mid) in (float(a), float(b)):
                    break
                fm = out.at(mid, derivative)
                if (fm > 0) == (fa > 0) and fm != 0:
                    a, fa = mid, fm
                else:
                    b = mid
            return float(b)

    def rates(self) -> tuple[float, float]:
        """``(fastest, fastest oscillating)`` pole moduli (the second 0 without one)."""
        lam = np.array([complex(x) for x in self.lam])
        osc = np.abs(lam.imag) > 1e-9 * np.abs(lam)
        return float(np.max(np.abs(lam))), float(np.max(np.abs(lam[osc]), initial=0.0))

    def grid(self, t_end: float = np.inf, max_steps: int = 400_000) -> np.ndarray:
        """Times from 0 that resolve every mode: steps of 0.2 over the fastest oscillating
        modulus, and for the real modes (a sum of real exponentials changes on the time
        scale of its own age) steps of 1 % of t, at least 0.2 over the fastest modulus."""
        fast, osc = self.rates()
        h_osc = 0.2 / osc if osc > 0 else np.inf
        h_fast = 0.2 / fast
        # 0 .. 100 h_fast in steps h; then 1 % steps up to where they reach h_osc; then h_osc
        h = min(h_osc, h_fast)
        t1 = min(100.0 * h_fast, t_end)
        parts = [np.arange(0.0, t1, h)]
        # 1 % of t reaches h_osc at 100 h_osc; no real mode lives beyond e^40 fast scales
        t2 = min(100.0 * h_osc, t_end, t1 * np.exp(40.0))
        if t2 > t1:
            n = min(int(np.ceil(np.log(t2 / t1) / np.log(1.01))), max_steps)
            parts.append(t1 * 1.01 ** np.arange(n + 1))
        if np.isfinite(h_osc) and t_end > t2:
            end = t_end if np.isfinite(t_end) else t2 + max_steps * h_osc
            parts.append(np.arange(t2, min(end, t2 + max_steps * h_osc), h_osc))
        t = np.unique(np.concatenate(parts))[:max_steps]
        out = t
        if np.isfinite(t_end):
            out = np.append(out[out < t_end], t_end)
        return out

    def lobe_end(self, horizon: float = 1e9) -> float:
        """The first t > 0 with a_h(t) <= 0 (inf if none before ``horizon`` or the grid's end)."""
        t = self.grid()
        t = t[t <= horizon]
        for start in range(0, t.size, 4096):
            tt = t[max(start - 1, 0) : start + 4096]
            a = self._signs("head_acceleration", tt)
            if start == 0:
                a[0] = 1.0  # a_h(0) = C_c v / M_h >= 0 and rising when C_c = 0
            neg = np.flatnonzero(a <= 0)
            if neg.size:
                k = int(neg[0])
                return self._bisect("head_acceleration", tt[k - 1], tt[k], 0)
        return float("inf")

    def maximum(self, name: str, t_end: float) -> tuple[float, float]:
        """``(time, value)`` of the maximum of an output over ``[0, t_end]`` (kept)."""
        if (name, t_end) not in self._maxima:
            self._maxima[(name, t_end)] = self._maximum(name, t_end)
        return self._maxima[(name, t_end)]

    def _maximum(self, name: str, t_end: float) -> tuple[float, float]:
        t = self.grid(t_end)
        t = np.union1d(t, np.linspace(0.0, t_end, 2001))
        steps = t.size
        y = self._signs(name, t)
        cands = [0, steps - 1]
        inner = np.flatnonzero((y[1:-1] >= y[:-2]) & (y[1:-1] >= y[2:])) + 1
        cands += list(inner[np.argsort(y[inner])[::-1][:4]])
        cands += list(inner[self._ranked_peaks(name, t, inner)[:4]])
        best = (0.0, -float("inf"))
        for j in cands:
            tj = float(t[j])
            if 0 < j < steps - 1:
                lo, hi = float(t[j - 1]), float(t[j + 1])
                d_lo, d_hi = self.value(name, lo, 1), self.value(name, hi, 1)
                if d_lo > 0 > d_hi:
                    tj = self._bisect(name, lo, hi, 1)
            val = self.value(name, tj)
            if val > best[1]:
                best = (tj, val)
        return best

    def _ranked_peaks(self, name: str, t: np.ndarray, inner: np.ndarray) -> np.ndarray:
        """The grid's local maxima ``inner``, best first by their value polished in double
        precision (bisection of the derivative between the grid neighbours).

        A grid value falls short of its peak by up to ~0.5 % of the amplitude (steps of 0.2
        over the modulus), far more than slowly decaying peaks differ (an undamped foam
        oscillating for the whole constrained window): ranked by grid values, the first
        and highest peak can be missed."""
        out = self.outputs[name]
        a, b = t[inner - 1].astype(float), t[inner + 1].astype(float)
        rising = (out.grid(a, 1)[0] > 0) & (out.grid(b, 1)[0] < 0)
        for _ in range(60):
            mid = 0.5 * (a + b)
            up = out.grid(mid, 1)[0] > 0
            a, b = np.where(up, mid, a), np.where(up, b, mid)
        peak = out.grid(np.where(rising, 0.5 * (a + b), t[inner]))[0]
        return np.argsort(peak)[::-1]

    def metrics(self, constrained_window: float | None = None) -> dict[str, float]:
        """``t_imp`` and the first-lobe maxima ``a_max, eps_max, f_max`` (v_c as given)."""
        t_imp = self.lobe_end() if constrained_window is None else constrained_window
        out = {"t_imp": t_imp}
        if not np.isfinite(t_imp):
            return {**out, "a_max": np.nan, "eps_max": np.nan, "f_max": np.nan}
        for key, name in (
            ("a_max", "head_acceleration"),
            ("eps_max", "compression"),
            ("f_max", "force"),
        ):
            if self.constrained and name == "head_acceleration":
                out[key] = 0.0  # the head against a wall does not move
                continue
            out[key] = self.maximum(name, t_imp)[1]
        return out

    def terms(self, name: str, t: float, derivative: int = 0) -> float:
        """The sum of the magnitudes of an output's terms at ``t``: the scale of its rounding
        noise in any evaluation of the modal sum in double precision."""
        out = self.outputs[name]
        size = float(np.sum(np.abs(out.rd * out.ld**derivative * np.exp(out.ld * t))))
        if derivative == 0:
            size += abs(out.p0d) + abs(out.p1d * t)
        elif derivative == 1:
            size += abs(out.p1d)
        return size

    def tolerances(self, exact: dict[str, float], rtol: float, noise: float) -> dict[str, float]:
        """Absolute tolerances of the metrics from their conditioning.

        ``rtol`` relative to each value, plus the rounding ``noise`` (relative to the sum of
        the terms' magnitudes) of the modal sums: of a_h at the lobe end (with the contact
        force over M_h, of which a_h is the balance against the neck's forces), divided by the
        slope of a_h there (how far that noise moves the zero), and of each output at its maximum;
        a maximum at the lobe end moves with it (its slope times the lobe end's tolerance).
        """
        t_imp = exact["t_imp"]
        slope = abs(self.value("head_acceleration", t_imp, 1))
        # a_h = (f_c - C_h v_h - K_h d_h) / M_h: near the lobe end a small balance of the
        # contact force against the neck's, so its noise scales with the force too
        scale = self.terms("head_acceleration", t_imp) + self.terms("force", t_imp) / self.head_mass
        noisy = noise * scale
        tol_t = rtol * t_imp + (noisy / slope if slope > 0 else np.inf)
        out = {"t_imp": tol_t}
        for key, name in (
            ("a_max", "head_acceleration"),
            ("eps_max", "compression"),
            ("f_max", "force"),
        ):
            t_max, y = self.maximum(name, t_imp)
            tol = rtol * abs(y) + noise * self.terms(name, t_max)
            if t_imp - t_max <= tol_t:  # a maximum at the lobe end moves with it
                tol += abs(self.value(name, t_imp, 1)) * tol_t
            out[key] = tol
        return out

    def window_tolerances(
        self, exact: dict[str, float], rtol: float, noise: float
    ) -> dict[str, float]:
        """Absolute tolerances of the constrained metrics (a fixed window ``[0, t_imp]``, no
        lobe end to move): ``rtol`` of each maximum plus the rounding ``noise`` of its
        modal sum (relative to the sum of its terms' magnitudes) where it is reached."""
        out = {}
        for key, name in (("eps_max", "compression"), ("f_max", "force")):
            t_max, y = self.maximum(name, exact["t_imp"])
            out[key] = rtol * abs(y) + noise * self.terms(name, t_max)
        return out
