"""The crowd a robot actually met: pedpy's density and speed along its path (issue 23, item 3).

A crowd scenario is built for a nominal density (persons per m^2 of the whole walkable
area); where the robot drives, the crowd may be denser or thinner (streams bunch up, the
pedestrians slow down, the ends are emptier). :func:`faced_crowd` measures it with pedpy,
the analysis library of the Jülich pedestrian-dynamics group (the authors of JuPedSim), in
a *measurement band*: the rectangle of half width h_M along the straight line from the
robot's start to its goal (:func:`measurement_band`; h_M is cut to the line's clearance
from the walkable area's boundary, so the band lies in the walkable area and is convex, as
pedpy requires):

- the classic density (pedpy ``compute_classic_density``: pedestrians in the band / its
  area, per frame), averaged over the frames of the run, ``measured_density_per_m2``;
- the mean speed of the pedestrians in the band (pedpy ``compute_individual_speed`` over
  +-:data:`SPEED_FRAMES` frames, one-sided at a trajectory's ends, and
  ``compute_mean_speed_per_frame``), averaged over the frames with someone in the band,
  ``mean_ped_speed_m_per_s``.

The records (every pedestrian step, 100 Hz) are thinned to :data:`FRAME_RATE` frames per
second first: the measures then cost about a tenth of the run's records (a few tens of ms for
a 20 s run with 50 pedestrians).

Examples
--------
>>> import numpy as np
>>> t = np.arange(11) * 0.1                       # one pedestrian at 1.2 m/s along y = 0.5
>>> P = np.stack([1.0 + 1.2 * t, np.full(11, 0.5)], axis=1)[:, None, :]
>>> f = faced_crowd(t, P, measurement_band((0.0, 0.5), (4.0, 0.5), half_width=1.0))
>>> round(f.measured_density_per_m2, 6), round(f.mean_ped_speed_m_per_s, 6)
(0.125, 1.2)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import LineString, Polygon

from designlab.errors import InvalidParameterError
from designlab.navigation.crowds.extra import pedpy
from designlab.params import Param
from designlab.results import Result, Status

__all__ = [
    "FRAME_RATE",
    "MEASURE_HALF_WIDTH",
    "SPEED_FRAMES",
    "FacedCrowd",
    "FacedStatus",
    "faced_by",
    "faced_by_runs",
    "faced_crowd",
    "faced_crowds",
    "measurement_band",
]

Array = NDArray[np.float64]

#: Frames per second the records are thinned to before pedpy measures them, Hz.
FRAME_RATE = 10.0
#: Half window of pedpy's individual speed, in thinned frames (+-0.5 s at 10 Hz).
SPEED_FRAMES = 5
#: Half width of the measurement band along the robot's straight path (m): 1 m takes in the
#: pedestrians the robot meets head-on and those it passes at arm's length.
MEASURE_HALF_WIDTH = Param("h_M", "m", "half width of the measurement band along the robot's "
                           "straight path (cut to the path's clearance from the walls)",
                           gt=0, le=50, default=1.0, name="half_width")  # fmt: skip

#: Rows (pedestrian-frames) of the runs measured in one pedpy call at most. Below, one call
#: costs about what one run's does (pandas' fixed cost, about 20 ms); above, a call costs
#: more per row than calls apart (2026-12-05, 2-core VM, benchmarks/crowds.py: a 20 s run
#: with 10 pedestrians gives 2,000 rows, 10-16 of them together cost 5-7 ms each against
#: 21-24 ms alone; with 50 it gives 9,000 rows, 3 together cost more than alone).
_BATCH_ROWS = 20_000


class FacedStatus(Status):
    """Status of a :class:`FacedCrowd`.

    ``OK``: measured; ``NO_PEDESTRIANS``: nobody was ever in the band (density 0, speed NaN);
    ``TOO_SHORT``: fewer than two frames after thinning (both NaN); ``NO_BAND``: the straight
    path from the robot's start to its goal leaves the walkable area or runs along its
    boundary, so there is no band to measure in (both NaN; :func:`faced_by`).
    """

    OK = "ok"
    NO_PEDESTRIANS = "no_pedestrians"
    TOO_SHORT = "too_short"
    NO_BAND = "no_band"


@dataclass(frozen=True)
class FacedCrowd(Result):
    """The density and speed of the pedestrians in the measurement band over a run.

    Attributes
    ----------
    measured_density_per_m2
        pedpy's classic density in the band, averaged over the frames, persons/m^2.
    mean_ped_speed_m_per_s
        Mean speed of the pedestrians in the band, averaged over the frames with someone in
        it, m/s (NaN when nobody was).
    band_area_m2, half_width_m
        The band's area and half width (after the cut to the path's clearance).
    frames
        Per thinned frame: ``t_s``, ``density_per_m2``, ``speed_m_per_s`` (0 when empty).
    status, warnings
        :class:`FacedStatus` and what a user should know.
    """

    measured_density_per_m2: float
    mean_ped_speed_m_per_s: float
    band_area_m2: float
    half_width_m: float
    frames: pd.DataFrame = field(repr=False)
    status: str = FacedStatus.OK
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """One row: the two measures, the band's area and half width."""
        return pd.DataFrame([{
            "measured_density_per_m2": self.measured_density_per_m2,
            "mean_ped_speed_m_per_s": self.mean_ped_speed_m_per_s,
            "band_area_m2": self.band_area_m2, "band_half_width_m": self.half_width_m,
            "status": str(self.status),
        }])  # fmt: skip


