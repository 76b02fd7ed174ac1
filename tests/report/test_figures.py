"""Every report figure is readable: no tick labels or axis labels overlap or are clipped.

Every study kind runs a small study (settings reduced so that each takes seconds)
through its report writer; every figure the writer hands to ``write_png`` is drawn
with Agg and its text measured: the tick labels of one axis must not overlap each
other, the axis labels, titles and tick labels of the whole figure must not
overlap each other across axes, and none may stand outside the figure.
"""

from __future__ import annotations

import importlib
import itertools
import pkgutil
from pathlib import Path
from typing import Any

import pytest
from matplotlib.figure import Figure
from matplotlib.text import Text
from matplotlib.transforms import Bbox

import designlab.report
from designlab.study import parse_study, run_study

#: A pixel of slack: anti-aliased glyph boxes of neighbours may touch.
SLACK = 1.0

SMALL_STUDIES: dict[str, str] = {
    "impact_cases": "cases:\n  - {robot: MANIPULATOR_1, foam: FOAM_1, head: TEST_HEAD, "
    "impact_velocity: 0.4}\n",
    "impact_sweep": "base: {robot: MANIPULATOR_1, foam: FOAM_1, head: HEAD_MIN, "
    "impact_velocity: 1.25}\nsweep:\n  method: grid\n  parameters:\n"
    "    foam.stiffness: {values: [2.0e+4, 4.0e+4]}\n    head.mass: {values: [3.0, 5.0]}\n"
    "sensitivity: {metrics: [a_h_max_g], one_at_a_time: {deltas_pct: [-10, 10]}}\n",
    "foam_envelope_sweep": "base: {robot: MANIPULATOR_1, foam: FOAM_1}\n"
    "damping: {low: 0, high: 200, num: 5}\nsweep:\n  method: grid\n  parameters:\n"
    "    robot.mass: {values: [5.0, 20.0]}\n",
    "foam_design": "robots: [MANIPULATOR_1]\nfoams: [FOAM_1]\n"
    "damping: {low: 20, high: 100, num: 3}\noptimal: false\nworst_case_check: false\n",
    "joint_reduction": "joints:\n  - {name: geared, inertia: 0.059, k_mech: 2000, c_mech: 2.0, "
    "k_cont: 1500, c_cont: 30, lever_arm: 0.2}\nratios: {low: 0.1, high: 100, num: 4}\n",
    "zeng_ch3_claims": "readings:\n  - {name: b, impact_velocity: 0.25, feedforward: false}\n"
    "speed_ratios: [1.0]\n",
    "tether_comparison": "paths: [{type: slalom}]\ncontrollers: [{type: PseudoJoystick}, "
    "{type: FollowTheLeader}]\ndesired_lengths: [0.6]\n",
    "tether_sweep": "base: {controller: {type: FollowTheLeader}, path: {type: slalom}}\n"
    "sweep:\n  method: grid\n  parameters:\n    controller.lookahead: {values: [0.1, 0.5]}\n"
    "    controller.desired_length: {values: [0.6, 1.0]}\n",
    "navigation_scenarios": "scenarios: [{configuration: 1}]\nmethods:\n  - {label: vff, gains: "
    '{k1: 4.3, b: 0.68, k3: 20.3, k5: 240.7}, stabilising: "off"}\n',
    "navigation_sweep": "base: {gains: {k1: 4.3, b: 0.68, k3: 20.3, k5: 240.7}, "
    'scenarios: [[1, 6]], stabilising: "off"}\nsweep:\n  method: grid\n  parameters:\n'
    "    gains.k1: {values: [3.0, 4.3]}\n    gains.k5: {values: [120.0, 240.0]}\n",
    "accompanying": "tasks: [forward, left_pivot]\n"
    "tuning: {tune_on: [forward], derivative_free: false}\n",
    "tether_tuning": "laws: [FollowTheLeader]\npaths: [{type: slalom}]\nspeeds: [0.5]\n"
    "validation_paths: [{type: square_s}]\npopsize: 4\nmaxiter: 2\n",
    "navigation_gains": 'configurations: [1]\nvalidation: [3]\nmodes: ["off"]\npopsize: 4\n'
    "max_evaluations: 8\nrefine: false\nsensitivity: false\n",
    "tether_stability": "controllers: [{type: PseudoJoystick}]\n"
    "lengths: {low: 0.5, high: 2.0, num: 2}\nangles: 3\nmax_time: 5\n",
    "tether_step_size": "paths: [{type: square_s}]\nmin_steps: [0.01, 0.4]\n",
    "tether_snagging": "gaps: {low: 1.0, high: 2.5, num: 3}\ndetail_gaps: [2.5]\n",
    "tether_modes": "paths: [{type: straight_line, length: 3.0}]\nmodes: [SideJoystick]\n"
    "side_offsets: [0.5]\nbrake_laws: [PseudoJoystick]\n",
    "navigation_planners": "scenarios: [{configuration: 1}]\nmirror: false\n"
    "planners: [{method: vo, settings: {horizon: 2.0}}]\nmethods: []\n",
    "codesign": "scenarios: [{configuration: 2}]\n"
    "front: {objectives: [arrival_time, foam_thickness], population: 4, generations: 1}\n"
    "speed_map: {stiffness: {num: 3}, damping: {num: 3}}\n"
    "risk: {foams: [FOAM_1], speeds: {num: 3}, samples: 1000}\n",
    "navigation_crowds": "scenarios: [corridor_counterflow, crossing]\ndensities: [0.1, 0.2]\n"
    "seeds: [0]\nmethods: [{method: vff}, {method: masoud}]\n"
    "crowd: {length: 8.0, horizon: 0.5}\nanimations: false\n",
}


