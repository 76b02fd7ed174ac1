"""The Lyapunov function over the held periods, not only at the samples (Zeng 2011, Sec. 5.5).

The stabilising force F_L is computed at each navigation sample so that dV/dt <= -b |v_L|^2
holds *at that instant* (true by construction where the limits are inactive); the force
is then held for T_s = 0.06 s while the robot and the obstacles move. This audit evaluates
V at every dynamics step of a recorded run and asks, for every period the robot spends in
an active region (no critical region, the same regions and detour sides at both ends),
whether V ended the period higher than it began, and by how much.

Examples
--------
>>> import designlab as dl
>>> nav = dl.navigation
>>> res = nav.simulate(nav.configuration(1), nav.EXPERIMENT_GAINS, stabilising="lyapunov")
>>> audit = res.hold_audit()
>>> audit.periods > 0 and 0.0 <= audit.share_rose <= 1.0
True
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from designlab.navigation.engine import obstacle_tracks
from designlab.navigation.field import ObstacleGeometry, build_field
from designlab.navigation.methods import METHOD, METHODS
from designlab.navigation.scenarios import Scenario
from designlab.results import Result

__all__ = ["HoldAudit", "hold_audit"]

Array = NDArray[np.float64]


@dataclass(frozen=True)
class HoldAudit(Result):
    """V over every held period of a run.

    Attributes
    ----------
    t
        Times of the dynamics steps (s).
    V
        The Lyapunov function at every dynamics step.
    periods
        Number of audited periods (active region at both ends, no critical region,
        no change of region or detour side).
    rose
        Per audited period: whether V(t_{k+1}) > V(t_k) (relative tolerance 1e-9).
    rise
        Per audited period: V(t_{k+1}) - V(t_k).
    share_rose
        Fraction of the audited periods in which V rose (nan if none).
    max_rise
        The largest rise of V over one period (0 if it never rose).
    """

    t: Array = field(repr=False)
    V: Array = field(repr=False)
    periods: int
    rose: NDArray[np.bool_] = field(repr=False)
    rise: Array = field(repr=False)
    share_rose: float
    max_rise: float


def _field_inputs(
    scenario: Scenario, t: Array, position: Array, velocity: Array
) -> tuple[Array, Array]:
    """The field's state (p, v) and obstacle (position, velocity, acceleration) per step."""
    x = np.concatenate([position, velocity], axis=1).T  # (4, n)
    P, Vo, Ao = obstacle_tracks(scenario, t)
    n = len(scenario.obstacles)
    obs = np.zeros((6 * n, t.size))
    for i in range(n):
        obs[6 * i : 6 * i + 2] = P[i].T
        obs[6 * i + 2 : 6 * i + 4] = Vo[i].T
        obs[6 * i + 4 : 6 * i + 6] = Ao[i].T
    return x, obs


def hold_audit(
    scenario: Scenario,
    t: Array,
    position: Array,
    velocity: Array,
    gains: Array,
    *,
    stabilising: bool,
    tie: int,
    period: float,
    method: str = METHOD.default,
) -> HoldAudit:
    """Evaluate V at every dynamics step and check it over each held period.

    Parameters
    ----------
    scenario
        The scenario of the run.
    t, position, velocity
        The recorded run at every dynamics step (s, m, m/s; the field's velocity).
    gains
        (k1, b, k3, k5) of the new VFF.
    stabilising
        Whether F_L was on.
    tie
        The detour tie-break side (+1/-1).
    period
        The navigation period T_s in s.
    method
        The method of the run: one with the Lyapunov function (``stabilised``, the new VFF
        filtered or not), whose V is evaluated.

    Returns
    -------
    HoldAudit
    """
    geos = tuple(ObstacleGeometry.of(o) for o in scenario.obstacles)
    fn = build_field(geos, METHODS.get(method, stabilised=True).name)
    robot = scenario.robot
    params = np.array([robot.mass, float(tie), 1.0 if stabilising else 0.0, robot.max_accel])
    x, obs = _field_inputs(scenario, t, position, velocity)
    mapped = fn.map(t.size)
    out = mapped(x, np.tile(np.asarray(scenario.goal, float)[:, None], t.size), obs,
                 np.tile(np.asarray(gains, float)[:, None], t.size),
                 np.tile(params[:, None], t.size))  # fmt: skip
    V = np.asarray(out[2]).ravel()
    crit = np.asarray(out[1]).ravel() > 0.5
    act = np.asarray(out[8]).reshape(len(geos), t.size) > 0.5 if geos else np.zeros((0, t.size))
    sig = np.asarray(out[10]).reshape(len(geos), t.size) if geos else np.zeros((0, t.size))
    n_sub = max(1, round(period / (t[1] - t[0]))) if t.size > 1 else 1
    starts = np.arange(0, t.size - n_sub, n_sub)
    keep = []
    for k in starts:
        seg = slice(k, k + n_sub + 1)
        a = act[:, seg]
        ok = a.any(axis=0).all() and not crit[seg].any()
        ok = ok and bool((a == a[:, :1]).all()) and bool((sig[:, seg] == sig[:, k : k + 1]).all())
        keep.append(ok)
    sel = starts[np.asarray(keep, bool)] if starts.size else starts
    rise = V[sel + n_sub] - V[sel]
    rose = rise > 1e-9 * np.maximum(1.0, np.abs(V[sel]))
    share = float(rose.mean()) if rose.size else float("nan")
    return HoldAudit(
        t, V, int(sel.size), rose, rise, share, float(max(0.0, rise.max())) if rise.size else 0.0
    )