def measurement_band(
    start: Sequence[float], goal: Sequence[float], area: Any = None,
    half_width: float = MEASURE_HALF_WIDTH.default,
) -> Polygon:  # fmt: skip
    """The rectangle of half width ``half_width`` along the segment start -> goal (flat ends).

    Parameters
    ----------
    start, goal
        The robot's start and goal, m.
    area
        The walkable area (shapely): the half width is cut to the segment's distance from its
        boundary, so the band lies inside it; ``None``: no cut.
    half_width
        h_M in m (:data:`MEASURE_HALF_WIDTH`).

    Returns
    -------
    shapely.Polygon

    Examples
    --------
    >>> from shapely.geometry import box
    >>> measurement_band((1.5, 2.0), (28.5, 2.0), box(0, 0, 30, 4)).bounds
    (1.5, 1.0, 28.5, 3.0)
    >>> measurement_band((1.5, 2.0), (28.5, 2.0), box(0, 0, 30, 4), half_width=3.0).bounds
    (1.5, 0.5, 28.5, 3.5)
    """
    h = MEASURE_HALF_WIDTH.check(half_width)
    (x0, y0), (x1, y1) = (float(v) for v in start), (float(v) for v in goal)
    length = math.hypot(x1 - x0, y1 - y0)
    if not length > 0:
        raise InvalidParameterError("goal", (x1, y1), "must differ from the start", "m")
    if area is not None:
        segment = LineString([(x0, y0), (x1, y1)])
        if not area.covers(segment):
            raise InvalidParameterError(
                "start, goal", ((x0, y0), (x1, y1)), "must be joined by a segment in the area", "m"
            )
        clear = float(area.boundary.distance(segment))
        if not clear > 0:
            raise InvalidParameterError(
                "start, goal", ((x0, y0), (x1, y1)), "must stay off the area's boundary", "m"
            )
        h = min(h, clear)
    nx, ny = -(y1 - y0) / length * h, (x1 - x0) / length * h
    return Polygon([(x0 + nx, y0 + ny), (x0 - nx, y0 - ny), (x1 - nx, y1 - ny), (x1 + nx, y1 + ny)])


@dataclass(frozen=True)
class _Thinned:
    """One run's records thinned to :data:`FRAME_RATE` for pedpy: the rows (pedestrian,
    frame, x, y) where a pedestrian is present, its frame rate and the thinned times."""

    ped: NDArray[np.int64]
    frame: NDArray[np.int64]
    xy: Array
    rate: float
    t: Array


def _thinned(times: Array, P: Array, bounds: tuple[float, ...]) -> _Thinned:
    """The records thinned to :data:`FRAME_RATE`. Pedestrians never within ``bounds`` (the
    band's bounding box) are left out: they change neither measure (a pedestrian's speed is
    its own)."""
    dt = float(np.median(np.diff(times))) if times.size > 1 else math.inf
    stride = max(1, round(1.0 / (FRAME_RATE * dt))) if math.isfinite(dt) and dt > 0 else 1
    t, Q = times[::stride], P[::stride]
    x0, y0, x1, y1 = bounds
    with np.errstate(invalid="ignore"):
        near = (Q[..., 0] >= x0) & (Q[..., 0] <= x1) & (Q[..., 1] >= y0) & (Q[..., 1] <= y1)
    Q = Q[:, near.any(axis=0)]
    T, N = Q.shape[:2]
    frame, ped = np.repeat(np.arange(T), N), np.tile(np.arange(N), T)
    xy = Q.reshape(T * N, 2)
    keep = np.isfinite(xy).all(axis=1)
    rate = 1.0 / (stride * dt) if math.isfinite(dt) else 1.0
    return _Thinned(ped[keep], frame[keep], xy[keep], rate, t)


