"""The exponential CBF safety filter on the attractive field (moved from the engine).

One QP per navigation period (OSQP, warm-started): minimise |a - a_nom|^2 subject to
h'' + k1 h' + k0 h >= 0 for h = d - r3 of every obstacle (derivatives by CasADi) and an
octagon inside |a| <= a_max; if the QP is infeasible the robot brakes along its velocity
(``docs/navigation.md``, "Baselines").
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from designlab.navigation.field import ObstacleGeometry, build_cbf_rows, build_field
from designlab.navigation.methods import METHODS
from designlab.navigation.parameters import HolonomicRobot, NonholonomicRobot
from designlab.navigation.scenarios import Scenario

__all__ = ["CBFFilter"]

Array = NDArray[np.float64]


class CBFFilter:
    """Exponential control-barrier-function filter of the attractive field, one OSQP QP per step.

    Parameters
    ----------
    geos : tuple of ObstacleGeometry
        The scenario's obstacles; each gives one constraint on h = d - r3 (critical
        radius r3 in m).
    robot : HolonomicRobot or NonholonomicRobot
        The robot: its ``max_accel`` (m/s^2) bounds |a| and its ``mass`` (kg) turns the
        field's force into the nominal acceleration.
    k : tuple of float
        (k_0, k_1) of the constraint h'' + k_1 h' + k_0 h >= 0, in 1/s^2 and 1/s.
    nominal : str
        The filtered method, one of :data:`~designlab.navigation.methods.METHODS` with
        ``filtered``: ``"cbf"`` (the attractive PD field) or ``"vff_cbf"`` (the new VFF);
        its field gives the nominal force.
    stabilising : bool
        With a stabilised method (``"vff_cbf"``): the nominal force includes the
        stabilising force F_L.
    tie : int
        Detour side (+1 / -1) of the nominal field where its rules leave it open.
    period : float
        The navigation period T_s in s: the barrier is tightened by the sampled-data margin
        ``a_max T_s^2 / 2`` (h = d - r3 - margin) for a method with ``sampled_margin``
        (``"vff_cbf"``), see :attr:`margin`.
    """

    def __init__(
        self,
        geos: tuple[ObstacleGeometry, ...],
        robot: HolonomicRobot | NonholonomicRobot,
        k: tuple[float, float],
        *,
        nominal: str = "cbf",
        stabilising: bool = False,
        tie: int = 1,
        period: float = 0.0,
    ) -> None:
        import osqp
        import scipy.sparse as sp

        method = METHODS.get(nominal, parameter="nominal", filtered=True)
        self.rows = build_cbf_rows(geos, "critical")
        self.field = build_field(geos, method.name)
        self.params = [robot.mass, float(tie), 1.0 if stabilising else 0.0, robot.max_accel]
        #: Sampled-data margin (m): how far the held acceleration can carry the robot from
        #: the path a continuously updated filter would command within one period.
        #: ``"cbf"`` keeps its earlier form (no margin), its reports unchanged.
        self.margin = 0.5 * robot.max_accel * period**2 if method.sampled_margin else 0.0
        self.n = len(geos)
        self.k = np.asarray(k, dtype=float)
        amax = robot.max_accel
        ang = np.arange(8) * np.pi / 4
        self.poly = np.stack([np.cos(ang), np.sin(ang)], axis=1)  # |a| <= amax as an octagon
        self.amax = amax * math.cos(math.pi / 8)  # inscribed octagon
        A = np.ones((self.n + 8, 2))  # dense pattern: every entry is stored and updated
        self.A = sp.csc_matrix(A)
        self.solver = osqp.OSQP()
        m = A.shape[0]
        opts = dict(verbose=False, eps_abs=1e-6, eps_rel=1e-6)
        new_api = int(osqp.__version__.split(".")[0]) >= 1
        opts.update(
            dict(warm_starting=True, polishing=False)
            if new_api
            else dict(warm_start=True, polish=False)
        )
        self.solve_kw = {"raise_error": False} if new_api else {}
        self.solver.setup(
            P=sp.csc_matrix(np.eye(2)),
            q=np.zeros(2),
            A=self.A,
            l=-np.inf * np.ones(m),
            u=np.inf * np.ones(m),
            **opts,
        )
        self.last_status = ""
        self.mass = robot.mass

    def force(
        self, x: Array, goal: Array, gains: Array, obs: Array, robot: Any, scenario: Scenario
    ) -> Array:
        if x.size == 5:
            x4 = np.array([x[0], x[1], x[3] * math.cos(x[2]), x[3] * math.sin(x[2])])
        else:
            x4 = x[:4]
        F = np.array(
            self.field(x=x4, goal=goal, obs=obs, gains=gains, params=self.params)["F"]
        ).ravel()
        a_nom = F / self.mass
        rows = self.rows(x=x4, obs=obs, k=self.k)
        Ab = np.array(rows["A"]).reshape(self.n, 2)
        lb = np.array(rows["lb"]).ravel() + self.k[0] * self.margin  # h -> h - margin
        A = np.vstack([Ab, self.poly])
        lower = np.concatenate([lb, -np.inf * np.ones(8)])
        upper = np.concatenate([np.inf * np.ones(self.n), self.amax * np.ones(8)])
        self.solver.update(q=-a_nom, Ax=A.ravel(order="F"), l=lower, u=upper)
        res = self.solver.solve(**self.solve_kw)
        self.last_status = str(res.info.status)
        if res.info.status_val not in (1, 2) or res.x is None or not np.all(np.isfinite(res.x)):
            # infeasible: brake along the velocity (the safest fallback), recorded in qp_status
            v = x4[2:4]
            sp_ = float(np.hypot(*v))
            a = -v / sp_ * robot.max_accel if sp_ > 1e-9 else np.zeros(2)
        else:
            a = res.x
        return np.array([1.0, *(self.mass * a)])
