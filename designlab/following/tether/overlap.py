"""Do two leader paths share a stretch? (Honest validation of tuned gains.)

Gains tuned on some paths and "validated" on a path that contains one of them
(the out-and-back slalom starts with the one-way slalom) or is one of them
scaled (the a = 2 m figure-eight is the a = 4 m one at half size) are
validated on what they were tuned on. :func:`shared_stretch` measures the
longest stretch of one path that lies within a tolerance of another, in place
and after normalising both paths for position, heading, size and mirroring
(each translated to start at the origin, rotated to start along +x, scaled to
unit length, and also reflected in the x axis). :func:`overlapping_paths` lists
the pairs of a validation set and a tuning set that share more than a crossing.

Examples
--------
>>> from designlab.following.tether.paths import figure_eight, slalom, square_s
>>> round(shared_stretch(slalom(out_and_back=True), slalom()).in_place, 2)
7.41
>>> shared_stretch(figure_eight(a=2.0), figure_eight(a=4.0)).normalised > 0.99
True
>>> overlapping_paths([square_s()], [figure_eight(a=4.0), slalom()])
[]
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from designlab.following.tether.paths import LeaderPath

__all__ = ["SharedStretch", "overlapping_paths", "shared_stretch", "sliding_stretch"]

#: Two paths "share a segment" if a stretch this long (m) lies within IN_PLACE_TOL of the other.
MIN_SHARED = 0.5
#: Distance (m) within which a point of one path is on the other.
IN_PLACE_TOL = 0.02
#: The same for the normalised (unit-length) paths: a fraction of the path length.
NORMALISED_TOL = 0.002
#: Fraction of a normalised path that counts as shared.
MIN_SHARED_FRACTION = 0.2
#: A normalised shared stretch counts only if it turns by at least this much (rad).
MIN_TURNING = 0.5


#: Sliding windows: the window along path ``a`` (m), its stride (m), the spacing of the
#: candidate starts on ``b`` (m), the samples per window and the largest heading difference
#: (rad) of a match; a window must turn by at least MIN_TURNING, and the scale of the copy
#: lie within SCALES.
WINDOW = 2.0
#: A sliding stretch this long (m of ``a``) is shared: a window and 1 m more of one placement.
MIN_SLIDING = 3.0
WINDOW_STRIDE = 0.1
START_STEP = 0.005
WINDOW_SAMPLES = 33
HEADING_TOL = 0.005
SCALES = (0.2, 5.0)


@dataclass(frozen=True)
class SharedStretch:
    """The longest stretch of path ``a`` on path ``b``.

    Attributes
    ----------
    in_place
        Length in m of the longest stretch of ``a`` within ``IN_PLACE_TOL`` of ``b``.
    normalised
        Fraction of ``a``'s length of the longest stretch of normalised ``a``
        within ``NORMALISED_TOL`` of normalised ``b`` (or of its mirror image)
        that turns by at least ``MIN_TURNING`` (straight pieces all look alike
        once sizes are normalised).

    sliding
        Length in m (of ``a``) of the longest stretch of ``a`` whose every ``WINDOW``-long
        window is a copy of one stretch of ``b`` anywhere along it, moved, rotated, scaled
        (by ``SCALES``) or mirrored (:func:`sliding_stretch`; shared from ``MIN_SLIDING``):
        the heading along the window, relative to its start, as a function of the fraction
        of the window's length, agrees within ``HEADING_TOL``
        (the turning function determines a curve up to similarity). 0 when no window that
        turns by ``MIN_TURNING`` matches.
    """

    in_place: float
    normalised: float
    sliding: float = 0.0

    @property
    def shared(self) -> bool:
        """True if the paths share more than a crossing."""
        return (
            self.in_place >= MIN_SHARED
            or self.normalised >= MIN_SHARED_FRACTION
            or self.sliding >= MIN_SLIDING
        )


def _resample(xy: NDArray[np.float64], step: float) -> NDArray[np.float64]:
    """Points every ``step`` of arc length along a polyline."""
    seg = np.hypot(*np.diff(xy, axis=0).T)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    t = np.linspace(0.0, s[-1], max(int(np.ceil(s[-1] / step)), 1) + 1)
    return np.column_stack([np.interp(t, s, xy[:, 0]), np.interp(t, s, xy[:, 1])])


def _runs(flags: NDArray[np.bool_]) -> NDArray[np.int64]:
    """(start, stop) index pairs of the runs of True in ``flags``."""
    padded = np.concatenate([[0], flags.astype(np.int8), [0]])
    edges = np.flatnonzero(np.diff(padded))
    return edges.reshape(-1, 2)


def _turning(pts: NDArray[np.float64]) -> NDArray[np.float64]:
    """Cumulative absolute turning (rad) at each point of a resampled polyline."""
    heading = np.unwrap(np.arctan2(*np.diff(pts, axis=0).T[::-1]))
    return np.concatenate([[0.0, 0.0], np.cumsum(np.abs(np.diff(heading)))])


def _stretch(a: NDArray, b: NDArray, tol: float, step: float, min_turning: float = 0.0) -> float:
    """Longest stretch (in units of the paths) of ``a`` within ``tol`` of ``b``.

    Only stretches that turn by at least ``min_turning`` rad count (a straight
    piece has the shape of every other straight piece once sizes are normalised).
    """
    pa = _resample(a, step)
    pb = _resample(b, 0.25 * tol)  # dense enough that point distance ~ polyline distance
    d, _ = cKDTree(pb).query(pa)
    turn = _turning(pa) if min_turning > 0 else np.zeros(len(pa))
    best = 0
    edge = int(np.ceil(4 * tol / step))  # a corner at either end of a run is not shared
    for start, stop in _runs(d <= tol):
        inner = (min(start + edge, stop - 1), max(stop - 1 - edge, start))
        if min_turning == 0 or turn[inner[1]] - turn[inner[0]] >= min_turning:
            best = max(best, stop - start - 1)
    return best * float(np.hypot(*(pa[1] - pa[0])))


def _normalise(path: LeaderPath) -> NDArray[np.float64]:
    """Start at the origin, start along +x, unit length."""
    xy = path.points - path.points[0]
    head = path.initial_heading
    if head is None:
        head = float(np.arctan2(xy[1, 1], xy[1, 0]))
    c, s = np.cos(-head), np.sin(-head)
    return (xy @ np.array([[c, -s], [s, c]]).T) / path.length


def _heading(xy: NDArray[np.float64], step: float) -> tuple[NDArray, NDArray, NDArray]:
    """Arc length, unwrapped heading and cumulative absolute turning of a resampled path."""
    pts = _resample(xy, step)
    seg = np.diff(pts, axis=0)
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*seg.T))])
    head = np.unwrap(np.arctan2(seg[:, 1], seg[:, 0]))
    head = np.concatenate([head, head[-1:]])  # heading of the segment that starts at each point
    turn = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(head)))])
    return s, head, turn


def _window_candidates(
    sig: NDArray, turning: float, s: NDArray, head: NDArray, turn: NDArray, width: float
) -> NDArray[np.float64]:
    """Placements on the path ``(s, head, turn)`` of which the window signature ``sig``
    (heading against the fraction of the window, from 0) is a similar copy: rows of
    (start on b in m, scale, mirrored 0/1)."""
    u = np.linspace(0.0, 1.0, len(sig))
    key = turn + 1e-12 * s  # strictly increasing: the end is where the turning is reached
    starts = s[key <= key[-1] - turning]
    if len(starts) == 0:
        return np.empty((0, 3))
    t0 = np.interp(starts, s, key)
    length = np.interp(t0 + turning, key, s) - starts
    ok = (length >= SCALES[0] * width) & (length <= SCALES[1] * width)
    starts, length = starts[ok], length[ok]
    at = starts[:, None] + length[:, None] * u[None, :]
    other = np.interp(at, s, head) - np.interp(starts, s, head)[:, None]
    same = np.abs(other - sig[None, :]).max(axis=1)
    mirrored = np.abs(other + sig[None, :]).max(axis=1)
    keep = np.minimum(same, mirrored) <= HEADING_TOL
    return np.column_stack([starts[keep], length[keep] / width, (mirrored < same)[keep]])


def _chained(previous: NDArray, chain: NDArray, current: NDArray) -> NDArray[np.int64]:
    """Chain lengths of the current window's placements: one more than the longest chain of
    a placement of the previous window that this one continues (same scale and mirroring,
    its start moved on by the stride at that scale)."""
    out = np.ones(len(current), dtype=np.int64)
    if len(previous) == 0 or len(current) == 0:
        return out
    step = WINDOW_STRIDE * previous[:, 1]
    for j, (start, scale, mirror) in enumerate(current):
        fits = (
            (np.abs(previous[:, 1] - scale) <= 0.01 * scale)
            & (previous[:, 2] == mirror)
            & (np.abs(previous[:, 0] + step - start) <= 2 * START_STEP + 0.01 * step)
        )
        if fits.any():
            out[j] = 1 + int(chain[fits].max())
    return out


def sliding_stretch(a: LeaderPath, b: LeaderPath) -> float:
    """Longest stretch (m of ``a``) of ``a`` that is a similar copy of a stretch of ``b``.

    Every ``WINDOW``-long window of ``a`` (every ``WINDOW_STRIDE``) is compared with every
    stretch of ``b`` that turns by as much, wherever it lies along ``b``: anchoring neither
    path at its start, a copy placed mid-path is found. Consecutive windows count as one
    stretch only when they match one placement (the same scale and mirroring, moving on
    along ``b`` together), so isolated look-alike arcs do not add up. See
    :class:`SharedStretch`.

    Parameters
    ----------
    a, b
        Leader paths.

    Examples
    --------
    >>> from designlab.following.tether.paths import figure_eight, slalom
    >>> sliding_stretch(slalom(), figure_eight(a=4.0))
    0.0
    """
    sa, ha, ta = _heading(a.points, 0.01)
    sb, hb, tb = _heading(b.points, START_STEP)
    width = min(WINDOW, sa[-1])
    u = np.linspace(0.0, 1.0, WINDOW_SAMPLES)
    previous, chain, longest = np.empty((0, 3)), np.empty(0, dtype=np.int64), 0
    for s0 in np.arange(0.0, sa[-1] - width + 1e-9, WINDOW_STRIDE):
        turning = float(np.interp(s0 + width, sa, ta) - np.interp(s0, sa, ta))
        current = np.empty((0, 3))
        if turning >= MIN_TURNING:
            sig = np.interp(s0 + width * u, sa, ha) - np.interp(s0, sa, ha)
            current = _window_candidates(sig, turning, sb, hb, tb, width)
        chain = _chained(previous, chain, current)
        previous = current
        if len(chain):
            longest = max(longest, int(chain.max()))
    return 0.0 if longest == 0 else float(width + (longest - 1) * WINDOW_STRIDE)


def shared_stretch(a: LeaderPath, b: LeaderPath) -> SharedStretch:
    """The longest stretch of ``a`` that lies on ``b``, in place and normalised.

    Parameters
    ----------
    a, b
        Leader paths.

    Returns
    -------
    SharedStretch
    """
    in_place = _stretch(a.points, b.points, IN_PLACE_TOL, 0.01)
    na, nb = _normalise(a), _normalise(b)
    mirror = nb * np.array([1.0, -1.0])
    norm = max(_stretch(na, other, NORMALISED_TOL, 0.001, MIN_TURNING) for other in (nb, mirror))
    return SharedStretch(
        in_place=float(in_place), normalised=float(norm), sliding=sliding_stretch(a, b)
    )


def overlapping_paths(
    validation: Sequence[LeaderPath], tuning: Sequence[LeaderPath]
) -> list[tuple[str, str, SharedStretch]]:
    """The (validation, tuning) pairs that share more than a crossing.

    Parameters
    ----------
    validation, tuning
        The two sets of leader paths.

    Returns
    -------
    list of (validation name, tuning name, SharedStretch)
    """
    out = []
    for v in validation:
        for t in tuning:
            st = shared_stretch(v, t)
            if st.shared:
                out.append((v.name, t.name, st))
    return out