def _texts(fig: Figure) -> list[tuple[str, Text]]:
    """Every visible, non-empty tick label, axis label and title, with where it belongs."""
    out: list[tuple[str, Text]] = []
    for i, ax in enumerate(fig.axes):
        for name, axis in (("x", ax.xaxis), ("y", ax.yaxis)):
            out += [(f"ax{i} {name} tick", t) for t in axis.get_ticklabels()]
            out.append((f"ax{i} {name} label", axis.label))
        out += [(f"ax{i} title", t) for t in (ax.title, ax._left_title, ax._right_title)]
    if fig._suptitle is not None:
        out.append(("suptitle", fig._suptitle))
    return [(w, t) for w, t in out if t.get_visible() and t.get_text().strip()]


def _shrunk(box: Bbox) -> Bbox:
    return Bbox.from_extents(box.x0 + SLACK, box.y0 + SLACK, box.x1 - SLACK, box.y1 - SLACK)


def _drawn(where: str, box: Bbox, fig: Figure, renderer: object) -> bool:
    """A tick label is drawn only if its tick lies within the axes' view (others are kept)."""
    if " tick" not in where:
        return True
    ax = fig.axes[int(where.split()[0][2:])]
    span = ax.get_window_extent(renderer)
    if where.split()[1] == "x":
        return span.x0 - SLACK <= (box.x0 + box.x1) / 2 <= span.x1 + SLACK
    return span.y0 - SLACK <= (box.y0 + box.y1) / 2 <= span.y1 + SLACK