def _check_records(times: ArrayLike, pedestrian_positions: ArrayLike) -> tuple[Array, Array]:
    """``times`` as ``(T,)`` and the positions as ``(T, N, 2)`` floats, or a clear error."""
    t = np.asarray(times, dtype=float).ravel()
    P = np.asarray(pedestrian_positions, dtype=float)
    if P.ndim != 3 or P.shape[2] != 2 or P.shape[0] != t.size:
        raise InvalidParameterError(
            "pedestrian_positions", P.shape, f"must be (T, N, 2) with T = {t.size} (the times)"
        )
    return t, P


def faced_crowd(times: ArrayLike, pedestrian_positions: ArrayLike, band: Polygon) -> FacedCrowd:
    """pedpy's classic density and mean speed of the pedestrians in ``band`` over a run.

    Parameters
    ----------
    times
        ``(T,)`` times of the records, s (uniform).
    pedestrian_positions
        ``(T, N, 2)`` positions, m (NaN where a pedestrian is not in the simulation).
    band
        The measurement area (convex; :func:`measurement_band`).

    Returns
    -------
    FacedCrowd
        See the module's text for the two measures.
    """
    return faced_crowds([(times, pedestrian_positions)], band)[0]


def faced_crowds(runs: Sequence[tuple[ArrayLike, ArrayLike]], band: Polygon) -> list[FacedCrowd]:
    """:func:`faced_crowd` of several runs in one band, with one call of each pedpy method.

    pedpy's per-call cost (its pandas tables, about 20 ms) is paid once for all the runs:
    their pedestrians get distinct ids and their frames distinct numbers (run k's after run
    k-1's), so the measures of each run are those :func:`faced_crowd` gives it alone.

    Parameters
    ----------
    runs
        ``(times, pedestrian_positions)`` of each run, as in :func:`faced_crowd`.
    band
        The measurement area shared by the runs (convex; :func:`measurement_band`).

    Returns
    -------
    list of FacedCrowd
        One per run, in order.

    Examples
    --------
    >>> t = np.arange(11) * 0.1
    >>> P = np.stack([1.0 + 1.2 * t, np.full(11, 0.5)], axis=1)[:, None, :]
    >>> band = measurement_band((0.0, 0.5), (4.0, 0.5), half_width=1.0)
    >>> [round(f.mean_ped_speed_m_per_s, 6) for f in faced_crowds([(t, P), (t, 0.5 * P)], band)]
    [1.2, 0.6]
    """
    thin = [_thinned(*_check_records(t, P), band.bounds) for t, P in runs]
    area, h = pedpy().MeasurementArea(band), _half_width(band)
    out: list[FacedCrowd | None] = [None] * len(thin)
    by_rate: dict[float, list[int]] = {}
    for k, th in enumerate(thin):
        if th.t.size < 2:
            empty = pd.DataFrame({"t_s": th.t, "density_per_m2": np.nan, "speed_m_per_s": np.nan})
            out[k] = FacedCrowd(math.nan, math.nan, area.area, h, empty, FacedStatus.TOO_SHORT,
                                ("fewer than two frames: nothing measured",))  # fmt: skip
        elif th.ped.size == 0:
            out[k] = _nobody(th.t, 0.0, area.area, h)
        else:
            by_rate.setdefault(th.rate, []).append(k)
    for rate, ks in by_rate.items():  # runs of one frame rate share the pedpy calls
        for part in _parts([thin[k].ped.size for k in ks]):
            batch = [ks[i] for i in part]
            for k, f in zip(batch, _measured([thin[k] for k in batch], rate, area, h), strict=True):
                out[k] = f
    return [f for f in out if f is not None]


def _parts(rows: list[int]) -> list[list[int]]:
    """Consecutive runs, as index lists, of at most :data:`_BATCH_ROWS` rows together (a run
    with more is a part of its own)."""
    parts: list[list[int]] = [[]]
    total = 0
    for i, r in enumerate(rows):
        if parts[-1] and total + r > _BATCH_ROWS:
            parts.append([])
            total = 0
        parts[-1].append(i)
        total += r
    return parts


