"""Fuzz: the compiled impact kernel against an independent evaluator, settled by mpmath.

Run from the repository root::

    python benchmarks/fuzz_kernel.py --designs 1e6              # 1e6 designs per family
    python benchmarks/fuzz_kernel.py --designs 1e8 --seconds 3000 --markdown fuzz.md
    python benchmarks/fuzz_kernel.py --families full_wide,full_stiff --evaluator numpy
    python benchmarks/fuzz_kernel.py --designs 4e6 --start-chunk 30   # start at chunk 30
    python benchmarks/fuzz_kernel.py --designs 1e8 --state run.json --markdown run.md  # resumable

Designs are drawn (seeded per family and chunk) from families of valid designs of the
reduced model (docs/impact.md, "Self-check"):

* ``thesis``: the thesis's ranges of benchmarks/impact.py (M_r 5-60 kg, C_r
  100-600 N s/m, K_r 10-50 kN/m, K_c 5-100 kN/m, xi_c 0.05-0.2, the head-neck
  ranges 4.4-5.3 kg, 46-130 N s/m, 3-5 kN/m);
* ``wide``: the wide ranges of issue 22 (M_r 2-20, C_r 0-800, K_r 5e3-5e4,
  K_c 5e3-8e4, C_c 0-300, M_h 3-6, C_h 0-150, K_h 1e3-1e4);
* ``critical``: the arm's and the head's own modes critically damped within
  1e-3 (C_r = 2 sqrt(K_r M_r) (1 + d), likewise C_h; nearly double real poles);
* ``repeated``: the arm's own mode equal to the head's (K_r / M_r = K_h / M_h,
  C_r / M_r = C_h / M_h) and a soft foam (K_c, C_c 1e-3 of the wide ranges):
  nearly repeated complex pairs;
* ``overdamped``: dampers 10-100 times the wide ranges;
* ``heavy``: M_r log-uniform up to 1e3 kg and K_r up to 1e7 N/m;

of the reduced model's constrained impact (the head against a wall, window
[0, 0.05 s]; :data:`CONSTRAINED_FAMILIES`): ``constrained_wide``,
``constrained_heavy`` (the ranges of ``wide`` and ``heavy``) and
``constrained_critical`` (the arm's mode on the foam critically damped within
1e-6: a nearly double pole, which the compiled path's certificate hands to the
numpy path); and of the full series joint (10 parameters, :data:`FULL_FAMILIES`):
``full_wide`` (wide ranges, K_mech / K_cont log-uniform in [0.03, 3000]),
``full_stiff`` (a stiff motor node: C_mech 0, C_cont 1e-4-1e-2) and
``full_constrained`` (``full_wide`` against a wall). The compiled full joint's
certificate (distinct poles, condition <= 1e4, backward error <= 1e-13) sends a
design it does not certify to the eigen path; the harness counts those fallbacks.

Each design goes through the kernel as :func:`designlab.impact.metrics_of_matrix`
uses it (its a-posteriori self-check, suspects settled by the numpy path) and
through an independent evaluator: by default ``fast`` (``benchmarks/fuzz_fast.py``:
Aberth roots or LAPACK eigenvalues, residues from the initial state's linear system,
dense sampling refined by Newton; no code shared with the kernel or the numpy path),
or ``numpy`` (the numpy modal path, :mod:`designlab.impact.modal`, about 20 times
slower). Every design where a_h,max, eps_max, F_max or t_imp differ by more than
1e-10 (relative), or the statuses differ, is settled by a 40-digit mpmath
evaluation written for the tests (``tests/impact/exact_reference.py``): each
evaluator is wrong where it is off the mpmath value by more than its certified
tolerance (1e-8 relative for the maxima, 1e-9 for t_imp), or where it reports
no lobe end although a_h crosses zero before the kernel's documented horizon
(``((max_lobe_steps // 12) 12 + 11) 0.4 / rate``), or the reverse. A design the
kernel reports ``uncertified`` (metrics NaN, said in a warning) is counted apart:
it is not a number presented as exact.

The run goes in chunks of ``--chunk`` designs, the families taking turns chunk by
chunk (memory stays constant; ``--seconds`` stops after the round in which the time
is up, so every family gets the same number of chunks). Chunk ``k`` of a family
is drawn from ``numpy.random.default_rng([seed, family, k, chunk])``, so a run can
be split or resumed (``--start-chunk``). Printed: every disagreement and its
verdict, then a table per family: designs, CPU seconds (this process: kernel,
evaluator, mpmath), disagreements, kernel wrong, evaluator wrong, uncertified,
self-check fallbacks (reduced: designs the self-check sent to the extended-precision
evaluation, double-double then 40-digit decimal, and, if refused there too, the numpy
path, with the open lobes whose a_h came near its rounding noise, retried there;
full joint and constrained: designs the certificate sent to the eigen or numpy
path). ``--markdown FILE`` writes that table with the date, the CPU and the
command. With ``--state FILE`` the tallies are saved after every family's chunk and a killed
run, started again with the same arguments, continues where it stopped (the markdown
is rewritten each time too). The exit status is 1 if the kernel was wrong on any
design.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this checkout's designlab
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "impact"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from designlab.impact import kernel, kernel_full
from designlab.impact import metrics as _m
from designlab.impact.full_joint_model import grid_rate

NAMES = ("force", "head_acceleration", "compression")
WIDE = [(2, 20), (0, 800), (5e3, 5e4), (5e3, 8e4), (0, 300), (3, 6), (0, 150), (1e3, 1e4)]
#: relative tolerances of the certified values: maxima (the branch and bound's 1e-8), t_imp
TOLERANCE = (1e-8, 1e-8, 1e-8, 1e-9)
#: relative difference above which the two evaluators disagree
DISAGREE = 1e-10
#: least grid cells of the mpmath referee over the window (none wider than a twelfth of
#: the fastest resolved period, whatever this is; :class:`exact_reference.MpImpact`)
SAMPLES = 256
#: the window of the constrained impact (s), as metrics_of_matrix's default stop_time
WINDOW = 0.05
#: the kernel's max_lobe_steps, as metrics_of_matrix's default
MAX_STEPS = 4096

FAMILIES = ("thesis", "wide", "critical", "repeated", "overdamped", "heavy")
#: the reduced model's constrained impact (8 parameters, the head's ignored)
CONSTRAINED_FAMILIES = ("constrained_wide", "constrained_critical", "constrained_heavy")
#: full-joint families (10 parameters, docs/impact_joint.md)
FULL_FAMILIES = ("full_wide", "full_stiff", "full_constrained")
ALL_FAMILIES = (*FAMILIES, *CONSTRAINED_FAMILIES, *FULL_FAMILIES)


def _uniform(rng: np.random.Generator, n: int, ranges: list) -> np.ndarray:
    return np.stack([rng.uniform(a, b, n) for a, b in ranges], axis=1)


def draw(family: str, rng: np.random.Generator, n: int) -> np.ndarray:
    """``(n, 8)`` designs of one reduced family (module docstring)."""
    if family == "thesis":
        p = _uniform(rng, n, [(5, 60), (100, 600), (1e4, 5e4), (5e3, 1e5), (0.05, 0.2),
                              (4.4, 5.3), (46, 130.2), (3e3, 5e3)])  # fmt: skip
        p[:, 4] = 2 * p[:, 4] * np.sqrt(4.4 * p[:, 3])
        return p
    p = _uniform(rng, n, WIDE)
    if family == "critical":
        p[:, 1] = 2 * np.sqrt(p[:, 2] * p[:, 0]) * (1 + rng.uniform(-1e-3, 1e-3, n))
        p[:, 6] = 2 * np.sqrt(p[:, 7] * p[:, 5]) * (1 + rng.uniform(-1e-3, 1e-3, n))
    elif family == "repeated":
        p[:, 2] = p[:, 7] / p[:, 5] * p[:, 0]
        p[:, 1] = p[:, 6] / p[:, 5] * p[:, 0]
        p[:, 3] *= 1e-3
        p[:, 4] *= 1e-3
    elif family == "overdamped":
        f = np.exp(rng.uniform(np.log(10.0), np.log(100.0), (n, 3)))
        p[:, [1, 4, 6]] *= f
    elif family in ("heavy", "constrained_heavy"):
        p[:, 0] = np.exp(rng.uniform(np.log(2.0), np.log(1e3), n))
        p[:, 2] = np.exp(rng.uniform(np.log(5e3), np.log(1e7), n))
    elif family == "constrained_critical":  # C_r + C_c = 2 sqrt((K_r + K_c) M_r) (1 + d)
        total = 2 * np.sqrt((p[:, 2] + p[:, 3]) * p[:, 0]) * (1 + rng.uniform(-1e-6, 1e-6, n))
        p[:, 4] = np.minimum(p[:, 4], 0.5 * total)
        p[:, 1] = total - p[:, 4]
    return p


def draw_full(family: str, rng: np.random.Generator, n: int) -> np.ndarray:
    """``(n, 10)`` full-joint designs (M_r, C_mech, K_mech, K_c, C_c, M_h, C_h, K_h, C_cont,
    K_cont)."""
    k_q = rng.uniform(5e3, 5e4, n)
    k_m = k_q * np.exp(rng.uniform(np.log(0.03), np.log(3000.0), n))
    p = np.column_stack([
        rng.uniform(2, 20, n), rng.uniform(0, 500, n), k_m, rng.uniform(5e3, 8e4, n),
        rng.uniform(0, 300, n), rng.uniform(3, 6, n), rng.uniform(0, 150, n),
        rng.uniform(1e3, 1e4, n), rng.uniform(1, 800, n), k_q,
    ])  # fmt: skip
    if family == "full_stiff":
        p[:, 1] = 0.0
        p[:, 8] = np.exp(rng.uniform(np.log(1e-4), np.log(1e-2), n))
    return p


def kind(family: str) -> str:
    """The model of a family: ``reduced``, ``constrained``, ``full`` or ``full_constrained``."""
    if family in FAMILIES:
        return "reduced"
    if family in CONSTRAINED_FAMILIES:
        return "constrained"
    return "full_constrained" if family == "full_constrained" else "full"


def designs(family: str, seed: int, chunk_index: int, chunk: int) -> np.ndarray:
    """Chunk ``chunk_index`` (``chunk`` designs) of ``family``, seeded by all four."""
    rng = np.random.default_rng([seed, ALL_FAMILIES.index(family), chunk_index, chunk])
    return draw_full(family, rng, chunk) if family in FULL_FAMILIES else draw(family, rng, chunk)


def by_kernel(p: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """The kernel's unit-v_c rows ``(a_max, eps_max, f_max, t_imp)``, status codes and the
    number of self-check fallbacks (as :func:`designlab.impact.metrics_of_matrix`: the
    refused designs, and the open lobes that came near a_h's noise level, from
    extended-precision poles and residues, then the numpy path)."""
    rows, codes = kernel.reduced_metrics(p, (True, True, True), printed=False, stop_time=WINDOW,
                                         max_lobe_steps=MAX_STEPS, diagnostics=False)  # fmt: skip
    sus = np.flatnonzero(codes >= kernel.SUSPECT_POLES)
    _m.settle_suspects(p, NAMES, "correct", rows, codes, WINDOW, MAX_STEPS, False)
    return rows[:, :4], codes, int(sus.size)


def by_kernel_closed(p: np.ndarray, constrained: bool) -> tuple[np.ndarray, np.ndarray, int]:
    """The full joint, or a constrained impact, as :func:`designlab.impact.metrics_of_matrix`
    evaluates it: rows, status codes, and how many designs the compiled certificate
    (distinct poles, condition <= 1e4, backward error <= 1e-13) or the self-check sent to
    the eigen or numpy path."""
    names = ("force", "compression") if constrained else NAMES
    sel = tuple(k in names for k in NAMES)
    _, codes = kernel_full.full_metrics(p, sel, constrained=constrained, stop_time=WINDOW,
                                        max_lobe_steps=MAX_STEPS, diagnostics=False)  # fmt: skip
    fb = int(np.sum((codes == kernel_full.FALLBACK) | (codes >= kernel.SUSPECT_POLES)))
    m = _m._full_kernel(p, np.ones(p.shape[0]), names, constrained, WINDOW, MAX_STEPS, False)
    rows = np.stack([m.peak_head_acceleration, m.max_compression, m.peak_force,
                     m.impact_duration], axis=1)  # fmt: skip
    status = np.array([list(_m._KERNEL_STATUS).index(s) for s in m.design_status], np.int8)
    return rows, status, fb


def by_numpy(p: np.ndarray, constrained: bool) -> tuple[np.ndarray, np.ndarray]:
    """The numpy modal path's rows and status codes (the eigen-decomposition of the state
    space for the full joint)."""
    names = ("force", "compression") if constrained else NAMES
    resp = _m.ramp_responses(_m.response_model(p, constrained), p, names)
    poles = resp[names[0]].poles
    h = 0.4 / (grid_rate(poles) if p.shape[1] == 10 else np.abs(poles).max(axis=1))
    rows, codes = _m._numpy_rows(resp, h, constrained, WINDOW, MAX_STEPS, False)
    return rows[:, :4], codes


def by_fast(p: np.ndarray, model: str) -> tuple[np.ndarray, np.ndarray]:
    """The fast independent evaluator (``benchmarks/fuzz_fast.py``)."""
    import fuzz_fast

    return fuzz_fast.evaluate(p, model, WINDOW, MAX_STEPS)


def disagreements(a: np.ndarray, ca: np.ndarray, b: np.ndarray, cb: np.ndarray) -> np.ndarray:
    """Indices where the rows differ by more than :data:`DISAGREE` or the statuses differ."""
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(a == b, 0.0, np.abs(a - b) / np.abs(b))
    rel = np.where(np.isnan(a) & np.isnan(b), 0.0, rel)
    rel = np.where(np.isnan(rel), np.inf, rel)
    return np.flatnonzero((rel.max(axis=1) > DISAGREE) | (ca != cb))


def _horizon_rate(poles: list, full: bool) -> float:
    """The rate of the kernel's documented horizon (every pole; the full joint's real poles
    above ten times its fastest oscillatory one, or its slowest, left out)."""
    z = np.array([complex(x) for x in poles])
    return float(grid_rate(z[None, :])[0] if full else np.abs(z).max())


def referee(q: np.ndarray, rows: list[np.ndarray], model: str) -> tuple[np.ndarray, list[bool]]:
    """The 40-digit values ``(a_max, eps_max, f_max, t_imp)`` of design ``q`` and, for each of
    ``rows``, whether it is right (within :data:`TOLERANCE`; NaN right only where mpmath
    finds no lobe end before the latest t_imp claimed and the kernel's horizon). For a
    constrained model only eps_max and F_max over the window are compared."""
    from exact_reference import MpConstrained, MpFullJoint, MpImpact

    if model == "constrained":
        mp = MpConstrained(q, dps=40)
    elif model.startswith("full"):
        mp = MpFullJoint(q, dps=40, constrained=model == "full_constrained")
    else:
        mp = MpImpact(q, dps=40)
    if model in ("constrained", "full_constrained"):
        truth = np.array([np.nan, np.nan, np.nan, np.nan])
        truth[1:3] = [mp.maximum(o, WINDOW, samples=SAMPLES) for o in (2, 0)]
        cols = [1, 2]
        verdict = [bool(np.all(np.abs(r[cols] - truth[cols]) <= 1e-8 * np.abs(truth[cols])))
                   for r in rows]  # fmt: skip
        return truth, verdict
    poles = mp.lam if model == "full" else mp.poles
    horizon = ((MAX_STEPS // 12) * 12 + 11) * 0.4 / _horizon_rate(poles, model == "full")
    ends = [float(r[3]) for r in rows if np.isfinite(r[3])]
    t_hi = min(1.05 * max(ends), horizon) if ends else horizon
    t = mp.first_zero(t_hi, samples=SAMPLES)
    truth = np.array([np.nan, np.nan, np.nan, t])
    if np.isfinite(t):
        truth[:3] = [mp.maximum(o, t, samples=SAMPLES) for o in (1, 2, 0)]
    verdict = []
    for r in rows:
        if not np.isfinite(t):
            verdict.append(bool(np.all(np.isnan(r))))
            continue
        err = np.abs(r - truth) / np.abs(truth)
        verdict.append(bool(np.all(err <= np.array(TOLERANCE))))
    return truth, verdict


COUNTS = ("designs", "fallbacks", "disagreements", "kernel_wrong", "evaluator_wrong",
          "uncertified", "cpu_kernel", "cpu_evaluator", "cpu_mpmath")  # fmt: skip


def run_chunk(family: str, p: np.ndarray, evaluator: str, out: dict, log=print) -> list:  # type: ignore[no-untyped-def]
    """Fuzz the designs ``p`` of ``family`` into the tallies ``out``; returns the designs the
    kernel got wrong (each ``(params, kernel row, truth)``)."""
    model = kind(family)
    constrained = model in ("constrained", "full_constrained")
    t0 = time.process_time()
    a, ca, fb = by_kernel(p) if model == "reduced" else by_kernel_closed(p, constrained)
    t1 = time.process_time()
    b, cb = by_fast(p, model) if evaluator == "fast" else by_numpy(p, constrained)
    t2 = time.process_time()
    if constrained:  # a_h is 0 and the window fixed: eps_max and F_max carry the comparison
        a[:, [0, 3]] = b[:, [0, 3]] = np.nan
    out["cpu_kernel"] += t1 - t0
    out["cpu_evaluator"] += t2 - t1
    out["designs"] += p.shape[0]
    out["fallbacks"] += fb
    wrong = []
    for i in disagreements(a, ca, b, cb):
        out["disagreements"] += 1
        truth, (k_ok, e_ok) = referee(p[i], [a[i], b[i]], model)
        if ca[i] >= kernel.SUSPECT_POLES:  # said so (metrics NaN): not an error
            out["uncertified"] += 1
            k_ok = True
        out["kernel_wrong"] += not k_ok
        out["evaluator_wrong"] += not e_ok
        if not k_ok:
            wrong.append((p[i].tolist(), a[i].tolist(), truth.tolist()))
        kv, ev = ("right" if ok else "WRONG" for ok in (k_ok, e_ok))
        log(
            f"  {family} design {p[i].tolist()}: kernel {a[i].tolist()} status {ca[i]} ({kv}), "
            f"{evaluator} {b[i].tolist()} status {cb[i]} ({ev}), mpmath {truth.tolist()}"
        )
    out["cpu_mpmath"] += time.process_time() - t2
    return wrong


def run(family: str, n: int, seed: int, chunk: int, verbose: bool = True,
        evaluator: str = "fast", start_chunk: int = 0) -> dict:  # fmt: skip
    """Fuzz ``n`` designs of ``family`` (chunks from ``start_chunk``); the tallies."""
    out = dict.fromkeys(COUNTS, 0)
    out["wrong"] = []
    k = start_chunk
    while out["designs"] < n:
        p = designs(family, seed, k, chunk)[: n - out["designs"]]
        log = (lambda s: print(s, flush=True)) if verbose else (lambda s: None)
        out["wrong"] += run_chunk(family, p, evaluator, out, log)
        k += 1
    return out


def table(tallies: dict) -> list[str]:
    """The tally table (markdown) of ``{family: tallies}``, with a total row."""
    cols = ("designs", "kernel CPU s", "evaluator CPU s", "mpmath CPU s", "disagreements",
            "kernel wrong", "evaluator wrong", "uncertified", "self-check fallbacks")  # fmt: skip
    lines = ["| family | " + " | ".join(cols) + " |", "|---" * (len(cols) + 1) + "|"]
    total = dict.fromkeys(COUNTS, 0)
    for fam, r in [*tallies.items(), ("total", total)]:
        if fam != "total":
            for c in COUNTS:
                total[c] += r[c]
        lines.append(
            f"| {fam} | {r['designs']:,} | {r['cpu_kernel']:.0f} | {r['cpu_evaluator']:.0f} | "
            f"{r['cpu_mpmath']:.0f} | {r['disagreements']} | {r['kernel_wrong']} | "
            f"{r['evaluator_wrong']} | {r['uncertified']} | {r['fallbacks']} |"
        )
    return lines


def _cpu() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _markdown(path: str, state: dict, tallies: dict) -> int:
    """Write the tally table of a run (``state``: its arguments, chunks, times) to ``path``;
    returns how many designs the kernel got wrong."""
    lines = table(tallies)
    wrong = sum(t["kernel_wrong"] for t in tallies.values())
    a = state["args"]
    head = [
        f"Fuzz run of {state['when']}: `python benchmarks/fuzz_kernel.py {state['command']}` "
        f"({_chunks(state, len(tallies))}, chunks of {a['chunk']:,} designs, "
        f"seed {a['seed']}, evaluator `{a['evaluator']}`), one process on {_cpu()}, load "
        f"average {state['load_start']:.1f} at the start and {os.getloadavg()[0]:.1f} at the "
        f"end, {state['wall']:.0f} s wall time. CPU seconds are this process's.",
        "",
    ]
    tail = ["", f"Designs the kernel got wrong: {wrong}."]
    for f, t in tallies.items():
        for q, row, truth in t["wrong"]:
            tail.append(f"- {f}: {q}: kernel {row}, mpmath {truth}")
    Path(path).write_text("\n".join(head + lines + tail) + "\n")
    return wrong


def _chunks(state: dict, families: int) -> str:
    """The chunks a run covered, e.g. ``0-4`` or ``0-4 and chunk 5 for 3 of the 12 families``."""
    first, k, done = state["first_chunk"], state["next_chunk"], state.get("done", [])
    whole = f"{first}-{k - 1}" if k > first else ""
    if not done:
        return whole
    part = f"chunk {k} for {len(done)} of the {families} families"
    return f"{whole} and {part}" if whole else part


def _resume(
    path: str | None, args: argparse.Namespace, families: list[str], argv: list[str]
) -> tuple[dict, dict]:
    """The run's state and tallies: read from ``path`` where a run with the same seed, chunk
    size, evaluator and families saved them (a resumed run continues at its next chunk),
    else new."""
    keys = ("seed", "chunk", "evaluator", "designs")
    if path and Path(path).exists():
        state = json.loads(Path(path).read_text())
        same = all(state["args"][k] == getattr(args, k) for k in keys)
        if not same or list(state["tallies"]) != families:
            raise SystemExit(f"--state {path}: saved by a run with other arguments")
        return state, state.pop("tallies")
    state = {
        "args": {k: getattr(args, k) for k in keys},
        "command": " ".join(argv),
        "when": datetime.datetime.now(datetime.UTC).strftime("%d %B %Y, %H:%M UTC"),
        "first_chunk": args.start_chunk,
        "next_chunk": args.start_chunk,
        "done": [],
        "load_start": os.getloadavg()[0],
        "wall": 0.0,
    }
    return state, {f: {**dict.fromkeys(COUNTS, 0), "wrong": []} for f in families}


def _save(args: argparse.Namespace, state: dict, tallies: dict) -> None:
    """Write the state (``--state``, whole, then renamed: a kill leaves the last one) and
    the markdown table (``--markdown``)."""
    if args.state:
        tmp = Path(args.state + ".tmp")
        tmp.write_text(json.dumps({**state, "tallies": tallies}))
        tmp.replace(args.state)
    if args.markdown:
        _markdown(args.markdown, state, tallies)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=float, default=1e5, help="designs per family (at most)")
    ap.add_argument("--seed", type=int, default=34)
    ap.add_argument("--chunk", type=int, default=65_536, help="designs per chunk")
    ap.add_argument("--start-chunk", type=int, default=0, help="first chunk (resume, split)")
    ap.add_argument(
        "--seconds", type=float, default=np.inf, help="stop after the round in which time is up"
    )
    ap.add_argument("--families", default=",".join(ALL_FAMILIES))
    ap.add_argument("--evaluator", choices=("fast", "numpy"), default="fast")
    ap.add_argument("--markdown", help="write the tally table to this file (after every round)")
    ap.add_argument("--state", help="save the tallies here after every chunk; resume from it")
    ap.add_argument(
        "--report", action="store_true", help="only write --markdown from --state (no run)"
    )
    args = ap.parse_args(argv)
    families = args.families.split(",")
    for f in families:
        if f not in ALL_FAMILIES:
            ap.error(f"--families: unknown family {f!r}; known: {', '.join(ALL_FAMILIES)}")
    start = time.time()
    state, tallies = _resume(args.state, args, families, sys.argv[1:] if argv is None else argv)
    n = int(args.designs)
    wall0 = state["wall"]
    if args.report:
        return 1 if _markdown(args.markdown, state, tallies) else 0
    while time.time() - start < args.seconds and any(tallies[f]["designs"] < n for f in families):
        k = state["next_chunk"]
        for f in families:
            left = n - tallies[f]["designs"]
            if left > 0 and f not in state["done"]:
                p = designs(f, args.seed, k, args.chunk)[:left]
                tallies[f]["wrong"] += run_chunk(f, p, args.evaluator, tallies[f],
                                                 lambda s: print(s, flush=True))  # fmt: skip
            state["done"].append(f)
            state["wall"] = wall0 + time.time() - start
            _save(args, state, tallies)  # after every family's chunk: a kill loses at most one
        state["next_chunk"], state["done"] = k + 1, []
        _save(args, state, tallies)
        print(f"chunk {k} done: {sum(t['designs'] for t in tallies.values()):,} designs, "
              f"{state['wall']:.0f} s", flush=True)  # fmt: skip
    print("\n".join(table(tallies)))
    wrong = sum(t["kernel_wrong"] for t in tallies.values())
    if args.markdown:
        _markdown(args.markdown, state, tallies)
    return 1 if wrong else 0


if __name__ == "__main__":
    sys.exit(main())
