"""The reduced impact model's modal solution in extended precision, for the rare design the
compiled kernel's self-check does not certify (issue 34; docs/impact.md, "Self-check").

The kernel's residue and pole error bounds (:func:`.kernel_modal.residue_errors`) come
from double-precision roots and are first-order; on nearly repeated modes under a soft
foam, or nearly double real poles, they exceed the share of a maximum the self-check
allows although the true errors are 100-200 times smaller, and the design would end
``uncertified``. Here the same closed-form transfer functions
(:func:`.kernel_poles.coefficients`, Zeng 2011 (3.5.11), (3.5.14), (3.9.2)) are
evaluated in 40-digit decimal arithmetic (the standard library's :mod:`decimal`):
the poles refined from numpy's roots by the Weierstrass (Durand-Kerner) iteration
and enclosed in the disks ``|z - z_j| <= 4 |W_j|`` (``W_j = D(z_j) / prod_(k != j)
(z_j - z_k)``; the union of the disks holds every root and a disk apart from the
others exactly one, Carstensen 1991), a pole real where its disk is the only one
meeting its mirror image, the residues and the polynomial part at 40 digits. Rounded
to double precision, each residue and pole is then exact to about one rounding of
its own size, and the error bounds handed to the kernel's searches say so. A design
whose disks overlap (poles equal to about 1e-20 of their size) is not certified here.

It costs about a millisecond a design in Python, and runs only on the designs the
kernel's self-check refused (about 3 in 20,000 of wide-range designs) and that the same
algorithm compiled in double-double arithmetic (about 32 digits, :mod:`.kernel_dd`,
about 15 microseconds a design) could not isolate; with the compiled kernels that one
is tried first.

Examples
--------
>>> import numpy as np
>>> q = np.array([[9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 46, 3e3]])
>>> resp, ok = precise_responses(q, printed=False, names=("head_acceleration",))
>>> bool(ok[0]), resp["head_acceleration"].poles.shape
(True, (1, 4))
>>> float(resp["head_acceleration"].errors.max()) < 1e-10
True
"""

from __future__ import annotations

import decimal
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from designlab.impact import kernel
from designlab.impact.kernel_dd import dd_responses
from designlab.impact.modal import ModalResponse

__all__ = ["DIGITS", "precise_responses"]

#: decimal digits of the evaluation
DIGITS = 40
#: a generous bound of the decimal evaluation's relative rounding (1e5 units of the last digit)
_EPS = 10.0 ** (5 - DIGITS)
#: the Weierstrass iteration stops once every root's disk is this small (relative): far
#: below the one rounding of a double that the result carries
_CONVERGED = 1e-30
#: most Weierstrass iterations from numpy's roots (a simple root converges quadratically)
_ITERATIONS = 60
#: the outputs, in the kernel's order (force, head acceleration, compression)
_OUTPUTS = ("force", "head_acceleration", "compression")
_UNIT = 2.0**-53
_CTX = decimal.Context(prec=DIGITS)
_D = decimal.Decimal
_ZERO = _D(0)


class _C:
    """A complex number of two decimals (the few operations the solution needs)."""

    __slots__ = ("im", "re")

    def __init__(self, re: decimal.Decimal, im: decimal.Decimal = _ZERO) -> None:
        self.re, self.im = re, im

    def __add__(self, o: _C) -> _C:
        return _C(self.re + o.re, self.im + o.im)

    def __sub__(self, o: _C) -> _C:
        return _C(self.re - o.re, self.im - o.im)

    def __mul__(self, o: _C) -> _C:
        return _C(self.re * o.re - self.im * o.im, self.re * o.im + self.im * o.re)

    def __truediv__(self, o: _C) -> _C:
        d = o.re * o.re + o.im * o.im
        return _C((self.re * o.re + self.im * o.im) / d, (self.im * o.re - self.re * o.im) / d)

    def abs(self) -> float:
        """``|z|`` (as a float, to about one rounding: only bounds use it)."""
        return math.hypot(float(self.re), float(self.im))

    def to_complex(self) -> complex:
        return complex(float(self.re), float(self.im))


def _horner(coef: Sequence[decimal.Decimal], x: _C) -> tuple[_C, _C]:
    """``P(x)`` and ``P'(x)`` of the real coefficients ``coef`` (descending)."""
    f, df = _C(coef[0]), _C(_ZERO)
    for a in coef[1:]:
        df = df * x + f
        f = f * x
        f.re += a
    return f, df