def _measured(thin: list[_Thinned], rate: float, area: Any, h: float) -> list[FacedCrowd]:
    """pedpy's measures of the runs ``thin`` (each with somebody), in one table."""
    frames = np.cumsum([0] + [th.t.size for th in thin])  # first frame of each run
    ids = np.cumsum([0] + [int(th.ped.max()) + 1 for th in thin])
    xy = np.concatenate([th.xy for th in thin])
    table = pd.DataFrame({
        "id": np.concatenate([th.ped + i for th, i in zip(thin, ids, strict=False)]),
        "frame": np.concatenate([th.frame + f for th, f in zip(thin, frames, strict=False)]),
        "x": xy[:, 0], "y": xy[:, 1],
    })  # fmt: skip
    ped = pedpy()
    traj = ped.TrajectoryData(data=table, frame_rate=rate)
    density = ped.compute_classic_density(traj_data=traj, measurement_area=area)
    speed = ped.compute_individual_speed(
        traj_data=traj, frame_step=SPEED_FRAMES,
        speed_calculation=ped.SpeedCalculation.BORDER_SINGLE_SIDED,
    )  # fmt: skip
    mean = ped.compute_mean_speed_per_frame(
        traj_data=traj, individual_speed=speed, measurement_area=area
    )
    rho, v = np.zeros(frames[-1]), np.zeros(frames[-1])  # pedpy's frames: those with anyone in
    rho[density["frame"].to_numpy()] = density["density"].to_numpy()
    v[mean["frame"].to_numpy()] = mean["speed"].to_numpy()
    out = []
    for k, th in enumerate(thin):
        r, s = rho[frames[k] : frames[k + 1]], v[frames[k] : frames[k + 1]]
        if not (r > 0).any():
            out.append(_nobody(th.t, float(r.mean()), area.area, h))
            continue
        series = pd.DataFrame({"t_s": th.t, "density_per_m2": r, "speed_m_per_s": s})
        out.append(FacedCrowd(float(r.mean()), float(s[r > 0].mean()), area.area, h, series))
    return out


def _nobody(t: Array, rho: float, area: float, h: float) -> FacedCrowd:
    """Nobody in the band at any frame."""
    frames = pd.DataFrame({"t_s": t, "density_per_m2": 0.0, "speed_m_per_s": 0.0})
    return FacedCrowd(rho, math.nan, area, h, frames, FacedStatus.NO_PEDESTRIANS,
                      ("no pedestrian in the band",))  # fmt: skip


def _half_width(band: Polygon) -> float:
    """Half the band's width (the shorter side of its rectangle)."""
    xy = np.asarray(band.exterior.coords)[:3]
    return 0.5 * float(min(np.hypot(*(xy[1] - xy[0])), np.hypot(*(xy[2] - xy[1]))))


def faced_by(result: Any, half_width: float = MEASURE_HALF_WIDTH.default) -> FacedCrowd:
    """:func:`faced_crowd` of a crowd run, in the band along its robot's straight path.

    Parameters
    ----------
    result
        A :class:`~designlab.navigation.crowds.results.CrowdResult` (its crowd's start, goal
        and walkable area, its times and pedestrian positions up to the arrival).
    half_width
        h_M in m (:data:`MEASURE_HALF_WIDTH`; cut to the path's clearance).

    Returns
    -------
    FacedCrowd

    Examples
    --------
    >>> import designlab as dl
    >>> nav = dl.navigation
    >>> c = nav.crowd("corridor_counterflow", density=0.5, length=10.0, seed=1, horizon=2.0)
    >>> f = faced_by(nav.simulate(c, nav.VFFGains(4.3, 0.68, 20.3, 240.7)))
    >>> f.band_area_m2, 0.1 < f.measured_density_per_m2 < 1.5, 0.3 < f.mean_ped_speed_m_per_s < 2
    (14.0, True, True)
    """
    from designlab.navigation.crowds.results import CrowdResult  # results import this module

    if not isinstance(result, CrowdResult):
        raise InvalidParameterError("result", result, "must be a CrowdResult (a crowd run)")
    c = result.crowd
    MEASURE_HALF_WIDTH.check(half_width)
    try:
        band = measurement_band(c.robot_start, c.robot_goal, c.geometry.area, half_width)
    except InvalidParameterError as exc:  # a path around a corner: no straight band
        frames = pd.DataFrame({"t_s": np.asarray(result.times, dtype=float)})
        return FacedCrowd(math.nan, math.nan, math.nan, math.nan, frames, FacedStatus.NO_BAND,
                          (f"no measurement band: {exc}",))  # fmt: skip
    return faced_crowd(result.times, result.pedestrian_positions, band)


