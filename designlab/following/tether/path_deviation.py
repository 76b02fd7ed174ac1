"""Normal path deviation between a leader path and a follower path (Allan 2015 App. A).

The thesis's primary accuracy metric (Sec. 2.5.1.3, App. A): the leader path
(path 1) is split into short segments and, from the midpoint of each, a normal
line is extended to the follower path (path 2); the distance to the
intersection is that segment's deviation. The algorithm, as in App. A:

1. re-segment both paths: a minimum-length pass merges segments shorter than
   ``min_segment`` with the next one (the last one backwards; this also drops
   the repeated nodes of a stopped robot), then a maximum-length pass splits
   segments longer than ``max_segment`` into ``ceil(L / max_segment)`` equal parts;
2. find the intersections of every segment pair of the two paths by
   eq. (A.2)-(A.3) and insert them as nodes in both paths;
3. find the comparison range: from the first segment of path 1 to path 2,
   and from the last segment of path 2 to path 1, by the same normal
   procedure. ``comparison="ordered"`` (the default) searches the start only
   in the first half of path 2 and the end only in the second half of path 1
   (by arc length), so that closed or out-and-back paths do not match the
   robot's end to the leader's start; ``"literal"`` searches all;
4. the normal deviation of each path-1 segment in range against path 2 in
   range: the nearest hit of the normal line in either direction (unsigned),
   within ``max_search`` (2 m). Where there is no hit, the point-to-polyline
   distance is used instead (the "fallback").

This is App. A by default. One heuristic is an opt-in option:
``far_hit_fallback_ratio=k`` also replaces a normal hit that is more than k
times farther than the nearest point of path 2 by that point-to-polyline
distance (meant for a normal that crosses a corner and hits an unrelated part
of the path, the failure App. A.6 describes). It is not App. A: where the
paths cross or return on themselves it swaps valid hits for the distance to
another leg and lowers the deviation (see ``docs/following.md`` for its
measured effect).

Mean, standard deviation and maximum are reported in metres and in units of
the wheel track (b = 0.28 m, as Tables 3.2/3.3). See ``docs/following.md``.

Examples
--------
>>> import numpy as np
>>> x = np.linspace(0.0, 5.0, 501)
>>> d = normal_path_deviation(np.column_stack([x, 0 * x]), np.column_stack([x, 0.1 + 0 * x]))
>>> round(d.mean, 6), round(d.std, 6), round(d.mean_over_b, 4)
(0.1, 0.0, 0.3571)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import chain
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from designlab.errors import InvalidParameterError
from designlab.following.tether.parameters import WHEEL_TRACK
from designlab.params import Param, check_size
from designlab.results import Result, Status

__all__ = [
    "COMPARISON",
    "FAR_HIT_FALLBACK_RATIO",
    "MAX_SEARCH",
    "MAX_SEGMENT",
    "MIN_SEGMENT",
    "DeviationStatus",
    "PathDeviation",
    "normal_path_deviation",
    "normal_path_deviations",
    "resegment",
]

#: L_min of the re-segmentation (App. A, Fig. A.3).
MIN_SEGMENT = Param(
    "L_min",
    "m",
    "shortest segment of the re-segmentation",
    gt=0,
    le=1,
    default=0.01,
    name="min_segment",
)
#: L_max of the re-segmentation (App. A, Fig. A.4).
MAX_SEGMENT = Param(
    "L_max",
    "m",
    "longest segment of the re-segmentation",
    gt=0,
    le=10,
    default=0.05,
    name="max_segment",
)
#: The longest normal searched.
MAX_SEARCH = Param(
    None, "m", "longest normal searched", gt=0, le=100, default=2.0, name="max_search"
)
#: Opt-in heuristic (not App. A): a normal hit farther than this multiple of the
#: point-to-polyline distance is replaced by that distance.
FAR_HIT_FALLBACK_RATIO = Param(
    None,
    "",
    "replace a normal hit farther than this multiple of the point-to-polyline distance "
    "by that distance (a heuristic, not App. A)",
    gt=0,
    le=1e6,
    optional=True,
    none="every hit within max_search (App. A)",
    default=None,
    name="far_hit_fallback_ratio",
)
#: The comparison range of App. A step 5.
COMPARISON = Param(
    kind="choice",
    choices=("ordered", "literal"),
    doc="comparison range (App. A step 5)",
    default="ordered",
    name="comparison",
)
#: The most nodes of a path compared.
_MAX_NODES = 1_000_000


class DeviationStatus(Status):
    """Status of a normal path deviation.

    ``OK``: the deviation was measured over a comparison range. ``EMPTY``: the
    two paths have no comparison range (App. A.6: the paths are too dissimilar).
    """

    OK = "ok"
    EMPTY = "empty"


@dataclass(frozen=True, eq=False)
class PathDeviation(Result):
    """Normal path deviation of a follower path from a leader path (Allan 2015 App. A).

    Attributes
    ----------
    mean, std, max
        Statistics of the per-segment deviation in m (``std`` with ddof 0).
    profile
        Per-segment deviation in m over the comparison range, shape (M,).
    distance
        Arc length along the re-segmented leader path of each segment
        midpoint in m, shape (M,) (the profile's x-axis).
    midpoints
        Segment midpoints in m, shape (M, 2).
    fallback
        True where the point-to-polyline fallback was used, shape (M,).
    wheel_track
        Normalising length b in m.
    leader_nodes, follower_nodes
        The re-segmented paths (with intersections inserted), in m.
    range_start, range_end
        Index of the first compared follower segment and of the last compared
        leader segment.
    status
        ``"ok"``, or why the deviation could not be measured everywhere.
    warnings
        What a user should know (e.g. segments measured by the point-to-polyline fallback).
    """

    profile: NDArray[np.float64]
    distance: NDArray[np.float64]
    midpoints: NDArray[np.float64]
    fallback: NDArray[np.bool_]
    wheel_track: float
    leader_nodes: NDArray[np.float64]
    follower_nodes: NDArray[np.float64]
    range_start: int
    range_end: int
    status: DeviationStatus = DeviationStatus.OK
    warnings: tuple[str, ...] = ()

    @property
    def mean(self) -> float:
        """Mean deviation in m."""
        return float(np.mean(self.profile)) if len(self.profile) else math.nan

    @property
    def std(self) -> float:
        """Standard deviation of the deviation in m."""
        return float(np.std(self.profile)) if len(self.profile) else math.nan

    @property
    def max(self) -> float:
        """Maximum deviation in m (dominated by end-of-range artefacts on simulated runs)."""
        return float(np.max(self.profile)) if len(self.profile) else math.nan

    @property
    def median(self) -> float:
        """Median deviation in m."""
        return float(np.median(self.profile)) if len(self.profile) else math.nan

    @property
    def mean_over_b(self) -> float:
        """Mean deviation in wheel tracks (as Allan 2015 Tables 3.2, 3.3)."""
        return self.mean / self.wheel_track

    @property
    def std_over_b(self) -> float:
        """Standard deviation in wheel tracks."""
        return self.std / self.wheel_track

    @property
    def max_over_b(self) -> float:
        """Maximum in wheel tracks."""
        return self.max / self.wheel_track

    @property
    def fallback_fraction(self) -> float:
        """Fraction of segments measured by the point-to-polyline fallback."""
        return float(np.mean(self.fallback)) if len(self.fallback) else math.nan

    def statistics(self) -> dict[str, float]:
        """Mean/std/max in m and in wheel tracks, and the fallback fraction."""
        return {
            "npd_mean_m": self.mean,
            "npd_std_m": self.std,
            "npd_max_m": self.max,
            "npd_mean_over_b": self.mean_over_b,
            "npd_std_over_b": self.std_over_b,
            "npd_max_over_b": self.max_over_b,
            "segments": float(len(self.profile)),
            "fallback_fraction": self.fallback_fraction,
        }

    def to_frame(self) -> pd.DataFrame:
        """The profile: distance along the leader path, deviation (m and /b), fallback."""
        return pd.DataFrame(
            {
                "distance_m": self.distance,
                "x_m": self.midpoints[:, 0],
                "y_m": self.midpoints[:, 1],
                "deviation_m": self.profile,
                "deviation_over_b": self.profile / self.wheel_track,
                "fallback": self.fallback,
            }
        )


def _as_path(name: str, xy: Any) -> NDArray[np.float64]:
    if isinstance(xy, np.ndarray) and xy.size > 2 * _MAX_NODES:
        raise InvalidParameterError(name, f"{xy.size // 2} points", f"at most {_MAX_NODES}", "m")
    try:
        pts = np.array(xy, dtype=float)
    except (TypeError, ValueError):
        raise InvalidParameterError(
            name, type(xy).__name__, "an (N, 2) array of numbers", "m"
        ) from None
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise InvalidParameterError(name, f"shape {pts.shape}", "shape (N, 2)", "m")
    if not 2 <= pts.shape[0] <= _MAX_NODES:
        raise InvalidParameterError(
            name, f"{pts.shape[0]} point(s)", f"at least 2 and at most {_MAX_NODES} points", "m"
        )
    if not np.all(np.isfinite(pts)):
        bad = int(np.argwhere(~np.isfinite(pts))[0, 0])
        raise InvalidParameterError(f"{name}[{bad}]", pts[bad].tolist(), "finite coordinates", "m")
    return pts


def resegment(
    points: Any, min_segment: float = MIN_SEGMENT.default, max_segment: float = MAX_SEGMENT.default
) -> NDArray[np.float64]:
    """Re-segment a polyline as App. A (Figs. A.3, A.4): merge short, split long segments.

    Parameters
    ----------
    points
        (N, 2) nodes in m.
    min_segment
        L_min in m: a shorter segment is merged with the next (its shared
        node deleted); the last one is merged backwards.
    max_segment
        L_max in m: a longer segment is split into ``ceil(L / L_max)`` equal parts.

    Examples
    --------
    >>> resegment([[0, 0], [0.004, 0], [0.02, 0], [0.12, 0]]).tolist()
    [[0.0, 0.0], [0.02, 0.0], [0.07, 0.0], [0.12, 0.0]]
    """
    pts = _as_path("points", points)
    min_segment = MIN_SEGMENT.check(min_segment)
    max_segment = MAX_SEGMENT.check(max_segment)
    if max_segment < min_segment:
        raise InvalidParameterError(
            "max_segment", max_segment, f">= min_segment ({min_segment})", "m"
        )
    xs, ys = pts[:, 0].tolist(), pts[:, 1].tolist()
    keep = [0]
    lx, ly = xs[0], ys[0]
    hyp = math.hypot
    for i in range(1, len(xs) - 1):
        x, y = xs[i], ys[i]
        if hyp(x - lx, y - ly) >= min_segment:
            keep.append(i)
            lx, ly = x, y
    if len(keep) > 1 and hyp(xs[-1] - lx, ys[-1] - ly) < min_segment:
        keep.pop()  # the last segment is merged backwards
    keep.append(len(xs) - 1)
    nodes = pts[keep]
    seg = np.diff(nodes, axis=0)
    length = np.hypot(seg[:, 0], seg[:, 1])
    n_parts = np.maximum(np.ceil(length / max_segment - 1e-9), 1)
    check_size("max_segment", max_segment, 2.0 * float(np.sum(n_parts)), what="the segments")
    parts = n_parts.astype(int)
    if np.all(parts == 1):
        return nodes
    start = np.repeat(nodes[:-1], parts, axis=0)
    step = np.repeat(seg / parts[:, None], parts, axis=0)
    k = np.concatenate([np.arange(p) for p in parts])
    return np.vstack([start + k[:, None] * step, nodes[-1:]])


def _insert_intersections(
    p1: NDArray, p2: NDArray, max_segment: float
) -> tuple[NDArray, NDArray, int]:
    """Insert the proper intersections of the two polylines into both (eq. A.2-A.3)."""
    a, b = p1[:-1], p1[1:]
    c, d = p2[:-1], p2[1:]
    r = max(float(np.max(np.hypot(*(b - a).T))), float(np.max(np.hypot(*(d - c).T))))
    tree1 = cKDTree(0.5 * (a + b))
    tree2 = cKDTree(0.5 * (c + d))
    pairs = tree1.sparse_distance_matrix(tree2, r + 1e-12, output_type="ndarray")
    i, j = pairs["i"].astype(np.int64), pairs["j"].astype(np.int64)
    if len(i) == 0:
        return p1, p2, 0
    u = b[i] - a[i]
    v = d[j] - c[j]
    w = c[j] - a[i]
    den = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]  # the determinant of (A.2)
    ok = np.abs(den) > 1e-14 * np.hypot(*u.T) * np.hypot(*v.T)
    with np.errstate(divide="ignore", invalid="ignore"):
        m = (w[:, 0] * v[:, 1] - w[:, 1] * v[:, 0]) / den
        n = (w[:, 0] * u[:, 1] - w[:, 1] * u[:, 0]) / den
    eps = 1e-12
    ok &= (m > eps) & (m < 1 - eps) & (n > eps) & (n < 1 - eps)  # (A.3), nodes excluded
    if not np.any(ok):
        return p1, p2, 0
    i, j, m, n = i[ok], j[ok], m[ok], n[ok]
    xpt = a[i] + m[:, None] * u[ok]

    def insert(p: NDArray, seg: NDArray, par: NDArray) -> NDArray:
        order = np.lexsort((par, seg))
        return np.insert(p, seg[order] + 1, xpt[order], axis=0)

    return insert(p1, i, m), insert(p2, j, n), len(i)


def _flatten(lists: Any) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """(row, item) index pairs of a sequence of index lists (cKDTree ball queries)."""
    lengths = np.fromiter(map(len, lists), dtype=np.int64, count=len(lists))
    rows = np.repeat(np.arange(len(lists)), lengths)
    items = np.fromiter(chain.from_iterable(lists), dtype=np.int64, count=int(lengths.sum()))
    return rows, items


def _point_segment_distance(pts: NDArray, c: NDArray, d: NDArray) -> NDArray:
    v = d - c
    vv = np.einsum("ij,ij->i", v, v)
    t = np.clip(np.einsum("ij,ij->i", pts - c, v) / np.where(vv > 0, vv, 1.0), 0.0, 1.0)
    q = c + t[:, None] * v
    return np.hypot(*(pts - q).T)


def _nearest_segments(
    mid: NDArray, tree: cKDTree, c: NDArray, d: NDArray, half: float
) -> tuple[NDArray, NDArray]:
    """The exact point-to-polyline distance of each point and the index of the nearest segment."""
    nq = len(mid)
    # every segment within the nearest-midpoint distance + half a segment is a candidate
    dn, _ = tree.query(mid)
    qi, sj = _flatten(tree.query_ball_point(mid, dn + half + 1e-12))
    dist = _point_segment_distance(mid[qi], c[sj], d[sj])
    order = np.lexsort((dist, qi))
    first = np.ones(len(order), bool)
    first[1:] = qi[order][1:] != qi[order][:-1]
    near_seg = np.empty(nq, dtype=int)
    d_pl = np.empty(nq)
    near_seg[qi[order][first]] = sj[order][first]
    d_pl[qi[order][first]] = dist[order][first]
    return d_pl, near_seg


def _normal_hits(
    mid: NDArray, normal: NDArray, tree: cKDTree, c: NDArray, d: NDArray, half: float, rho: NDArray
) -> tuple[NDArray, NDArray]:
    """Distance to the nearest hit of each normal line within ``rho`` (inf: none), and its segment.

    A segment with a point within ``rho`` of the midpoint has its own midpoint
    within ``rho + half``, so every hit within ``rho`` is among the candidates.
    """
    nq = len(mid)
    qi, sj = _flatten(tree.query_ball_point(mid, rho + half + 1e-12))
    nrm = normal[qi]
    v = d[sj] - c[sj]
    w = c[sj] - mid[qi]
    den = nrm[:, 0] * v[:, 1] - nrm[:, 1] * v[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (w[:, 0] * v[:, 1] - w[:, 1] * v[:, 0]) / den
        u = (w[:, 0] * nrm[:, 1] - w[:, 1] * nrm[:, 0]) / den
    at = np.abs(t)
    hit = (np.abs(den) > 1e-15) & (u >= 0.0) & (u <= 1.0) & (at <= rho[qi])
    best = np.full(nq, np.inf)
    best_seg = np.zeros(nq, dtype=int)
    if np.any(hit):
        qh, th, sh = qi[hit], at[hit], sj[hit]
        order = np.lexsort((th, qh))
        first = np.ones(len(order), bool)
        first[1:] = qh[order][1:] != qh[order][:-1]
        best[qh[order][first]] = th[order][first]
        best_seg[qh[order][first]] = sh[order][first]
    return best, best_seg


def _normal_deviation(
    mid: NDArray,
    normal: NDArray,
    c: NDArray,
    d: NDArray,
    max_search: float,
    far_hit_ratio: float | None,
) -> tuple[NDArray, NDArray, NDArray]:
    """Nearest normal hit (or fallback) from each midpoint to the segments CD.

    The nearest hit is searched in growing radii (twice the point-to-polyline
    distance first, then doubling up to the search limit): a hit found within
    a radius is the nearest of all, so the answer equals one search over the
    whole limit, at a fraction of its cost. Returns the deviation, the index of
    the segment hit (or nearest), and the fallback mask.
    """
    nq = len(mid)
    half = 0.5 * float(np.max(np.hypot(*(d - c).T)))
    tree = cKDTree(0.5 * (c + d))
    d_pl, near_seg = _nearest_segments(mid, tree, c, d, half)
    limit = np.full(nq, max_search)
    if far_hit_ratio is not None:
        limit = np.minimum(limit, far_hit_ratio * d_pl + 1e-9)
    best = np.full(nq, np.inf)
    best_seg = near_seg.copy()
    todo = np.arange(nq)
    rho = np.minimum(limit, np.maximum(2.0 * d_pl, 2.0 * half) + 1e-9)
    while len(todo):
        b, bs = _normal_hits(mid[todo], normal[todo], tree, c, d, half, rho[todo])
        found = np.isfinite(b)
        best[todo[found]] = b[found]
        best_seg[todo[found]] = bs[found]
        more = ~found & (rho[todo] < limit[todo])
        todo = todo[more]
        rho[todo] = np.minimum(limit[todo], 2.0 * rho[todo])
    fallback = ~np.isfinite(best)
    dev = np.where(fallback, d_pl, best)
    best_seg = np.where(fallback, near_seg, best_seg)
    return dev, best_seg, fallback


def _segments(p: NDArray) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    seg = np.diff(p, axis=0)
    length = np.hypot(seg[:, 0], seg[:, 1])
    mid = 0.5 * (p[:-1] + p[1:])
    normal = np.column_stack([-seg[:, 1], seg[:, 0]]) / length[:, None]
    s_mid = np.concatenate([[0.0], np.cumsum(length)])[:-1] + 0.5 * length
    return mid, normal, s_mid, length


@dataclass(frozen=True)
class _Settings:
    """The checked App. A settings of :func:`normal_path_deviation`."""

    min_segment: float
    max_segment: float
    max_search: float
    far_hit_fallback_ratio: float | None
    comparison: str
    intersections: bool
    wheel_track: float

    @classmethod
    def checked(cls, **given: Any) -> _Settings:
        out = cls(
            min_segment=MIN_SEGMENT.check(given["min_segment"]),
            max_segment=MAX_SEGMENT.check(given["max_segment"]),
            max_search=MAX_SEARCH.check(given["max_search"]),
            far_hit_fallback_ratio=FAR_HIT_FALLBACK_RATIO.check(given["far_hit_fallback_ratio"]),
            comparison=COMPARISON.check(given["comparison"]),
            intersections=bool(given["intersections"]),
            wheel_track=WHEEL_TRACK.check(given["wheel_track"], "wheel_track"),
        )
        if out.max_segment < out.min_segment:
            raise InvalidParameterError(
                "max_segment", out.max_segment, f">= min_segment ({out.min_segment:g} m)", "m"
            )
        return out


def _comparison_range(
    q1: NDArray, q2: NDArray, st: _Settings
) -> tuple[int, int, tuple[NDArray, ...], tuple[NDArray, ...]]:
    """App. A step 5: the first compared follower segment and the last compared leader segment."""
    seg1, seg2 = _segments(q1), _segments(q2)
    (mid1, nrm1, s1, _), (mid2, nrm2, s2, _) = seg1, seg2
    c2, d2, c1, d1 = q2[:-1], q2[1:], q1[:-1], q1[1:]
    if st.comparison == "ordered":
        half2 = np.flatnonzero(s2 <= 0.5 * s2[-1] + 1e-12)
        half2 = half2 if len(half2) else np.arange(len(mid2))
        half1 = np.flatnonzero(s1 >= 0.5 * s1[-1] - 1e-12)
        half1 = half1 if len(half1) else np.arange(len(mid1))
    else:
        half2 = np.arange(len(mid2))
        half1 = np.arange(len(mid1))
    _, js, _ = _normal_deviation(
        mid1[:1], nrm1[:1], c2[half2], d2[half2], st.max_search, st.far_hit_fallback_ratio
    )
    _, ie, _ = _normal_deviation(
        mid2[-1:], nrm2[-1:], c1[half1], d1[half1], st.max_search, st.far_hit_fallback_ratio
    )
    return int(half2[js[0]]), int(half1[ie[0]]), seg1, seg2


def _deviation(
    leader: NDArray, robot: NDArray, st: _Settings, leader_nodes: NDArray | None = None
) -> PathDeviation:
    """The deviation of one robot path (the leader re-segmented once, if given)."""
    q1 = resegment(leader, st.min_segment, st.max_segment) if leader_nodes is None else leader_nodes
    q2 = resegment(robot, st.min_segment, st.max_segment)
    if st.intersections:
        q1, q2, _ = _insert_intersections(q1, q2, st.max_segment)
    j_start, i_end, (mid1, nrm1, s1, _), _ = _comparison_range(q1, q2, st)
    c2, d2 = q2[:-1], q2[1:]
    sel1 = np.arange(0, i_end + 1)
    if len(sel1) == 0 or j_start >= len(q2) - 1:
        sel1 = np.zeros(0, dtype=int)
    status, warns = DeviationStatus.OK, []
    if len(sel1):
        dev, _, fb = _normal_deviation(
            mid1[sel1],
            nrm1[sel1],
            c2[j_start:],
            d2[j_start:],
            st.max_search,
            st.far_hit_fallback_ratio,
        )
    else:
        dev, fb = np.zeros(0), np.zeros(0, bool)
        status = DeviationStatus.EMPTY
        warns.append(
            "the two paths have no comparison range (App. A.6: the paths are too dissimilar)"
        )
    if len(fb) and fb.mean() > 0.2:
        warns.append(
            f"{100 * fb.mean():.0f} % of the segments used the point-to-polyline fallback; "
            "the paths may be too dissimilar for the normal deviation (Allan 2015 App. A.6)"
        )
    if len(sel1) and len(sel1) < 0.25 * len(mid1):
        warns.append(f"only {len(sel1)} of {len(mid1)} leader segments are in the comparison range")
    return PathDeviation(
        profile=dev,
        distance=s1[sel1],
        midpoints=mid1[sel1],
        fallback=fb,
        wheel_track=st.wheel_track,
        leader_nodes=q1,
        follower_nodes=q2,
        range_start=j_start,
        range_end=i_end,
        status=status,
        warnings=tuple(warns),
    )


def normal_path_deviation(
    leader_xy: Any,
    robot_xy: Any,
    *,
    min_segment: float = MIN_SEGMENT.default,
    max_segment: float = MAX_SEGMENT.default,
    max_search: float = MAX_SEARCH.default,
    far_hit_fallback_ratio: float | None = None,
    comparison: str = COMPARISON.default,
    intersections: bool = True,
    wheel_track: float = WHEEL_TRACK.default,
) -> PathDeviation:
    """Normal path deviation of ``robot_xy`` from ``leader_xy`` (Allan 2015 App. A).

    Parameters
    ----------
    leader_xy, robot_xy
        Leader (path 1) and follower (path 2) positions in m, (N, 2) each,
        at least two points, finite. Time is ignored.
    min_segment, max_segment
        L_min and L_max of the re-segmentation in m (0.01, 0.05).
    max_search
        Longest normal searched, in m (2.0).
    far_hit_fallback_ratio
        ``None`` (default, App. A): every normal hit within ``max_search``
        counts. A number k opts in to a heuristic that is not App. A: a hit
        more than k times farther than the nearest point of the follower path
        is replaced by that point-to-polyline distance (it lowers the deviation
        where the paths cross or return on themselves; ``docs/following.md``).
    comparison
        ``"ordered"`` (default) or ``"literal"`` comparison range (see the module notes).
    intersections
        Insert the path intersections as nodes (App. A step 4).
    wheel_track
        Normalising length b in m (0.28 m).

    Returns
    -------
    PathDeviation
        ``.mean``, ``.std``, ``.max``, ``.profile`` in m; ``*_over_b`` in wheel tracks.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, np.pi, 400)
    >>> inner = np.column_stack([np.cos(t), np.sin(t)])
    >>> d = normal_path_deviation(inner, 1.2 * inner)
    >>> round(d.mean, 4), round(d.max, 4)
    (0.2, 0.2)
    """
    p1 = _as_path("leader_xy", leader_xy)
    p2 = _as_path("robot_xy", robot_xy)
    st = _Settings.checked(
        min_segment=min_segment,
        max_segment=max_segment,
        max_search=max_search,
        comparison=comparison,
        intersections=intersections,
        wheel_track=wheel_track,
        far_hit_fallback_ratio=far_hit_fallback_ratio,
    )
    return _deviation(p1, p2, st)


def normal_path_deviations(
    leader_xy: Any, robot_paths: Any, **settings: Any
) -> list[PathDeviation]:
    """:func:`normal_path_deviation` of several follower paths from one leader path.

    The leader path is re-segmented once (the same numbers as one call per path).

    Parameters
    ----------
    leader_xy
        Leader positions in m, (N, 2).
    robot_paths
        Follower paths in m, each (N_i, 2) (e.g. a batch's ``robot_xy``).
    **settings
        The keyword arguments of :func:`normal_path_deviation`.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(0.0, 5.0, 501)
    >>> leader = np.column_stack([x, 0 * x])
    >>> devs = normal_path_deviations(leader, [leader + [0, 0.1], leader + [0, 0.2]])
    >>> [round(d.mean, 6) for d in devs]
    [0.1, 0.2]
    """
    defaults = {
        "min_segment": 0.01,
        "max_segment": 0.05,
        "max_search": 2.0,
        "far_hit_fallback_ratio": None,
        "comparison": "ordered",
        "intersections": True,
        "wheel_track": 0.28,
    }
    unknown = sorted(set(settings) - set(defaults))
    if unknown:
        raise InvalidParameterError(unknown[0], settings[unknown[0]], f"one of {sorted(defaults)}")
    st = _Settings.checked(**{**defaults, **settings})
    p1 = _as_path("leader_xy", leader_xy)
    q1 = resegment(p1, st.min_segment, st.max_segment)
    return [_deviation(p1, _as_path("robot_xy", r), st, q1) for r in robot_paths]