def layout_problems(fig: Figure) -> list[str]:
    """Text of ``fig`` that overlaps other text or stands outside the figure."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    texts = [(w, t, t.get_window_extent(renderer)) for w, t in _texts(fig)]
    texts = [(w, t, b) for w, t, b in texts if _drawn(w, b, fig, renderer)]
    problems = []
    frame = fig.bbox
    for where, text, box in texts:
        if not (box.x0 >= frame.x0 - SLACK and box.x1 <= frame.x1 + SLACK
                and box.y0 >= frame.y0 - SLACK and box.y1 <= frame.y1 + SLACK):  # fmt: skip
            problems.append(f"{where} {text.get_text()!r} is clipped by the figure edge")
    for (w1, t1, b1), (w2, t2, b2) in itertools.combinations(texts, 2):
        if _shrunk(b1).overlaps(_shrunk(b2)):
            problems.append(f"{w1} {t1.get_text()!r} overlaps {w2} {t2.get_text()!r}")
    return problems


def test_the_checker_sees_overlap_and_clipping() -> None:
    fig = Figure(figsize=(3, 2))
    ax = fig.subplots()
    ax.set_ylabel("a very long label that cannot fit beside an axes this short " * 2)
    ax.set_xticks([0, 0.01], ["a long tick label", "another long one"])
    problems = " ".join(layout_problems(fig))
    assert "clipped" in problems and "overlaps" in problems
    fig = Figure(figsize=(4, 3))
    ax = fig.subplots()
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    fig.tight_layout()
    assert layout_problems(fig) == []


def _capture(monkeypatch: pytest.MonkeyPatch) -> list[tuple[str, Figure]]:
    """Collect every figure a report writer hands to ``write_png``."""
    figures: list[tuple[str, Figure]] = []

    def fake_write_png(fig: Figure, path: object, **_: object) -> Path:
        figures.append((Path(str(path)).name, fig))
        return Path(str(path))

    for info in pkgutil.iter_modules(designlab.report.__path__):
        module = importlib.import_module(f"designlab.report.{info.name}")
        if hasattr(module, "write_png"):
            monkeypatch.setattr(module, "write_png", fake_write_png)
    return figures


def test_every_kind_has_a_small_study() -> None:
    """Every study kind's figures are rendered here."""
    from designlab.study.registry import study_kinds

    covered = set(SMALL_STUDIES) | set(FIGURELESS)
    assert set(study_kinds()) <= covered, sorted(set(study_kinds()) - covered)


#: Kinds whose reports are tables only (no figure to check), with what they hold.
FIGURELESS: dict[str, str] = {
    "navigation_account": "the row-by-row account of the thesis tables (CSV and Markdown)",
    "navigation_regions": "region sizes with every intermediate quantity (CSV and Markdown)",
}


@pytest.mark.parametrize("kind", sorted(FIGURELESS))
def test_figureless_kinds_declare_no_figure(kind: str) -> None:
    from designlab.study.registry import kind_of

    produces = " ".join(getattr(kind_of(kind).schema, "PRODUCES", ()))
    assert ".png" not in produces, f"{kind} produces figures: give it a small study above"


