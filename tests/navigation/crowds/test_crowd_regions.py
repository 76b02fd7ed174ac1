"""The closing-speed sizing of pedestrians' regions and the derived horizon (designlab.navigation
.crowds.regions; docs/navigation_crowds.md).

Claims checked: the closing-speed active radius is the thesis's r2 at the top closing speed and
r3 + V^2/(2a) + V (T_s + t_turn) at none; a pedestrian walking away or beside exerts exactly no
force beyond that radius (the compiled field, random geometry); the critical radius keeps the
stopping guarantee: braking after one period of delay, the robot stops before touching a
pedestrian that enters at r3 with any velocity up to the top speed (simulated over random
relative velocities); a receding pedestrian does not change the robot's run at all.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad
from scipy.optimize import brentq

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.navigation.crowds.regions import closing_speed_sizing
from designlab.navigation.field import ObstacleGeometry, build_field

nav = dl.navigation
GAINS = nav.VFFGains(4.3, 0.68, 20.3, 240.7)
speeds = st.floats(0.3, 1.5)
accels = st.floats(2.0, 20.0)


def _crowd(**kw):
    return nav.crowd("corridor_counterflow", 4, length=12.0, region_sizing="closing_speed", **kw)


@settings(max_examples=40, deadline=None)
@given(v=speeds, a=accels, vo=st.floats(0.5, 2.5), rho=st.floats(0.1, 0.4))
def test_radius_between_robot_only_and_thesis(v, a, vo, rho):
    robot = nav.HolonomicRobot(max_speed=v, max_accel=a)
    c = _crowd(robot=robot, max_desired_speed=vo, desired_speed=min(1.34, vo),
               pedestrian_radius=rho)  # fmt: skip
    s = closing_speed_sizing(c)
    thesis = nav.region_sizes(nav.Human(radius=rho, max_speed=vo), robot, 0.06)
    assert s.r3 == pytest.approx(thesis.r3, abs=1e-12)
    assert s.r2_max == pytest.approx(thesis.r2, abs=1e-12)
    assert s.r2_min == pytest.approx(s.r3 + v * v / (2 * a) + v * 0.06, abs=1e-12)
    cs = np.linspace(-1.0, vo + 1.0, 50)
    r2 = [s.active_radius(x) for x in cs]
    assert np.all(np.diff(r2) >= 0) and r2[0] == s.r2_min and r2[-1] == s.r2_max
    assert c.pedestrian_regions() == pytest.approx((thesis.r2, thesis.r3), abs=1e-12)


def _field_force(geo, robot_p, ped_p, ped_v, r2):
    f = build_field((geo,), "vff")
    out = f(x=[*robot_p, 0.3, -0.1], goal=[robot_p[0] + 5.0, robot_p[1]],
            obs=[*ped_p, *ped_v, 0.0, 0.0], gains=[4.3, 0.68, 20.3, 240.7],
            params=[4.4, 1.0, 0.0, 10.0], **({"r2": [r2]} if geo.r2_input else {}))  # fmt: skip
    return np.array(out["F"]).ravel() - np.array([4.3 * 5.0 - 0.68 * 4.3 * 0.3, 0.68 * 4.3 * 0.1])


@settings(max_examples=60, deadline=None)
@given(angle=st.floats(-math.pi, math.pi), extra=st.floats(0.0, 2.5),
       speed=st.floats(0.0, 1.8), turn=st.floats(math.pi / 2, 3 * math.pi / 2))  # fmt: skip
def test_receding_pedestrian_exerts_no_force_beyond_the_robot_only_radius(angle, extra, speed,
                                                                        turn):  # fmt: skip
    c = _crowd()
    s = c.closing_speed_sizing()
    d = s.r2_min + 1e-9 + extra
    u = np.array([math.cos(angle), math.sin(angle)])  # from the pedestrian to the robot
    robot_p = np.array([5.0, 2.0])
    ped_p = robot_p - d * u
    R = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    ped_v = speed * (R @ u)  # at least 90 degrees from the line of sight: receding or beside
    r2 = float(s.active_radii(robot_p, ped_p[None], ped_v[None])[0])
    assert r2 == pytest.approx(s.r2_min, abs=1e-12)
    F = _field_force(c.pedestrian_geometry(), robot_p, ped_p, ped_v, r2)
    assert np.all(F == 0.0)
    if d < s.r2_max - 1e-6:  # the worst-case region would have pushed
        fixed = ObstacleGeometry("disc", s.r2_max, s.r3, moving=True)
        assert np.any(np.abs(_field_force(fixed, robot_p, ped_p, ped_v, s.r2_max)) > 0)


def _positions(t, v, a, ts):
    """Displacement of a robot moving at v for ts, then braking at a to rest (exact)."""
    sp = float(np.hypot(*v))
    if sp == 0:
        return np.zeros((t.size, 2))
    u = v / sp
    tb = np.clip(t - ts, 0.0, sp / a)
    s = sp * np.minimum(t, ts) + sp * tb - 0.5 * a * tb**2
    return s[:, None] * u[None, :]


@settings(max_examples=100, deadline=None)
@given(bearing=st.floats(-math.pi, math.pi), heading=st.floats(-math.pi, math.pi),
       frac=st.floats(0.0, 1.0), ped_heading=st.floats(-math.pi, math.pi),
       ped_frac=st.floats(0.0, 1.0))  # fmt: skip
def test_critical_region_keeps_the_stopping_guarantee(bearing, heading, frac, ped_heading,
                                                     ped_frac):  # fmt: skip
    c = _crowd()
    s = c.closing_speed_sizing()
    robot = c.robot
    vmr, amr, ts = robot.max_speed, robot.max_accel, c.sample_time
    p0 = s.r3 * np.array([math.cos(bearing), math.sin(bearing)])  # the robot enters at r3
    v = frac * vmr * np.array([math.cos(heading), math.sin(heading)])
    vo = ped_frac * c.max_desired_speed * np.array([math.cos(ped_heading), math.sin(ped_heading)])
    t_stop = ts + float(np.hypot(*v)) / amr
    t = np.linspace(0.0, t_stop, 1001)
    rel = p0 + _positions(t, v, amr, ts) - t[:, None] * vo[None, :]
    assert np.hypot(rel[:, 0], rel[:, 1]).min() >= robot.radius + c.pedestrian_radius - 1e-9


def _run(sizing, paths):
    c = nav.crowd("corridor_counterflow", len(paths), length=12.0, start=(1.5, 2.0),
                  goal=(8.5, 2.0), paths=paths, horizon=20.0, region_sizing=sizing)  # fmt: skip
    return nav.simulate(c, GAINS)


def test_a_receding_pedestrian_does_not_change_the_run():
    far = (((11.7, 0.3), (11.7, 0.3)),)  # stands beyond every active region
    ahead = (((3.5, 2.0), (11.5, 2.0)),)  # walks away from the robot, faster than it
    alone = _run("closing_speed", far)
    passed = _run("closing_speed", ahead)
    assert math.isfinite(alone.arrival_time) and passed.arrival_time == alone.arrival_time
    np.testing.assert_array_equal(passed.robot_positions, alone.robot_positions)
    worst = _run("worst_case", ahead)  # the thesis's region of the walker ahead pushes back
    assert not np.array_equal(worst.robot_positions, alone.robot_positions[: len(
        worst.robot_positions)]) or worst.arrival_time != alone.arrival_time  # fmt: skip


def test_adopted_active_radius_is_refused_with_closing_speed():
    with pytest.raises(InvalidParameterError, match="active_radius"):
        _crowd(active_radius=3.0)


@settings(max_examples=12, deadline=None)
@given(x0=st.floats(1.0, 3.0), y0=st.floats(0.8, 3.2), x1=st.floats(4.0, 11.0),
       y1=st.floats(0.8, 3.2), v=speeds, a=accels)  # fmt: skip
def test_free_run_time_is_the_rest_to_rest_minimum(x0, y0, x1, y1, v, a):
    c = nav.crowd("corridor_counterflow", 1, length=12.0, start=(x0, y0), goal=(x1, y1),
                  paths=(((11.7, 0.3), (11.7, 0.3)),),
                  robot=nav.HolonomicRobot(max_speed=v, max_accel=a))  # fmt: skip
    d = math.hypot(x1 - x0, y1 - y0)

    def reach(T):  # distance of the fastest rest-to-rest speed profile lasting T, by quadrature
        kinks = [min(v / a, T / 2), max(T - v / a, T / 2)]
        return quad(lambda t: min(a * t, v, a * (T - t)), 0.0, T, points=kinks, limit=200)[0]

    assert c.free_run_time == pytest.approx(brentq(lambda T: reach(T) - d, 1e-6, 1e3), abs=1e-7)
    assert c.time_limit == pytest.approx(2.5 * c.free_run_time, abs=1e-12)
    assert c.replace(horizon=7.0).time_limit == 7.0
    assert c.replace(horizon_factor=4.0).time_limit == pytest.approx(4 * c.free_run_time)


@pytest.mark.parametrize(
    ("kw", "name"),
    [({"horizon_factor": 1.0}, "horizon_factor"), ({"horizon_factor": math.nan}, "horizon_factor"),
     ({"horizon_factor": math.inf}, "horizon_factor"), ({"region_sizing": "best"}, "region_sizing"),
     ({"horizon": -1.0}, "horizon")],
)  # fmt: skip
def test_bad_limits_and_sizings_are_refused(kw, name):
    with pytest.raises(InvalidParameterError, match=name):
        nav.crowd("corridor_counterflow", 4, length=12.0, **kw)
