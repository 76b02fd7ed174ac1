"""Do the committed reports reproduce on another machine? Rerun the studies as on a plain CPU.

Run from the repository root::

    python benchmarks/reproduce_reports.py codesign tether_modes # these studies
    python benchmarks/reproduce_reports.py                       # all but the gain searches
    python benchmarks/reproduce_reports.py --all                 # all of them (about 2 h)
    python benchmarks/reproduce_reports.py --native foam_design  # this CPU, to the bit
    python benchmarks/reproduce_reports.py --record accompanying # and keep its figures

Each study of ``studies/`` is run again (``designlab run``) in a subprocess whose
compiled and library code paths are those of a plain x86-64 CPU: numba compiles for a
generic CPU (in a cache of its own), glibc's libm and numpy leave out their AVX2, FMA
and AVX-512 variants. That is what changes when the same build runs on another CPU
(docs/developers.md, "Reproduction on another machine"). Every CSV table of the new
report is then compared with the committed one under the tolerances its kind declares
(:class:`designlab.study.reproduction.Reproduction`, on the kind's ``StudyKind``; each
report states them): same columns and rows, text cells identical, every number within
``atol + rtol max(|a|, |b|)``. Printed per study: tables, numeric cells, the largest
absolute and relative difference, the declared bound and the verdict. With ``--native``
the rerun uses this CPU and the claim checked is "to the bit". With ``--record`` the figures
of each rerun (per column: largest absolute and relative difference, first row that
differs; rows whose verdict changed) are written to ``designlab/data/reproduction.json``,
from which the reports' statements quote what was measured (no measured number is typed
into them); ``--reruns DIR`` compares reruns already made there instead of running.

The exit status is 1 if a study does not reproduce within its declaration or fails to run.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # this checkout's designlab

from designlab.report.writers import csv_digits  # noqa: E402
from designlab.study import load_study  # noqa: E402
from designlab.study.registry import kind_of  # noqa: E402
from designlab.study.reproduction import Reproduction  # noqa: E402

#: A plain x86-64 CPU for the code that dispatches on the host's instruction set: numba's
#: kernels, glibc's libm (its FMA/AVX2 variants of exp, sin, pow...), numpy's SIMD loops.
GENERIC_CPU = {
    "NUMBA_CPU_NAME": "generic",
    "GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX2,-FMA,-AVX512F,-AVX512DQ,-AVX512VL",
    "NPY_DISABLE_CPU_FEATURES": "X86_V3 X86_V4 AVX512_ICL AVX512_SPR",
}


#: The figures of the reruns (``--record``), which the reports' statements quote
#: (:class:`designlab.study.reproduction.Reproduction`, ``measured``)
RECORD = ROOT / "designlab" / "data" / "reproduction.json"

#: Kinds whose runs are long optimisations (about an hour together on a quiet 2-core
#: machine); their reports word their own statement (flat optima). Left out unless named
#: or ``--all``.
LONG_KINDS = ("navigation_gains", "tether_tuning")


def _rerun(study: Path, out: Path, cache: Path, native: bool) -> tuple[int, str]:
    env = {**os.environ, "DESIGNLAB_CACHE_DIR": str(cache), "MPLBACKEND": "Agg"}
    env.pop("NUMBA_CACHE_DIR", None)
    if not native:
        env.update(GENERIC_CPU)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), env.get("PYTHONPATH", "")])
    cmd = [sys.executable, "-m", "designlab", "run", str(study), "-o", str(out)]
    done = subprocess.run(cmd, env=env, capture_output=True, text=True, cwd=out, check=False)
    return done.returncode, done.stderr[-1500:]


def _numeric(s: pd.Series) -> pd.Series | None:
    values = pd.to_numeric(s, errors="coerce")
    blank = s.astype(str).str.strip().isin(["", "nan", "NaN"])
    return values if (values.notna() | blank).all() else None


def column_figures(a: pd.DataFrame, b: pd.DataFrame, name: str) -> dict:
    """Per numeric column ``file:column`` of two tables of the same shape: the largest
    absolute and relative difference, leaving out rows whose verdict (a text cell)
    changed, and the first row (from 1) where they differ (None where they do not);
    exempt columns included (what the statements quote)."""
    out = {}
    numeric = {c: (_numeric(a[c]), _numeric(b[c])) for c in a.columns}
    flipped = np.zeros(len(a), bool)
    for col, (x, y) in numeric.items():
        if x is None or y is None:
            flipped |= (a[col].astype(str) != b[col].astype(str)).to_numpy()
    for col, (x, y) in numeric.items():
        if x is None or y is None:
            continue
        xa, ya = x.to_numpy(float), y.to_numpy(float)
        same = (xa == ya) | (np.isnan(xa) & np.isnan(ya))
        both = np.isfinite(xa) & np.isfinite(ya) & ~flipped
        d = np.abs(xa[both] - ya[both])
        scale = np.maximum(np.abs(xa), np.abs(ya))[both]
        rel = np.divide(d, scale, out=np.zeros_like(d), where=scale > 0)
        first = int(np.argmin(same)) + 1 if not same.all() else None
        out[f"{name}:{col}"] = {
            "abs": float(d.max()) if d.size else 0.0,
            "rel": float(rel.max()) if rel.size else 0.0,
            "first": first,
        }
    return out


def compare_table(a: pd.DataFrame, b: pd.DataFrame, name: str, rule: Reproduction) -> dict:
    """Largest differences of table ``b`` from ``a`` and the cells outside ``rule``."""
    out = {"cells": 0, "abs": 0.0, "rel": 0.0, "bad": [], "flips": 0, "rows": len(a)}
    if list(a.columns) != list(b.columns) or len(a) != len(b):
        out["bad"].append(f"{name}: shape {a.shape} -> {b.shape} or columns differ")
        return out
    columns = [c for c in a.columns if not rule.exempts(name, str(c))]
    numeric = {c: (_numeric(a[c]), _numeric(b[c])) for c in columns}
    text = [c for c in columns if numeric[c][0] is None or numeric[c][1] is None]
    flipped = np.zeros(len(a), bool)
    for col in text:
        flipped |= (a[col].astype(str) != b[col].astype(str)).to_numpy()
    out["flips"] = int(flipped.sum())
    if flipped.sum() > rule.flips * len(a):
        rows = np.flatnonzero(flipped)
        out["bad"] += [f"{name}: verdict changed in {flipped.sum()} rows (first {rows[:3]})"]
    for col in columns:
        if col in text:
            continue
        x, y = numeric[col]
        xa, ya = x.to_numpy(float)[~flipped], y.to_numpy(float)[~flipped]
        out["cells"] += len(xa)
        both = np.isfinite(xa) & np.isfinite(ya)
        d = np.abs(xa[both] - ya[both])
        if d.size:
            scale = np.maximum(np.abs(xa), np.abs(ya))[both]
            out["abs"] = max(out["abs"], float(d.max()))
            rel = np.divide(d, scale, out=np.zeros_like(d), where=scale > 0)
            out["rel"] = max(out["rel"], float(rel.max()))
        digits = None if rule.bound() == "a = b (to the bit)" else csv_digits()
        bad = [i for i in range(len(xa)) if not rule.close(xa[i], ya[i], digits)]
        out["bad"] += [f"{name}:{col} row {i}: {xa[i]!r} -> {ya[i]!r}" for i in bad[:3]]
    return out


def compare_report(old: Path, new: Path, rule: Reproduction) -> dict:
    """Compare every CSV table of the committed report ``old`` with ``new``; also the
    figures of every column (:func:`column_figures`) under ``"columns"``."""
    total = {"tables": 0, "cells": 0, "abs": 0.0, "rel": 0.0, "bad": [], "flips": 0, "rows": 0}
    total["columns"] = {}
    for csv in sorted(old.glob("*.csv")):
        other = new / csv.name
        if not other.is_file():
            total["bad"].append(f"{csv.name}: missing")
            continue
        read = {"keep_default_na": False, "dtype": str}
        a, b = pd.read_csv(csv, **read), pd.read_csv(other, **read)
        if a.shape == b.shape and list(a.columns) == list(b.columns):
            total["columns"].update(column_figures(a, b, csv.name))
        if rule.exempts(csv.name, "*"):  # the whole table is not compared
            continue
        got = compare_table(a, b, csv.name, rule)
        total["tables"] += 1
        total["rows"] += got["rows"]
        total["cells"] += got["cells"]
        total["flips"] += got["flips"]
        total["abs"], total["rel"] = max(total["abs"], got["abs"]), max(total["rel"], got["rel"])
        total["bad"] += got["bad"]
    return total


def _studies(args: argparse.Namespace) -> list[Path]:
    paths = sorted((ROOT / "studies").glob("*.yaml"))
    if args.studies:
        chosen = {Path(s).stem for s in args.studies}
        return [p for p in paths if p.stem in chosen]
    if args.all:
        return paths
    return [p for p in paths if load_study(p).kind not in LONG_KINDS]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("studies", nargs="*", help="study names (default: all but LONG_KINDS)")
    ap.add_argument("--all", action="store_true", help="every study of studies/")
    ap.add_argument("--native", action="store_true", help="rerun on this CPU (to the bit)")
    ap.add_argument("--reruns", help="compare the reruns already in this directory (no run)")
    ap.add_argument("--record", action="store_true", help=f"write the figures to {RECORD}")
    args = ap.parse_args()
    work = Path(args.reruns) if args.reruns else Path(tempfile.mkdtemp(prefix="designlab-repro-"))
    record = json.loads(RECORD.read_text()) if RECORD.is_file() else {}
    failed = 0
    head = ("study", "tables", "cells", "flips", "max |a-b|", "max rel")
    print("{:28} {:>6} {:>7} {:>5} {:>10} {:>9}  verdict".format(*head))
    for study in _studies(args):
        name = load_study(study).name
        kind = kind_of(load_study(study).kind)
        rule = Reproduction() if args.native else kind.reproduction
        start = time.perf_counter()
        code, err = (0, "") if args.reruns else _rerun(study, work, work / "cache", args.native)
        if code != 0:
            failed += 1
            print(f"{name:28} run failed ({code}): {err.strip().splitlines()[-1:]}")
            continue
        got = compare_report(ROOT / "reports" / name, work / name, rule)
        if args.record and not args.native:
            record[name] = _figures(got, work / name)
        ok = not got["bad"]
        failed += not ok
        verdict = "within " + rule.bound() if ok else f"OUTSIDE {rule.bound()}"
        row = (name, got["tables"], got["cells"], got["flips"], got["abs"], got["rel"])
        print("{:28} {:6d} {:7d} {:5d} {:10.3g} {:9.3g}".format(*row), end="  ")
        print(f"{verdict}  ({time.perf_counter() - start:.0f} s)")
        for line in got["bad"][:6]:
            print(f"    {line}")
    print(f"(reruns in {work}; {'this CPU' if args.native else 'a generic x86-64 CPU'})")
    if args.record and not args.native:
        RECORD.write_text(json.dumps(record, indent=1, sort_keys=True) + "\n")
        print(f"figures written to {RECORD.relative_to(ROOT)}")
    return 1 if failed else 0


def _figures(got: dict, rerun: Path) -> dict:
    """What :data:`RECORD` keeps of a study's comparison (the statements quote it)."""
    when = time.strftime("%Y-%m-%d", time.gmtime(rerun.stat().st_mtime))
    keep = ("tables", "cells", "rows", "flips", "abs", "rel", "columns")
    return {"rerun": when, "cpu": "generic x86-64", **{k: got[k] for k in keep}}


if __name__ == "__main__":
    sys.exit(main())