def _value(coef: Sequence[decimal.Decimal], x: _C) -> _C:
    """``P(x)`` of the real coefficients ``coef`` (descending)."""
    f = _C(coef[0])
    for a in coef[1:]:
        f = f * x
        f.re += a
    return f


def _coefficients(q: Sequence[float], printed: bool) -> tuple[list, list]:
    """The monic denominator (5,) and the numerators (3 x 6, descending) of
    :func:`.kernel_poles.coefficients`, exact to 40 digits from the design ``q``."""
    m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h = (_D(float(x)) for x in q)
    mm = m_r * m_h
    cc = c_c * c_r + c_c * c_h + (0 if printed else c_r * c_h)
    den = [
        _D(1),
        (c_r + c_c) / m_r + (c_c + c_h) / m_h,
        (k_r + k_c) / m_r + (k_h + k_c) / m_h + cc / mm,
        (k_r * (c_c + c_h) + k_c * (c_r + c_h) + k_h * (c_c + c_r)) / mm,
        (k_r * k_h + k_c * k_h + k_r * k_c) / mm,
    ]
    zr1, zr2, zh1, zh2 = c_r / m_r, k_r / m_r, c_h / m_h, k_h / m_h
    e = [_D(1), zr1 + zh1, zr2 + zr1 * zh1 + zh2, zr1 * zh2 + zr2 * zh1, zr2 * zh2]
    force = [c_c * e[0]] + [c_c * e[k] + k_c * e[k - 1] for k in range(1, 5)] + [k_c * e[4]]
    head = [c_c, c_c * zr1 + k_c, c_c * zr2 + k_c * zr1, k_c * zr2, _D(0), _D(0)]
    return den, [force, [x / m_h for x in head], [_D(0), *e]]


def _roots(den: list, start: NDArray[np.complex128]) -> tuple[list[_C], list[float]] | None:
    """The four roots of ``den`` refined from ``start`` and the radii of disks around them
    that hold one root each (None where two disks overlap: not isolated at this precision).

    The last Weierstrass corrections ``W_j`` are computed at the previous points, whose
    disks of radius ``4 |W_j|`` (plus the decimal rounding of ``D(z_j)`` over the
    product) lie within the disks of five times that around the new points."""
    z = [_C(_D(float(x.real)), _D(float(x.imag))) for x in start]
    size = [float(abs(a)) for a in den]
    radius = [np.inf] * 4
    for _ in range(_ITERATIONS):
        w = []
        for j in range(4):
            prod = _C(_D(1))
            for k in range(4):
                if k != j:
                    prod = prod * (z[j] - z[k])
            if prod.re == 0 and prod.im == 0:
                return None
            w.append(_value(den, z[j]) / prod)
            ax = z[j].abs()
            noise = _EPS * sum(c * ax ** (4 - k) for k, c in enumerate(size)) / prod.abs()
            radius[j] = 5.0 * (4.0 * w[j].abs() + noise)
        z = [zj - wj for zj, wj in zip(z, w, strict=True)]
        if max(radius) <= _CONVERGED * max(x.abs() for x in z):
            break
    for j in range(4):
        for k in range(j + 1, 4):
            if not (z[j] - z[k]).abs() > radius[j] + radius[k]:
                return None
    return z, radius


def _fold(z: list[_C], radius: list[float]) -> list[tuple[int, float]] | None:
    """The roots kept by the fold (one per conjugate pair) and their weights (2 for a
    pair, 1 for a real root); None where a disk meets the real axis and another disk."""
    keep = []
    for j, x in enumerate(z):
        if abs(float(x.im)) > radius[j]:  # the disk lies off the axis: a complex root
            if x.im > 0:
                keep.append((j, 2.0))
            continue
        mirror = _C(x.re, -x.im)
        for k in range(4):  # the mirror disk may meet this disk only: the root is real
            if k != j and (mirror - z[k]).abs() <= radius[j] + radius[k]:
                return None
        z[j] = _C(x.re)  # moved by at most the radius
        radius[j] *= 2.0
        keep.append((j, 1.0))
    return keep


