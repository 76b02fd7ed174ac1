"""Contact speeds from navigation runs: the closing-speed input of the injury model.

For every navigation run and every disc obstacle (people are discs; rectangles are
furniture) the encounter is the robot's closest approach to the obstacle before
arrival, or its first contact when the surfaces touch (surface distance <= 0). At
that instant the relative velocity ``v_rel = v_robot - v_obstacle`` gives

* ``relative_speed`` = |v_rel|: the closing speed of a contact taken head-on, the
  worst case of Zeng 2011, Sec. 3.2 (the head velocity normal to the contact surface,
  gamma_c = 0), and the default sample of the injury model;
* ``normal_speed`` = -d(d)/dt, the component along the line of centres (zero at a
  closest approach without contact; the actual normal closing speed at a contact);
* ``approach_speed``: the largest normal closing speed while the robot was inside the
  obstacle's active region (d <= r2) up to the encounter: how fast the robot closed
  in on the obstacle it was avoiding (0 if it never entered the region);
* ``angle``: the angle between v_rel and the line from the robot to the obstacle
  (0: head-on), and ``distance`` / ``surface_distance`` at that instant.

:class:`ContactSpeeds` holds them and is itself a distribution of the closing speed:
``rvs`` draws from the empirical distribution (bootstrap of the samples), ``cdf`` /
``sf`` / ``ppf`` / ``mean`` / ``support`` are those of the samples, and
``np.asarray(speeds)`` is the samples, so it can be passed as the ``closing_speed`` of
:func:`designlab.codesign.injury_probability`. :meth:`ContactSpeeds.histogram` gives
a smooth :class:`scipy.stats.rv_histogram` instead.

What it does not cover: which body part is struck (the head model takes every
contact as a head contact), contacts during the approach before the closest point
(a closer pass would have been faster or slower), and obstacles other than discs.

Examples
--------
>>> import designlab as dl
>>> nav, cd = dl.navigation, dl.codesign
>>> human = nav.Disc("human", 0.3, r2=0.8, r3=0.6,
...                  motion=nav.ConstantVelocity((-2.0, 3.6), (0.3, 0.0)))
>>> sc = nav.Scenario("line", start=(6.0, 0.6), goal=(0.0, 0.6), obstacles=(human,))
>>> speeds = cd.contact_speeds(nav.simulate(sc, nav.EXPERIMENT_GAINS))
>>> round(float(speeds.distance[0]), 3), round(float(speeds.samples[0]), 3)
(3.0, 1.0)
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
import scipy.stats as st
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError
from designlab.navigation import CrowdResult, NavigationResult, Scenario, VFFGains, simulate
from designlab.navigation.scenarios import Disc
from designlab.progress import Progress, ProgressHook, report
from designlab.results import Result, Status

__all__ = [
    "ContactSpeeds",
    "ContactStatus",
    "contact_speeds",
    "navigation_contacts",
    "pedestrian_velocity",
]

Array = NDArray[np.float64]

#: The measures a :class:`ContactSpeeds` can sample (``measure=``).
MEASURES = ("relative", "normal", "approach")


class ContactStatus(Status):
    """Status of a :class:`ContactSpeeds`.

    ``OK``: at least one encounter; ``EMPTY``: the runs had no disc obstacle to meet.
    """

    OK = "ok"
    EMPTY = "empty"


@dataclass(frozen=True)
class ContactSpeeds(Result):
    """Encounters of navigation runs with their obstacles, and the closing-speed distribution.

    One entry per (run, disc obstacle). Arrays are aligned.

    Attributes
    ----------
    scenario, obstacle
        Names of the run's scenario and of the obstacle met.
    contact
        Whether the surfaces touched (the encounter is then the first contact).
    time
        Time of the closest approach or first contact (s).
    distance, surface_distance
        Centre distance and surface distance (centre distance minus both radii) there (m).
    relative_speed
        |v_robot - v_obstacle| there (m/s): the head-on closing speed.
    normal_speed
        Closing speed along the line of centres (m/s; > 0 approaching).
    approach_speed
        Largest normal closing speed inside the active region (d <= r2) up to the
        encounter (m/s; 0 if the robot never entered it).
    angle
        Angle between the relative velocity and the robot-to-obstacle line (rad; 0 head-on).
    robot_speed, obstacle_speed
        |v_robot| and |v_obstacle| there (m/s).
    measure
        ``"relative"`` (default, the worst case of Sec. 3.2), ``"normal"`` or
        ``"approach"``: which speed :attr:`samples` holds.
    status, warnings
        See :class:`ContactStatus`.
    """

    scenario: tuple[str, ...]
    obstacle: tuple[str, ...]
    contact: NDArray[np.bool_] = field(repr=False)
    time: Array = field(repr=False)
    distance: Array = field(repr=False)
    surface_distance: Array = field(repr=False)
    relative_speed: Array = field(repr=False)
    normal_speed: Array = field(repr=False)
    approach_speed: Array = field(repr=False)
    angle: Array = field(repr=False)
    robot_speed: Array = field(repr=False)
    obstacle_speed: Array = field(repr=False)
    measure: str = "relative"
    status: str = ContactStatus.OK
    warnings: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.measure not in MEASURES:
            raise InvalidParameterError("measure", self.measure, f"must be one of {MEASURES}")

    @property
    def samples(self) -> Array:
        """The closing-speed samples (m/s) of :attr:`measure`, clipped at 0."""
        raw = {
            "relative": self.relative_speed,
            "normal": self.normal_speed,
            "approach": self.approach_speed,
        }[self.measure]
        return np.clip(np.asarray(raw, dtype=float), 0.0, None)

    @property
    def n_contacts(self) -> int:
        """How many encounters were contacts."""
        return int(np.count_nonzero(self.contact))

    def __len__(self) -> int:
        return len(self.scenario)

    def __array__(self, dtype: Any = None, copy: Any = None) -> Array:
        return np.asarray(self.samples, dtype=dtype)

    # --- the distribution of the closing speed (empirical, scipy-like) -----------
    def _nonempty(self) -> Array:
        s = self.samples
        if s.size == 0:
            raise InvalidParameterError(
                "closing_speed", "ContactSpeeds", "has no encounter to sample (status 'empty')"
            )
        return s

    def rvs(self, size: Any = None, random_state: Any = None) -> Any:
        """Draws from the empirical distribution of :attr:`samples` (with replacement)."""
        rng = np.random.default_rng(random_state)
        return rng.choice(self._nonempty(), size=size, replace=True)

    def cdf(self, x: ArrayLike) -> Any:
        """Share of samples <= x."""
        s = np.sort(self._nonempty())
        return np.searchsorted(s, np.asarray(x, dtype=float), side="right") / s.size

    def sf(self, x: ArrayLike) -> Any:
        """Share of samples > x."""
        return 1.0 - self.cdf(x)

    def ppf(self, q: ArrayLike) -> Any:
        """Quantiles of the samples (the inverted empirical CDF)."""
        return np.quantile(self._nonempty(), q, method="inverted_cdf")

    def mean(self) -> float:
        """Mean closing speed (m/s)."""
        return float(self._nonempty().mean())

    def std(self) -> float:
        """Standard deviation of the closing speed (m/s)."""
        return float(self._nonempty().std())

    def support(self) -> tuple[float, float]:
        """(smallest, largest) sample (m/s)."""
        s = self._nonempty()
        return float(s.min()), float(s.max())

    def histogram(self, bins: int | str = "auto") -> Any:
        """A smooth continuous distribution of the samples (:class:`scipy.stats.rv_histogram`).

        Parameters
        ----------
        bins
            Passed to :func:`numpy.histogram`.
        """
        s = self._nonempty()
        if np.ptp(s) == 0.0:
            s = np.concatenate([s, s + 1e-6])
        return st.rv_histogram(np.histogram(s, bins=bins), density=False)

    def to_frame(self) -> pd.DataFrame:
        """One row per encounter, with unit-carrying column names."""
        return pd.DataFrame(
            {
                "scenario": list(self.scenario),
                "obstacle": list(self.obstacle),
                "contact": np.asarray(self.contact, dtype=bool),
                "t_s": self.time,
                "d_m": self.distance,
                "d_surface_m": self.surface_distance,
                "v_rel_m_per_s": self.relative_speed,
                "v_normal_m_per_s": self.normal_speed,
                "v_approach_m_per_s": self.approach_speed,
                "angle_rad": self.angle,
                "v_robot_m_per_s": self.robot_speed,
                "v_obstacle_m_per_s": self.obstacle_speed,
            }
        )


def _encounter_at(
    rel_p: Array, rel_v: Array, touch: float, r2: float
) -> tuple[int, bool, float, float, float]:
    """Index of the first contact (else the closest approach) of a relative track, whether it
    is a contact, and the relative, normal and approach speeds there."""
    d = np.hypot(rel_p[:, 0], rel_p[:, 1])
    hits = np.flatnonzero(d - touch <= 0.0)
    i = int(hits[0]) if hits.size else int(np.argmin(d))
    speed = float(np.hypot(*rel_v[i]))
    normal = -float(rel_p[i] @ rel_v[i]) / d[i] if d[i] > 0 else speed
    closing = -np.einsum("ij,ij->i", rel_p[: i + 1], rel_v[: i + 1]) / np.maximum(d[: i + 1], 1e-12)
    inside = d[: i + 1] <= r2
    approach = float(max(0.0, closing[inside].max())) if inside.any() else 0.0
    return i, bool(hits.size), speed, normal, approach


def _row(
    names: tuple[str, str], t: Array, p_r: Array, v_r: Array, p_o: Array, v_o: Array,
    touch: float, r2: float,
) -> dict[str, Any]:  # fmt: skip
    """One encounter row from aligned robot and obstacle tracks."""
    rel_p, rel_v = p_r - p_o, v_r - v_o
    i, contact, speed, normal, approach = _encounter_at(rel_p, rel_v, touch, r2)
    d = float(np.hypot(*rel_p[i]))
    angle = math.acos(min(1.0, max(-1.0, normal / speed))) if speed > 0 else 0.0
    return {
        "scenario": names[0],
        "obstacle": names[1],
        "contact": contact,
        "time": float(t[i]),
        "distance": d,
        "surface_distance": d - touch,
        "relative_speed": speed,
        "normal_speed": normal,
        "approach_speed": approach,
        "angle": angle,
        "robot_speed": float(np.hypot(*v_r[i])),
        "obstacle_speed": float(np.hypot(*v_o[i])),
    }


def _encounter(run: NavigationResult, obstacle: Disc) -> dict[str, Any]:
    """The closest approach (or first contact) of ``run`` with one disc obstacle."""
    t = np.asarray(run.t, dtype=float)
    end = np.searchsorted(t, run.arrival_time, side="right") if run.arrived else t.size
    end = max(int(end), 1)
    t = t[:end]
    p_o, v_o, _ = obstacle.state(t)
    touch = obstacle.collision_distance(run.scenario.robot.radius)
    names = (run.scenario.name, obstacle.name)
    return _row(names, t, run.position[:end], run.velocity[:end], p_o, v_o, touch, obstacle.r2)


def pedestrian_velocity(times: Array, positions: Array) -> Array:
    """Velocities ``(T, 2)`` of one pedestrian from its positions ``(T, 2)`` (NaN when absent).

    Second-order differences (:func:`numpy.gradient`, central inside, one-sided at the
    ends) over each stretch the pedestrian is present: exact for straight walking at
    constant speed, whatever the spacing of the records. NaN where absent, and 0 for a
    stretch of a single record.

    Parameters
    ----------
    times
        ``(T,)`` record times (s).
    positions
        ``(T, 2)`` positions (m), NaN where the pedestrian is absent.

    Returns
    -------
    numpy.ndarray

    Examples
    --------
    >>> import numpy as np
    >>> t = np.array([0.0, 0.1, 0.3, 0.4])
    >>> p = np.c_[1.0 + 1.2 * t, 2.0 - 0.5 * t]
    >>> pedestrian_velocity(t, p).round(12).tolist()[2]
    [1.2, -0.5]
    """
    v = np.full_like(positions, np.nan)
    idx = np.flatnonzero(np.isfinite(positions).all(axis=1))
    for part in np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1):
        if part.size == 1:
            v[part] = 0.0
        elif part.size > 1:
            edge = 2 if part.size > 2 else 1
            v[part] = np.gradient(positions[part], times[part], axis=0, edge_order=edge)
    return v


def _crowd_encounters(run: CrowdResult) -> list[dict[str, Any]]:
    """The closest approach (or first contact) of a crowd run with each pedestrian present
    before arrival (records at every pedestrian step)."""
    t = np.asarray(run.times, dtype=float)
    end = np.searchsorted(t, run.arrival_time, side="right") if run.arrived else t.size
    end = max(int(end), 1)
    c = run.crowd
    r2, _ = c.pedestrian_regions()
    touch = c.robot.radius + c.pedestrian_radius
    rows = []
    for n, pid in enumerate(np.asarray(run.pedestrian_ids)):
        P = np.asarray(run.pedestrian_positions[:, n], dtype=float)
        V = pedestrian_velocity(t, P)[:end]
        present = np.isfinite(P[:end]).all(axis=1)
        if not present.any():
            continue
        names = (f"crowd {c.layout} seed {c.seed}", f"pedestrian {int(pid)}")
        tr, pr, vr = (
            t[:end][present],
            run.robot_positions[:end][present],
            run.robot_velocities[:end][present],
        )
        rows.append(_row(names, tr, pr, vr, P[:end][present], V[present], touch, r2))
    return rows


def _check_runs(runs: Any) -> list[NavigationResult | CrowdResult]:
    if isinstance(runs, NavigationResult | CrowdResult):
        return [runs]
    if isinstance(runs, str | bytes) or not isinstance(runs, Iterable):
        raise InvalidParameterError("runs", runs, "must be NavigationResult or CrowdResult objects")
    out = list(runs)
    for r in out:
        if not isinstance(r, NavigationResult | CrowdResult):
            raise InvalidParameterError(
                "runs", r, "must contain NavigationResult or CrowdResult objects"
            )
    return out


def _run_encounters(
    run: NavigationResult | CrowdResult, keep: frozenset[str] | None
) -> list[dict[str, Any]]:
    """The encounters of one run with its kept disc obstacles or pedestrians."""
    if isinstance(run, CrowdResult):
        rows = _crowd_encounters(run)
        return [r for r in rows if keep is None or r["obstacle"] in keep]
    return [
        _encounter(run, o)
        for o in run.scenario.obstacles
        if isinstance(o, Disc) and (keep is None or o.name in keep)
    ]


def _check_names(obstacles: Any) -> frozenset[str] | None:
    if obstacles is None:
        return None
    if isinstance(obstacles, str):
        obstacles = (obstacles,)
    names = frozenset(obstacles)
    if not names or not all(isinstance(n, str) for n in names):
        raise InvalidParameterError("obstacles", obstacles, "must be obstacle names or None")
    return names


def contact_speeds(
    runs: NavigationResult | Iterable[NavigationResult],
    *,
    obstacles: str | Sequence[str] | None = None,
    measure: str = "relative",
) -> ContactSpeeds:
    """The encounters of navigation runs with their disc obstacles.

    Parameters
    ----------
    runs
        One or more results of :func:`designlab.navigation.simulate`.
    obstacles
        Names of the obstacles to keep (e.g. ``"human"``); ``None``: every disc.
    measure
        ``"relative"`` (|v_rel|, the head-on worst case), ``"normal"`` (the component
        along the line of centres) or ``"approach"`` (the largest normal closing speed
        inside the active region): which speed the samples hold.

    Returns
    -------
    ContactSpeeds

    Raises
    ------
    InvalidParameterError
        For runs that are not navigation results, an unknown measure, or empty names.

    Examples
    --------
    >>> import designlab as dl
    >>> nav = dl.navigation
    >>> run = nav.simulate(nav.configuration(2), nav.EXPERIMENT_GAINS)
    >>> speeds = dl.codesign.contact_speeds(run)
    >>> speeds.obstacle, bool(speeds.contact[0]), round(speeds.mean(), 2)
    (('human',), False, 0.39)
    """
    if measure not in MEASURES:
        raise InvalidParameterError("measure", measure, f"must be one of {MEASURES}")
    keep = _check_names(obstacles)
    checked = _check_runs(runs)
    if checked and all(isinstance(r, NavigationResult) for r in checked):
        _check_known(keep, [r.scenario for r in checked])
    rows = [row for run in checked for row in _run_encounters(run, keep)]
    return _from_rows(rows, measure)


def _check_known(keep: frozenset[str] | None, scenarios: list[Scenario]) -> None:
    """Refuse an obstacle name that is no disc obstacle of the scenarios (a typo kept
    nothing: an empty answer, not an error, before)."""
    if keep is None:
        return
    discs = {o.name for sc in scenarios for o in sc.obstacles if isinstance(o, Disc)}
    unknown = sorted(keep - discs)
    if unknown:
        raise InvalidParameterError(
            "obstacles", unknown, f"must name disc obstacles of the runs: {sorted(discs)}"
        )


def _from_rows(rows: list[dict[str, Any]], measure: str) -> ContactSpeeds:
    def col(name: str) -> Array:
        return np.array([r[name] for r in rows], dtype=float)

    warnings: list[str] = []
    hits = [r for r in rows if r["contact"]]
    if hits:
        warnings.append(
            f"{len(hits)} of {len(rows)} encounters were contacts (the encounter is the first "
            "contact there)"
        )
    if not rows:
        warnings.append("no disc obstacle was met: the runs give no closing speed")
    return ContactSpeeds(
        scenario=tuple(r["scenario"] for r in rows),
        obstacle=tuple(r["obstacle"] for r in rows),
        contact=np.array([r["contact"] for r in rows], dtype=bool),
        time=col("time"),
        distance=col("distance"),
        surface_distance=col("surface_distance"),
        relative_speed=col("relative_speed"),
        normal_speed=col("normal_speed"),
        approach_speed=col("approach_speed"),
        angle=col("angle"),
        robot_speed=col("robot_speed"),
        obstacle_speed=col("obstacle_speed"),
        measure=measure,
        status=ContactStatus.OK if rows else ContactStatus.EMPTY,
        warnings=tuple(warnings),
    )


def navigation_contacts(
    scenarios: Scenario | Sequence[Scenario],
    gains: VFFGains,
    *,
    obstacles: str | Sequence[str] | None = None,
    measure: str = "relative",
    progress: ProgressHook | None = None,
    **simulate_options: Any,
) -> ContactSpeeds:
    """Simulate ``scenarios`` with ``gains`` and return the encounters (:func:`contact_speeds`).

    Parameters
    ----------
    scenarios
        Scenarios to run (e.g. ``[nav.configuration(i) for i in (1, 2, 3, 4)]``, or the
        walks of :meth:`designlab.navigation.RandomWalks.expand`).
    gains
        The VFF gains.
    obstacles, measure
        As for :func:`contact_speeds`.
    progress
        Called after each run (:mod:`designlab.progress`).
    **simulate_options
        Passed to :func:`designlab.navigation.simulate` (``stabilising``, ``method``, ...).

    Returns
    -------
    ContactSpeeds

    Examples
    --------
    >>> import designlab as dl
    >>> nav = dl.navigation
    >>> walks = nav.RandomWalks(n=2, seed=0).expand(nav.configuration(2))
    >>> speeds = dl.codesign.navigation_contacts(walks, nav.EXPERIMENT_GAINS)
    >>> len(speeds), speeds.status
    (2, 'ok')
    """
    if isinstance(scenarios, (str, bytes)) or not isinstance(scenarios, Scenario | Iterable):
        raise InvalidParameterError("scenarios", scenarios, "must be one or more Scenario objects")
    items = [scenarios] if isinstance(scenarios, Scenario) else list(scenarios)
    if not items or not all(isinstance(sc, Scenario) for sc in items):
        raise InvalidParameterError("scenarios", scenarios, "must hold one or more Scenario")
    if not isinstance(measure, str) or measure not in MEASURES:
        raise InvalidParameterError("measure", measure, f"must be one of {MEASURES}")
    _check_known(_check_names(obstacles), items)
    allowed = [k for k in inspect.signature(simulate).parameters if k not in ("scenario", "gains")]
    for key in simulate_options:
        if key not in allowed:
            raise InvalidParameterError(
                "simulate_options", key, f"is not an option of simulate; allowed: {allowed}"
            )
    runs = []
    for k, sc in enumerate(items):
        runs.append(simulate(sc, gains, **simulate_options))
        report(progress, Progress(k + 1, len(items), label="run", note=sc.name))
    return contact_speeds(runs, obstacles=obstacles, measure=measure)