def faced_by_runs(
    results: Sequence[Any], half_width: float = MEASURE_HALF_WIDTH.default
) -> list[FacedCrowd]:
    """:func:`faced_by` of several crowd runs, runs in one band measured in one pedpy call.

    The runs whose robots share a start, goal and walkable area (a study's seeds and methods
    in one scenario) share their band; :func:`faced_crowds` measures them together, which
    pays pedpy's per-call cost once. The measures are those :func:`faced_by` gives each run.

    Parameters
    ----------
    results
        :class:`~designlab.navigation.crowds.results.CrowdResult` objects.
    half_width
        h_M in m (:data:`MEASURE_HALF_WIDTH`; cut to each path's clearance).

    Returns
    -------
    list of FacedCrowd
        One per run, in order.
    """
    MEASURE_HALF_WIDTH.check(half_width)
    out: list[FacedCrowd | None] = [None] * len(results)
    groups: dict[bytes, tuple[Polygon, list[int]]] = {}
    for k, result in enumerate(results):
        c = result.crowd
        try:
            band = measurement_band(c.robot_start, c.robot_goal, c.geometry.area, half_width)
        except InvalidParameterError:
            out[k] = faced_by(result, half_width)  # no straight band: NO_BAND
            continue
        groups.setdefault(band.wkb, (band, []))[1].append(k)
    for band, ks in groups.values():
        runs = [(results[k].times, results[k].pedestrian_positions) for k in ks]
        for k, f in zip(ks, faced_crowds(runs, band), strict=True):
            out[k] = f
    return [f for f in out if f is not None]


def voronoi_density(
    times: ArrayLike, pedestrian_positions: ArrayLike, band: Polygon, walkable: Polygon,
    frame_rate: float = 1.0,
) -> float:  # fmt: skip
    """pedpy's Voronoi density in ``band``, averaged over the frames (persons/m^2).

    Each pedestrian's Voronoi cell in the walkable area (pedpy
    ``compute_individual_voronoi_polygons``, no cut-off) counts with the share of it inside
    the band (``compute_voronoi_density``: sum of |cell ^ band| / |cell| over |band|). The
    records are thinned to ``frame_rate`` frames per second first (the cells cost far more
    than the classic count).

    Parameters
    ----------
    times
        ``(T,)`` s.
    pedestrian_positions
        ``(T, N, 2)`` m, NaN where absent.
    band
        The measurement area (convex, in the walkable area).
    walkable
        The walkable area.
    frame_rate
        Frames per second kept.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> P = np.array([[[1.0, 1.0], [3.5, 1.0]]] * 3)     # cells split at x = 2.25
    >>> round(voronoi_density([0.0, 1.0, 2.0], P, box(0, 0, 2, 2), box(0, 0, 4, 2)), 9)
    0.222222222
    """
    t, P = _check_records(times, pedestrian_positions)
    dt = float(np.median(np.diff(t))) if t.size > 1 else 1.0
    stride = max(1, round(1.0 / (frame_rate * dt)))
    Q = P[::stride]
    T, N = Q.shape[:2]
    frame, ped_id = np.repeat(np.arange(T), N), np.tile(np.arange(N), T)
    xy = Q.reshape(T * N, 2)
    keep = np.isfinite(xy).all(axis=1)
    if not keep.any():
        return 0.0
    ped = pedpy()
    table = pd.DataFrame({"id": ped_id[keep], "frame": frame[keep],
                          "x": xy[keep, 0], "y": xy[keep, 1]})  # fmt: skip
    traj = ped.TrajectoryData(data=table, frame_rate=1.0 / (stride * dt))
    cells = ped.compute_individual_voronoi_polygons(
        traj_data=traj, walkable_area=ped.WalkableArea(walkable)
    )
    rho, _ = ped.compute_voronoi_density(
        individual_voronoi_data=cells, measurement_area=ped.MeasurementArea(band)
    )
    per = np.zeros(T)
    per[rho["frame"].to_numpy()] = rho["density"].to_numpy()
    return float(per.mean())


__all__ += ["voronoi_density"]