def _design(q: Sequence[float], printed: bool, start: NDArray[np.complex128], out: tuple) -> bool:
    """One design's folded poles, residues, polynomial parts and error bounds into the rows
    ``out = (poles (4,), residues (3, 4), poly (3, 2), errors (3, 4, 2))``; False where
    the poles are not isolated."""
    poles, res, poly, err = out
    with decimal.localcontext(_CTX):
        den, nums = _coefficients(q, printed)
        found = _roots(den, start)
        if found is None:
            return False
        z, radius = found
        keep = _fold(z, radius)
        if keep is None or sum(w for _, w in keep) != 4:
            return False
        for slot, (j, w) in enumerate(keep):
            x = z[j]
            ax = x.abs()
            poles[slot] = x.to_complex()
            dp = x * x
            sep = 0.0
            for k in range(4):
                if k != j:
                    dp = dp * (x - z[k])
                    sep += (radius[j] + radius[k]) / (x - z[k]).abs()
            delta = radius[j] + ax * _UNIT  # the pole's error once rounded
            for o in range(3):
                f, df = _horner(nums[o], x)
                r = f * _C(_D(w)) / dp
                res[o, slot] = r.to_complex()
                a = r.abs()
                size = sum(abs(float(c)) * ax**k for k, c in enumerate(reversed(nums[o])))
                slope = df.abs() * w / dp.abs()
                # the decimal evaluation, the root's enclosure, then one rounding of r
                e = _EPS * size * w / dp.abs() + slope * radius[j] + a * (sep + 2 * radius[j] / ax)
                err[o, slot, 0] = 2.0 * (e + 2.0 * a * _UNIT)
                err[o, slot, 1] = 2.0 * a * delta
        for o in range(3):
            rho0 = nums[o][5] / den[4]
            poly[o] = float(rho0), float((nums[o][4] - den[3] * rho0) / den[4])
    for slot in range(len(keep), 4):  # unused slots: the first pole with a zero residue
        poles[slot] = poles[0]
    return True


def precise_responses(
    params: NDArray[np.float64], *, printed: bool, names: Sequence[str], compiled: bool = True
) -> tuple[dict[str, ModalResponse], NDArray[np.bool_]]:
    """The unit-ramp responses of reduced, unconstrained designs from 40-digit poles and
    residues, with error bounds of about one rounding.

    Parameters
    ----------
    params
        ``(N, 8)`` rows ordered as :data:`~designlab.impact.model.PARAM_NAMES`.
    printed
        Use the thesis's printed q2 of (3.5.14).
    names
        The outputs to return (of ``force``, ``head_acceleration``, ``compression``).
    compiled
        Try the compiled double-double evaluation first (where numba is available); else
        40-digit decimal only (error bounds about 1e10 times tighter where a residue is
        small against its numerator's terms: the lobe end of nearly repeated modes).

    Returns
    -------
    tuple
        ``{name: ModalResponse}`` (4 folded poles a design, unused ones with zero
        residues; ``errors`` the bounds of each residue's and pole's error) and a
        ``(N,)`` mask of the designs whose poles were isolated (the others' rows are
        NaN: not certified here).
    """
    p = np.asarray(params, dtype=np.float64)
    n = p.shape[0]
    poles = np.zeros((n, 4), dtype=np.complex128)
    res = np.zeros((n, 3, 4), dtype=np.complex128)
    poly = np.zeros((n, 3, 2))
    err = np.zeros((n, 3, 4, 2))
    ok = np.zeros(n, dtype=bool)
    if compiled and kernel.AVAILABLE:  # double-double first; the designs it leaves, in decimal
        poles, res, poly, err, ok = dd_responses(p, printed)
    for i in np.flatnonzero(~ok):
        m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h = p[i]
        cc = c_c * c_r + c_c * c_h + (0.0 if printed else c_r * c_h)
        den = [1.0, (c_r + c_c) / m_r + (c_c + c_h) / m_h,
               (k_r + k_c) / m_r + (k_h + k_c) / m_h + cc / (m_r * m_h),
               (k_r * (c_c + c_h) + k_c * (c_r + c_h) + k_h * (c_c + c_r)) / (m_r * m_h),
               (k_r * k_h + k_c * k_h + k_r * k_c) / (m_r * m_h)]  # fmt: skip
        start = np.roots(den)
        if start.size == 4 and np.all(np.isfinite(start)):
            ok[i] = _design(p[i], printed, start, (poles[i], res[i], poly[i], err[i]))
    for arr in (res, poly, err):
        arr[~ok] = np.nan
    out = {}
    for o, name in enumerate(_OUTPUTS):
        if name in names:
            out[name] = ModalResponse(poles.copy(), res[:, o].copy(), poly[:, o].copy(), err[:, o])
    return out, ok
