"""Hostile inputs of the tether follower (issue 18): clear errors, caps before allocation, the
same limits in Python and YAML, picklable results, progress."""

from __future__ import annotations

import math
import pickle

import pytest

from designlab.errors import DesignlabError, InvalidParameterError
from designlab.following import tether
from designlab.following.tether.parameters import DURATION
from designlab.progress import Progress
from designlab.study import parse_study


def _study(body: str) -> str:
    return f"designlab: 1\nkind: tether_comparison\nname: hostile\n{body}"


def test_from_csv_text_value_names_file_line_and_column(tmp_path):
    f = tmp_path / "walk.csv"
    f.write_text("x_m,y_m\n0,0\n1,0\n2,abc\n")
    with pytest.raises(InvalidParameterError) as exc:
        tether.from_csv(f)
    msg = str(exc.value)
    assert "walk.csv" in msg and "line 4" in msg and "'y_m'" in msg and "abc" in msg


def test_from_csv_empty_file(tmp_path):
    f = tmp_path / "empty.csv"
    f.write_text("")
    with pytest.raises(InvalidParameterError, match=r"empty\.csv"):
        tether.from_csv(f)


@pytest.mark.parametrize(
    "make",
    [
        lambda: tether.simulate(tether.FollowTheLeader(), tether.straight_line(1e7)),
        lambda: tether.simulate(tether.FollowTheLeader(), tether.straight_line(10.0), duration=1e7),
        lambda: tether.FollowerRobot(length_noise_std=1e6),
        lambda: tether.figure_eight(a=1e6),
        lambda: tether.simulate(tether.FollowTheLeader(desired_length=1e6), tether.slalom()),
        lambda: tether.simulate(
            tether.FollowTheLeader(), tether.straight_line(1e4), speed=1e-3
        ),  # 10**7 s of walking
        lambda: tether.simulate(
            tether.FollowTheLeader(), tether.slalom(), robot=tether.FollowerRobot(sample_time=1e-9)
        ),
    ],
)
def test_memory_and_time_hogs_are_refused_before_allocation(make):
    with pytest.raises(InvalidParameterError) as exc:
        make()
    assert " is not allowed: " in str(exc.value)


def test_duration_cap_is_the_declared_one():
    with pytest.raises(InvalidParameterError, match="duration"):
        tether.simulate(
            tether.PseudoJoystick(), tether.straight_line(5.0), duration=DURATION.le * 1.01
        )


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("paths: [{type: figure_eight, a: 1.0e6}]", "a"),
        ("paths: [{type: straight_line, length: 1.0e7}]", "length"),
        ("paths: [{type: slalom}]\ndesired_lengths: [1.0e6]", "desired_lengths"),
        ("paths: [{type: slalom}]\ndesired_lengths: [0.2]", "half the robot length"),
        ("paths: [{type: circle, radius: '0.4'}]", "radius"),
        ("paths: [{type: circle, radius: true}]", "radius"),
        ("paths: [{type: slalom}]\nrobot: {length_noise_std: 1.0e6}", "length_noise_std"),
        ("paths: [{type: straight_line, length: 9000.0}]\nspeed: 0.1", "duration"),
    ],
)
def test_yaml_refuses_what_the_run_refuses(field, value):
    with pytest.raises(DesignlabError) as exc:
        parse_study(_study(field))
    assert value in str(exc.value)


@pytest.mark.parametrize("bad", ["0.4", True, math.nan, math.inf, -0.4, 1e9])
def test_python_refuses_what_yaml_refuses(bad):
    with pytest.raises(InvalidParameterError, match=r"circle\.radius"):
        tether.circle(radius=bad)


@pytest.mark.parametrize(
    ("kwargs", "name"), [({"popsize": 0}, "popsize"), ({"maxiter": 0}, "maxiter")]
)
def test_tuner_settings_refused_in_python_and_yaml(kwargs, name):
    with pytest.raises(InvalidParameterError, match=name):
        tether.tune(tether.FollowTheLeader, [tether.slalom()], **kwargs)
    key, value = next(iter(kwargs.items()))
    text = (
        "designlab: 1\nkind: tether_tuning\nname: t\nlaws: [FollowTheLeader]\n"
        f"paths: [{{type: slalom}}]\nvalidation_paths: [{{type: square_s}}]\n{key}: {value}\n"
    )
    with pytest.raises(DesignlabError, match=name):
        parse_study(text)


def test_linear_analysis_pickles():
    lin = tether.linear_analysis(tether.FollowTheLeader(), speed=0.5)
    back = pickle.loads(pickle.dumps(lin))
    assert back.damping_ratio == lin.damping_ratio
    assert back.system.A.tolist() == lin.system.A.tolist()


def test_statuses_are_documented_enums_equal_to_strings():
    run = tether.simulate(tether.PseudoJoystick(), tether.straight_line(3.0))
    assert isinstance(run.status, tether.FollowerStatus) and run.status == "ok"
    assert str(run.status) == "ok"


def test_tune_reports_every_generation():
    seen: list[Progress] = []
    res = tether.tune(
        tether.PseudoJoystick,
        [tether.straight_line(4.0)],
        validation_paths=[tether.slalom()],
        popsize=2,
        maxiter=2,
        progress=seen.append,
    )
    assert [p.step for p in seen] == list(range(1, len(res.history) + 1))
    assert all(p.label == "generation" and p.total == 2 for p in seen)
    assert [p.best for p in seen] == list(res.history)
