"""The convergence map (Allan 2015 Sec. 2.4.5) and the step-size study (Sec. 2.5.5)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from designlab.errors import InvalidParameterError, StudyError
from designlab.following import tether as T
from designlab.following.tether.stability import _settled_time, convergence_map
from designlab.report import write_report
from designlab.study import parse_study, run_study


def test_pj_straight_ahead_converges_at_the_discrete_exponential_time():
    # l_k - l_d = (1 - k_V dt)^k (l_0 - l_d); V_k = k_V (l_k - l_d) < eps first at k*
    m = convergence_map(T.PseudoJoystick(), lengths=[2.0], angles=[0.0], max_time=5.0)
    k = math.ceil(math.log(0.01 / (5.0 * 1.0)) / math.log(1.0 - 5.0 * 0.01))
    assert m.time[0, 0] == pytest.approx(k * 0.01, abs=1e-9)
    assert m.final_length[0, 0] == pytest.approx(1.0, abs=1e-3)


def test_coded_laws_converge_everywhere_and_printed_pj_stops_askew_when_slack():
    ls, th = [0.5, 3.0, 8.0], np.linspace(-math.pi, math.pi, 9)
    for law in (T.PseudoJoystick(), T.FollowTheLeader(), T.FollowTheLeaderConstDistance()):
        m = convergence_map(law, ls, th, max_time=20.0)
        assert m.converged.all(), type(law).__name__
    # eq. 2.2 reverses a slack tether to l_d, and Omega = (2V/b) sin theta vanishes with V:
    # the robot stops at l_d without facing the leader
    printed = convergence_map(T.PseudoJoystick(law="printed"), [0.8], [0.3], max_time=10.0)
    assert not printed.converged[0, 0] and printed.at_rest[0, 0]
    assert printed.final_length[0, 0] == pytest.approx(1.0, abs=0.01)
    assert abs(printed.final_angle[0, 0]) > 0.1


def test_settled_time():
    ok = np.array([[False, True, True, True], [True, False, True, True], [True, True, True, False]])
    t = _settled_time(ok, 0.5, hold=1.0)
    assert t[0] == pytest.approx(0.5) and t[1] == pytest.approx(1.0) and math.isnan(t[2])


@pytest.mark.parametrize(
    "kwargs",
    [
        {"lengths": [], "angles": [0.0]},
        {"lengths": [1.0], "angles": [4.0]},
        {"lengths": [math.nan], "angles": [0.0]},
        {"lengths": ["a"], "angles": [0.0]},
        {"lengths": [1.0], "angles": [0.0], "max_time": -1.0},
        {"lengths": [1.0], "angles": [0.0], "max_time": 2.0, "hold": 3.0},
        {"lengths": np.linspace(0.1, 10, 1000), "angles": np.linspace(-3, 3, 1000)},
    ],
)
def test_convergence_map_refuses_bad_input(kwargs):
    with pytest.raises(InvalidParameterError):
        convergence_map(T.PseudoJoystick(), **kwargs)


def test_convergence_map_refuses_a_stepwise_mode():
    with pytest.raises(InvalidParameterError, match="controller"):
        convergence_map(T.SideTracking(), [1.0], [0.0])


def _stability(body: str) -> str:
    return f"designlab: 1\nkind: tether_stability\nname: s\n{body}"


def test_stability_study_and_report(tmp_path):
    study = parse_study(_stability("lengths: {low: 0.5, high: 4, num: 3}\nangles: 5\nmax_time: 10"))
    result = run_study(study)
    assert str(result.status) == "ok" and len(result.to_frame()) == 2 * 15
    out = write_report(result, tmp_path, index=False)
    files = {p.name for p in out.iterdir()}
    assert {"convergence.csv", "convergence_ftl.png", "convergence_pj.png", "summary.md"} <= files
    assert "every grid point converged (reproduced)" in (out / "summary.md").read_text()


@pytest.mark.parametrize(
    "body",
    [
        "lengths: {low: 4, high: 1, num: 3}",
        "angles: 1",
        "lengths: {low: 0.5, high: 4, num: 1000}\nangles: 1000",
        "max_time: 5\nhold: 6",
        "lengths: {low: -1, high: 4, num: 3}",
        "controllers: [{type: PseudoJoystick}, {type: PseudoJoystick}]",
    ],
)
def test_stability_study_refuses(body):
    with pytest.raises(StudyError, match=r"<string>:\d+: "):
        parse_study(_stability(body))


def test_step_size_study_and_claims(tmp_path):
    study = parse_study(
        "designlab: 1\nkind: tether_step_size\nname: z\npaths: [{type: square_s}]\n"
        "min_steps: [0.01, 0.4]"
    )
    result = run_study(study)
    frame = result.to_frame()
    assert frame["memory_m"].tolist() == pytest.approx([2.99, 119.6])
    ratio = frame["npd_mean_m"][1] / frame["npd_mean_m"][0]
    out = write_report(result, tmp_path, index=False)
    assert (out / "step_size_square_s.png").exists()
    assert f"mean deviation x{ratio:.2f}" in (out / "summary.md").read_text()


def test_step_size_study_refuses_pj():
    with pytest.raises(StudyError, match="step size"):
        parse_study(
            "designlab: 1\nkind: tether_step_size\nname: z\ncontroller: {type: PseudoJoystick}"
        )
