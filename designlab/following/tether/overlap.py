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

__all__ = ["SharedStretch", "overlapping_paths", "shared_stretch"]

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
    """

    in_place: float
    normalised: float

    @property
    def shared(self) -> bool:
        """True if the paths share more than a crossing."""
        return self.in_place >= MIN_SHARED or self.normalised >= MIN_SHARED_FRACTION


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
    return SharedStretch(in_place=float(in_place), normalised=float(norm))


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
