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
import pedpy
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import LineString, Polygon

from designlab.errors import InvalidParameterError
from designlab.params import Param
from designlab.results import Result, Status

__all__ = [
    "FRAME_RATE",
    "MEASURE_HALF_WIDTH",
    "SPEED_FRAMES",
    "FacedCrowd",
    "FacedStatus",
    "faced_by",
    "faced_crowd",
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


def _trajectories(
    times: Array, P: Array, bounds: tuple[float, ...]
) -> tuple[pd.DataFrame, float, Array]:
    """pedpy's trajectory table of the records thinned to :data:`FRAME_RATE` (id, frame, x,
    y; rows where a pedestrian is present), its frame rate and the thinned times. Pedestrians
    never within ``bounds`` (the band's bounding box) are left out: they change neither
    measure (a pedestrian's speed is its own)."""
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
    table = pd.DataFrame(
        {"id": ped[keep], "frame": frame[keep], "x": xy[keep, 0], "y": xy[keep, 1]}
    )
    return table, 1.0 / (stride * dt) if math.isfinite(dt) else 1.0, t


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
    t = np.asarray(times, dtype=float).ravel()
    P = np.asarray(pedestrian_positions, dtype=float)
    if P.ndim != 3 or P.shape[2] != 2 or P.shape[0] != t.size:
        raise InvalidParameterError(
            "pedestrian_positions", P.shape, f"must be (T, N, 2) with T = {t.size} (the times)"
        )
    table, rate, tt = _trajectories(t, P, band.bounds)
    area = pedpy.MeasurementArea(band)
    h = _half_width(band)
    if tt.size < 2:
        empty = pd.DataFrame({"t_s": tt, "density_per_m2": np.nan, "speed_m_per_s": np.nan})
        return FacedCrowd(math.nan, math.nan, area.area, h, empty, FacedStatus.TOO_SHORT,
                          ("fewer than two frames: nothing measured",))  # fmt: skip
    if table.empty:
        return _nobody(tt, 0.0, area.area, h)
    traj = pedpy.TrajectoryData(data=table, frame_rate=rate)
    density = pedpy.compute_classic_density(traj_data=traj, measurement_area=area)
    speed = pedpy.compute_individual_speed(
        traj_data=traj, frame_step=SPEED_FRAMES,
        speed_calculation=pedpy.SpeedCalculation.BORDER_SINGLE_SIDED,
    )  # fmt: skip
    mean = pedpy.compute_mean_speed_per_frame(
        traj_data=traj, individual_speed=speed, measurement_area=area
    )
    rho, v = np.zeros(tt.size), np.zeros(tt.size)  # pedpy's frames: those with anyone in
    rho[density["frame"].to_numpy()] = density["density"].to_numpy()
    v[mean["frame"].to_numpy()] = mean["speed"].to_numpy()
    if not (rho > 0).any():
        return _nobody(tt, float(rho.mean()), area.area, h)
    frames = pd.DataFrame({"t_s": tt, "density_per_m2": rho, "speed_m_per_s": v})
    return FacedCrowd(float(rho.mean()), float(v[rho > 0].mean()), area.area, h, frames)


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
    c = result.crowd
    MEASURE_HALF_WIDTH.check(half_width)
    try:
        band = measurement_band(c.robot_start, c.robot_goal, c.geometry.area, half_width)
    except InvalidParameterError as exc:  # a path around a corner: no straight band
        frames = pd.DataFrame({"t_s": np.asarray(result.times, dtype=float)})
        return FacedCrowd(math.nan, math.nan, math.nan, math.nan, frames, FacedStatus.NO_BAND,
                          (f"no measurement band: {exc}",))  # fmt: skip
    return faced_crowd(result.times, result.pedestrian_positions, band)
