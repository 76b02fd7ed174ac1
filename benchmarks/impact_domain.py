"""The larger run of tests/impact/test_impact_domain.py: admitted impact designs are right.

Draws designs log-uniformly over the whole declared box (to each declared upper bound; to
1e20 where a declaration has none) and within a factor 30 of the typical ranges, for the
reduced joint and the full series joint. Every design is either refused by the time-scale
bound (``designlab.impact.conditioning``; docs/impact.md, "Limits") or its first-lobe metrics
are compared with a 50-digit evaluation (tests/impact/mp_reference.py) against the declared
accuracy. Prints the counts and the largest error in units of the tolerance (must be <= 1);
lists every design beyond it.

Usage::

    python benchmarks/impact_domain.py --designs 400 --seed 1
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests" / "impact"))

from mp_reference import MpImpact

import designlab as dl
from designlab.errors import InvalidParameterError, ModelError
from designlab.impact.full_joint_model import FULL_PARAM_NAMES
from designlab.impact.metrics import impact_metrics
from designlab.impact.model import PARAM_NAMES
from designlab.params import params_of

RTOL, NOISE, UNBOUNDED, V_C = 1e-8, 1e-12, 1e20, 1.25


def _decls(full: bool) -> list:
    cd, foam, head = (params_of(c) for c in (dl.impact.ContactDynamics, dl.impact.Foam,
                                             dl.impact.HeadNeck))  # fmt: skip
    fj = params_of(dl.impact.FullJointContact)
    red = [cd["mass"], cd["damping"], cd["stiffness"], foam["stiffness"], foam["damping"],
           head["mass"], head["damping"], head["stiffness"]]  # fmt: skip
    if not full:
        return red
    return [fj["mass"], fj["transmission_damping"], fj["transmission_stiffness"], *red[3:],
            fj["control_damping"], fj["control_stiffness"]]  # fmt: skip


def _draw(rng: np.random.Generator, decls: list, whole: bool) -> list[float]:
    out = []
    for d in decls:
        upper = d.le if d.le is not None else UNBOUNDED
        low, high = d.typical if d.typical is not None else (1.0, 1e4)
        low = max(low, 1e-2)
        if whole:
            lo, hi = math.log10(low) - 3, math.log10(upper)
        else:
            lo, hi = math.log10(low / 30), math.log10(min(high * 30, upper))
        zero = d.ge == 0 and rng.random() < 1 / 8
        out.append(0.0 if zero else float(10 ** rng.uniform(lo, hi)))
    if len(out) == 10 and out[1] + out[8] == 0:
        out[8] = 1.0
    return out


def _score(p: list[float]) -> tuple[str, float]:
    names = FULL_PARAM_NAMES if len(p) == 10 else PARAM_NAMES
    try:
        m = impact_metrics([p], V_C, columns=names)
    except InvalidParameterError as err:
        return ("refused" if "time scales span" in str(err) else f"other: {err}"), 0.0
    except ModelError:
        return "no restoring stiffness", 0.0
    status = str(m.design_status[0])
    if status not in ("ok", "peak_at_contact"):
        return status, 0.0
    ref = MpImpact(p, V_C)
    exact = ref.metrics()
    tol = ref.tolerances(exact, RTOL, NOISE)
    got = {"t_imp": m.impact_duration[0], "a_max": m.peak_head_acceleration[0],
           "eps_max": m.max_compression[0], "f_max": m.peak_force[0]}  # fmt: skip
    return "checked", max(abs(float(got[k]) - exact[k]) / tol[k] for k in got)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=200, help="designs per family and box")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    worst = 0.0
    for full in (False, True):
        for whole in (True, False):
            counts: dict[str, int] = {}
            start = time.perf_counter()
            for _ in range(args.designs):
                p = _draw(rng, _decls(full), whole)
                kind, score = _score(p)
                counts[kind] = counts.get(kind, 0) + 1
                worst = max(worst, score)
                if score > 1:
                    print(f"  beyond the declared accuracy ({score:.3g} x): {p}")
            label = (
                f"{'full joint' if full else 'reduced':10} {'whole box' if whole else 'typical':9}"
            )
            print(f"{label} {counts} ({time.perf_counter() - start:.0f} s)")
    print(f"largest error / tolerance: {worst:.3g}")


if __name__ == "__main__":
    main()