@pytest.mark.slow  # 20 small studies run and drawn: minutes; .ci/run's slow step runs it
@pytest.mark.parametrize("kind", sorted(SMALL_STUDIES))
def test_report_figures_have_readable_labels(
    kind: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    figures = _capture(monkeypatch)
    text = f"designlab: 1\nkind: {kind}\nname: figs\n{SMALL_STUDIES[kind]}"
    result = run_study(parse_study(text, file=f"{kind}.yaml"))
    designlab.report.write_report(result, tmp_path, index=False)
    assert figures, f"{kind}: the report has no figure"
    problems = [f"{name}: {p}" for name, fig in figures for p in layout_problems(fig)]
    problems += [f"{name}: {p}" for name, fig in figures for p in legend_problems(fig, kind)]
    problems += [f"{name}: {p}" for name, fig in figures for p in label_problems(fig)]
    assert not problems, "\n".join(problems)


def _legend_entries(ax: object) -> list[tuple[str, str | None]]:
    """``(text, colour)`` of each entry of the axes' legend (colour None: a patch or image)."""
    from matplotlib.colors import to_hex

    legend = ax.get_legend()  # type: ignore[attr-defined]
    if legend is None:
        return []
    out = []
    for handle, text in zip(legend.legend_handles, legend.get_texts(), strict=True):
        get = getattr(handle, "get_color", None)
        colour = get() if get else None
        out.append((text.get_text(), to_hex(colour) if isinstance(colour, str | tuple) else None))
    return out


def legend_problems(fig: Figure, kind: str) -> list[str]:
    """A method drawn in a colour not its own, two methods in one colour, or a path plot of a
    navigation report without start and goal in its legend."""
    from designlab.report.figure_style import method_colour, method_key

    problems = []
    for i, ax in enumerate(fig.axes):
        entries = _legend_entries(ax)
        by_colour: dict[str, set] = {}
        for text, colour in entries:
            key = method_key(text.removeprefix("robot (").removesuffix(")"))
            if key is None or colour is None:
                continue
            if colour != method_colour(text.removeprefix("robot (").removesuffix(")")):
                problems.append(f"ax{i}: {text!r} drawn in {colour}, not its palette colour")
            by_colour.setdefault(colour, set()).add(key)
        problems += [
            f"ax{i}: methods {sorted(k)} share {c}" for c, k in by_colour.items() if len(k) > 1
        ]
        texts = {t for t, _ in entries}
        if (
            kind.startswith("navigation")
            and ax.get_xlabel() == "x (m)"
            and ax.get_ylabel() == "y (m)"
        ):
            problems += [f"ax{i}: no {w!r} in the legend of a path plot" for w in ("start", "goal")
                         if w not in texts]  # fmt: skip
    return problems


def _labelled_by_neighbour(ax: Any, name: str, axes: list[Any]) -> bool:
    """The axis's label stands on the panel below (x) or to the left (y) of the same column
    or row: one label for a column of panels."""
    box = ax.get_position()
    for other in axes:
        b = other.get_position()
        if name == "x" and other.get_xlabel().strip() and abs(b.x0 - box.x0) < 1e-3:
            if b.y0 < box.y0:
                return True
        if name == "y" and other.get_ylabel().strip() and abs(b.y0 - box.y0) < 1e-3:
            if b.x0 < box.x0:
                return True
    return False


def label_problems(fig: Figure) -> list[str]:
    """An axis showing tick labels without an axis label on it or on its column's (x) or
    row's (y) outer panel; colour bars excepted."""
    fig.canvas.draw()
    problems = []
    axes = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
    for i, ax in enumerate(fig.axes):
        if ax.get_label() == "<colorbar>" or not ax.get_visible() or not ax.axison:
            continue
        for name, axis in (("x", ax.xaxis), ("y", ax.yaxis)):
            shown = [t for t in axis.get_ticklabels() if t.get_visible() and t.get_text().strip()]
            if shown and not axis.label.get_text().strip():
                if not _labelled_by_neighbour(ax, name, axes):
                    problems.append(f"ax{i} ({ax.get_title()!r}): {name} ticks without a label")
    return problems


def test_tuning_figure_reads_with_as_many_scenarios_as_the_committed_study() -> None:
    """The committed tether_tuning study has 21 scenarios per law (its small study above, 2)."""
    from types import SimpleNamespace

    import pandas as pd

    from designlab.report.tether import _tuning_figure

    paths = ["figure_eight_a4", "slalom", "square_s", "corridor_corner", "circle_r1.5"]
    paths += ["random_walk_s101", "random_walk_s102"]
    rows = [
        {"set": "tuning" if i < 2 else "validation", "path": p, "speed_m_per_s": v,
         "controller": who, "npd_mean_over_b": 0.5 + 0.1 * i + (who == "default")}
        for i, p in enumerate(paths) for v in (0.3, 0.5, 0.8) for who in ("default", "tuned")
    ]  # fmt: skip
    r = SimpleNamespace(
        scenarios=pd.DataFrame(rows),
        history=[0.6] * 3 + [0.5] * 17,
        controller=SimpleNamespace(name="PseudoJoystick"),
    )
    fig = _tuning_figure(r)
    assert layout_problems(fig) == []
    ax = fig.axes[0]
    labels = [t.get_text() for t in [*ax.get_xticklabels(), *ax.get_yticklabels()]]
    assert sum("m/s" in text for text in labels) == 21  # every scenario labelled
