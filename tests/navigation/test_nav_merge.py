"""Merging obstacles whose critical regions overlap (Zeng 2011, Sec. 6.4.3)."""

from __future__ import annotations

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.navigation import Disc, Rectangle, Scenario, Stationary

nav = dl.navigation


def _disc(name: str, x: float, y: float, rho: float, r3: float, extra: float) -> Disc:
    return Disc(name, rho, r2=r3 + extra, r3=r3, motion=Stationary((x, y)))


def _contains(big_c: np.ndarray, big_r: float, c: np.ndarray, r: float) -> bool:
    return float(np.hypot(*(c - big_c))) + r <= big_r + 1e-9


@settings(max_examples=40, deadline=None)
@given(
    x=st.floats(1.0, 3.0), y=st.floats(-1.0, 1.0), dx=st.floats(0.0, 0.9), dy=st.floats(-0.5, 0.5),
    rho=st.tuples(st.floats(0.05, 0.3), st.floats(0.05, 0.3)),
    r3=st.tuples(st.floats(0.35, 0.6), st.floats(0.35, 0.6)),
    extra=st.tuples(st.floats(0.05, 1.0), st.floats(0.05, 1.0)),
)  # fmt: skip
def test_merged_disc_contains_both_regions_and_bodies(x, y, dx, dy, rho, r3, extra) -> None:
    a = _disc("a", x, y, rho[0], r3[0] + rho[0], extra[0])
    b = _disc("b", x + dx, y + dy, rho[1], r3[1] + rho[1], extra[1])
    assume(np.hypot(dx, dy) < a.r3 + b.r3)  # the critical regions overlap
    sc = Scenario("s", start=(6.0, 3.0), goal=(-2.0, -3.0), obstacles=(a, b))
    (m,) = nav.merge_critical_regions(sc).obstacles
    c = np.asarray(m.motion.state(np.zeros(1))[0][0])
    for o in (a, b):
        co = np.asarray(o.motion.state(np.zeros(1))[0][0])
        assert _contains(c, m.r3, co, o.r3)
        assert _contains(c, m.r2, co, o.r2)
        assert _contains(c, m.radius, co, o.radius)


def test_disc_and_rectangle_merge_into_a_bounding_rectangle() -> None:
    rect = Rectangle("box", (2.3, 0.0), 1.4, 0.6, r2=0.8, r3=0.4)
    disc = _disc("pole", 2.45, 1.0, 0.1, 0.4, 0.4)
    sc = Scenario("s", start=(4.5, 2.0), goal=(0.0, 2.0), obstacles=(rect, disc))
    assert sc.intersecting_critical_regions()
    merged = nav.merge_critical_regions(sc)
    (m,) = merged.obstacles
    assert isinstance(m, Rectangle) and m.name == "box+pole"
    assert m.r3 == 0.4 and m.r2 == 0.8  # the rectangle's clearances exceed the disc's (0.3/0.7)
    assert np.isclose(m.center[1] + m.width / 2, 1.1) and np.isclose(
        m.center[1] - m.width / 2, -0.3
    )
    # the robot no longer aims at the gap: it goes around both and never enters a region
    res = nav.simulate(merged, nav.EXPERIMENT_GAINS, stabilising="off")
    assert res.arrived and not res.entered_critical
    assert not any("overlap" in w for w in res.warnings)


def test_nothing_to_merge_keeps_the_scenario() -> None:
    sc = nav.configuration(3)
    assert nav.merge_critical_regions(sc) is sc
