"""How a study's report reproduces on another machine: one declaration per kind.

A seeded study gives the same tables to the bit on the same machine and build. On
another CPU (or libm, numpy or numba build) the last bits of floating-point sums and
elementary functions differ, and what a study computes from them differs by as much as
its computation amplifies them. Each kind declares how far its tables may move
(:class:`Reproduction`, on :class:`~designlab.study.registry.StudyKind`); the report
framework states it in every report ("Reproduction on another machine"), and
``benchmarks/reproduce_reports.py`` reruns the committed studies as on a plain x86-64
CPU and checks every number of every table against the declaration (docs/developers.md,
"Reproduction on another machine").

Examples
--------
>>> r = Reproduction(rtol=2e-8, why="the impact kernel certifies each metric to 1e-8")
>>> r.close(1.0, 1.0 + 1e-8), r.close(1.0, 1.0 + 1e-7), r.close(1.0, 1.000001, digits=7)
(True, False, True)
>>> print(r.sentence(digits=7))  # doctest: +NORMALIZE_WHITESPACE
The same study file (with its seeds) on the same machine and build gives these tables to
the bit. On another CPU (or libm, numpy or numba build) every number in its CSV tables reproduces
within |a - b| <= 2e-08 max(|a|, |b|) (the impact kernel certifies each metric to 1e-8),
give or take one unit in the last of the 7 significant digits printed; text cells are
identical.
"""

from __future__ import annotations

import fnmatch
import functools
import json
import math
from dataclasses import dataclass
from importlib import resources

__all__ = [
    "CERTIFIED_IMPACT",
    "CH3_CLAIMS",
    "CLOSED_FORM",
    "CODESIGN",
    "CONVERGENCE_MAP",
    "CROWD_TUNING",
    "ENVELOPE",
    "HEADING",
    "METRIC_DIFFERENCES",
    "NOISE_AROUND_ZERO",
    "SAME_ON_A_GENERIC_CPU",
    "TUNED_GAINS",
    "UNCHECKED",
    "Reproduction",
]

#: The heading of the section every report carries (written by the report framework
#: unless the kind's writer words its own, as the gain searches do).
HEADING = "## Reproduction on another machine"


@dataclass(frozen=True)
class Reproduction:
    """How far a kind's report tables may move on another machine.

    A number ``b`` regenerated elsewhere matches the committed ``a`` when
    ``|a - b| <= atol + rtol * max(|a|, |b|)``; two NaN cells match; text cells must
    be identical. Columns matching one of ``exempt`` (``"file.csv:column"`` glob
    patterns) are not compared: they hold what the report says does not reproduce
    digit for digit (a flat optimum's arguments), and ``why`` says so.

    Parameters
    ----------
    rtol, atol
        Relative and absolute tolerance of every numeric cell.
    why
        Where the tolerance comes from (the computation's certificate or the
        amplification measured), quoted in the report.
    exempt
        ``file:column`` glob patterns of cells not compared.
    checked
        ``False``: how far the tables move on another machine has not been
        measured yet (the report says so instead of claiming a tolerance).
    flips
        The largest fraction of a table's rows whose discrete outcome (a text or
        yes/no cell: converged, collided, status) may change: a design on the edge
        of a verdict can fall either side of it. Such rows are not compared further.
    measured
        The study (report name) whose rerun ``benchmarks/reproduce_reports.py --record``
        measured the figures ``why`` quotes (``designlab/data/reproduction.json``).
    figures
        ``(field, statistic, "file:column" glob)`` of each ``{field}`` in ``why``:
        ``abs`` / ``rel`` the largest absolute / relative difference of those columns,
        ``first`` the first row (counted from 1) where one differs, ``flips`` and
        ``rows`` the rows whose verdict changed and all rows. No measured number is
        typed into ``why``.
    """

    rtol: float = 0.0
    atol: float = 0.0
    why: str = ""
    exempt: tuple[str, ...] = ()
    flips: float = 0.0
    checked: bool = True
    measured: str = ""
    figures: tuple[tuple[str, str, str], ...] = ()

    def __post_init__(self) -> None:
        if not 0.0 <= self.flips <= 1.0:
            raise ValueError(f"Reproduction.flips = {self.flips!r} must be within [0, 1]")
        for name in ("rtol", "atol"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f"Reproduction.{name} = {value!r} must be finite and >= 0")

    def close(self, a: float, b: float, digits: int | None = None) -> bool:
        """Whether ``b`` reproduces ``a`` within the tolerances (NaN matches NaN).

        Parameters
        ----------
        a, b
            The committed and the regenerated value.
        digits
            Significant digits the values were printed with: a flip of the last
            printed digit (one unit in it) is allowed on top of the tolerances.
        """
        if math.isnan(a) or math.isnan(b):
            return math.isnan(a) and math.isnan(b)
        if math.isinf(a) or math.isinf(b):
            return a == b
        big = max(abs(a), abs(b))
        printed = 0.0
        if digits is not None and big > 0.0:
            printed = 10.0 ** (math.floor(math.log10(big)) - digits + 1) * (1 + 1e-9)
        return abs(a - b) <= self.atol + self.rtol * big + printed

    def exempts(self, file: str, column: str) -> bool:
        """Whether ``file:column`` is one of the cells not compared."""
        return any(fnmatch.fnmatchcase(f"{file}:{column}", p) for p in self.exempt)

    def bound(self) -> str:
        """The tolerance as a formula, e.g. ``|a - b| <= 1e-12 + 2e-08 max(|a|, |b|)``."""
        if self.rtol == 0.0 and self.atol == 0.0:
            return "a = b (to the bit)"
        terms = []
        if self.atol:
            terms.append(f"{self.atol:g}")
        if self.rtol:
            terms.append(f"{self.rtol:g} max(|a|, |b|)")
        return "|a - b| <= " + " + ".join(terms)

    def explanation(self) -> str:
        """``why`` with its figures filled in from the recorded rerun (:attr:`measured`)."""
        if not self.figures:
            return self.why
        record = measured_figures().get(self.measured)
        if record is None:
            raise ValueError(
                f"Reproduction: no recorded rerun of {self.measured!r} in {_FIGURES} "
                "(benchmarks/reproduce_reports.py --record)"
            )
        return self.why.format(**{f: _figure(record, stat, cols) for f, stat, cols in self.figures})

    def sentence(self, digits: int | None = None) -> str:
        """The report's statement (one paragraph).

        Parameters
        ----------
        digits
            Significant digits of the report's CSV numbers (a flip of the last one
            is allowed, :meth:`close`).
        """
        if not self.checked:
            return (
                "The same study file (with its seeds) on the same machine and build gives "
                "these tables to the bit. How far they move on another CPU (or libm, numpy "
                "or numba build) has not been measured yet (docs/developers.md, "
                "'Reproduction on another machine')."
            )
        same = self.bound() == "a = b (to the bit)"
        text = (
            "The same study file (with its seeds) on the same machine and build gives these "
            "tables to the bit. On another CPU (or libm, numpy or numba build) every number "
            "in its CSV tables "
            + ("is the same to the bit" if same else f"reproduces within {self.bound()}")
        )
        if self.why:
            text += f" ({self.explanation()})"
        if digits is not None and self.bound() != "a = b (to the bit)":
            text += (
                f", give or take one unit in the last of the {digits} significant digits printed"
            )
        if self.flips:
            text += (
                f"; a row's verdict (a text or yes/no cell) may change in at most "
                f"{self.flips:.2g} of a table's rows, on the edge of the verdict, and such "
                "rows are not compared further; other text cells are identical"
            )
        else:
            text += "; text cells are identical"
        if self.exempt:
            text += f", except {', '.join(self.exempt)}, which are not compared"
        return text + "."


#: The figures measured by reruns as on a plain x86-64 CPU (written by
#: ``benchmarks/reproduce_reports.py --record``; read by :meth:`Reproduction.explanation`)
_FIGURES = "reproduction.json"


@functools.cache
def measured_figures() -> dict[str, dict]:
    """The recorded reruns: report name -> ``{"rows", "flips", "columns": {"file:column":
    {"abs", "rel", "first"}}, ...}`` (``designlab/data/reproduction.json``)."""
    text = resources.files("designlab.data").joinpath(_FIGURES).read_text(encoding="utf-8")
    return dict(json.loads(text))


def _figure(record: dict, stat: str, columns: str) -> str:
    """One figure of a recorded rerun, printed as the statements print it."""
    if stat in ("flips", "rows"):
        return f"{int(record[stat]):,}"
    cols = [v for k, v in record["columns"].items() if fnmatch.fnmatchcase(k, columns)]
    if not cols:
        raise ValueError(f"Reproduction: no recorded column matches {columns!r}")
    if stat == "first":
        return f"{min(int(c['first']) for c in cols if c['first'] is not None):,}"
    mantissa, exponent = f"{max(float(c[stat]) for c in cols):.0e}".split("e")
    return f"{mantissa}e{int(exponent)}"


#: Kinds not yet rerun as on another machine: the report says so, claiming no tolerance.
UNCHECKED = Reproduction(checked=False)

#: Kinds whose numbers are impact metrics of the certified kernel (docs/impact.md).
CERTIFIED_IMPACT = Reproduction(
    rtol=2e-8,
    atol=1e-12,
    why=(
        "each impact metric is certified to 1e-8 relative (docs/impact.md, 'Self-check'), "
        "so two machines differ by at most twice that; a value that is rounding noise "
        "around zero moves within 1e-12"
    ),
)

#: Kinds that solve for the boundaries of the feasible foam region (docs/impact.md).
ENVELOPE = Reproduction(
    rtol=2e-6,
    atol=1e-12,
    why=(
        "the region's boundaries are solved to 1e-6 relative (docs/impact.md, 'Foam "
        "design'), and the search may stop on either side of that on another machine; "
        "the metrics are certified to 1e-8"
    ),
)

#: Kinds of closed-form expressions only.
CLOSED_FORM = Reproduction(
    rtol=1e-12,
    atol=1e-12,
    why="closed-form expressions: a few rounding errors each",
)

#: The reduced joint against the full joint: relative errors between certified metrics.
METRIC_DIFFERENCES = Reproduction(
    rtol=2e-8,
    atol=2e-8,
    why=(
        "each impact metric is certified to 1e-8 relative (docs/impact.md, 'Self-check'); "
        "a relative error between two of them moves by at most 2e-8"
    ),
)

#: Kinds whose every number was the same to the bit when rerun with the code paths of a
#: plain x86-64 CPU (``benchmarks/reproduce_reports.py``).
SAME_ON_A_GENERIC_CPU = Reproduction(
    why=(
        "rerun with the code paths of a plain x86-64 CPU (numba, libm and numpy without "
        "their AVX2, FMA and AVX-512 variants), every number was identical"
    ),
)

#: Kinds with quantities that are rounding noise around zero (the tether modes' offsets).
NOISE_AROUND_ZERO = Reproduction(
    atol=1e-12,
    why=(
        "rerun with the code paths of a plain x86-64 CPU, every number was identical "
        "but those that are rounding noise around zero, which moved by {noise} m; they "
        "move within 1e-12"
    ),
    measured="tether_modes",
    figures=(("noise", "abs", "*"),),
)

#: The accompanying robot: PID gains tuned by a Nelder-Mead search (docs/following.md).
TUNED_GAINS = Reproduction(
    rtol=1e-6,
    atol=1e-8,
    why=(
        "the PID gains are tuned by a Nelder-Mead search (docs/following.md), which ends "
        "a little elsewhere within its tolerances on another machine; rerun with the code "
        "paths of a plain x86-64 CPU, the gains moved by {gains} relative"
    ),
    measured="accompanying",
    figures=(("gains", "rel", "margins.csv:k[pid]"),),
)

#: Co-design: certified impact figures, and an evolutionary search that is not reproducible.
CODESIGN = Reproduction(
    rtol=2e-8,
    atol=1e-12,
    why=(
        "the speed limits and injury figures are certified impact metrics (docs/impact.md, "
        "'Self-check'); the evolutionary search is not reproducible design for design: its "
        "selections turn on last-bit ties, and rerun with the code paths of a plain x86-64 "
        "CPU it found a different archive and front (docs/codesign.md)"
    ),
    exempt=("designs.csv:*", "front.csv:*"),
)

#: The tether stability map: a convergence verdict per grid point (docs/following.md).
CONVERGENCE_MAP = Reproduction(
    atol=1e-12,
    flips=1e-3,
    why=(
        "a grid point's verdict is whether the follower settles within the simulated time; "
        "one on that edge can fall either side: rerun with the code paths of a plain "
        "x86-64 CPU, {flips} of {rows} rows changed verdict, and every other number was "
        "identical but rounding noise around zero, which moved by {noise}"
    ),
    measured="tether_stability",
    figures=(("flips", "flips", ""), ("rows", "rows", ""), ("noise", "abs", "*")),
)

#: Crowd runs with gains tuned by a seeded search (docs/navigation_crowds.md).
CROWD_TUNING = Reproduction(
    why=(
        "rerun with the code paths of a plain x86-64 CPU, every number of the runs' tables "
        "was identical; the gain search's history is not reproducible evaluation for "
        "evaluation: its proposals turn on last-bit ties, and there it took another path "
        "from evaluation {first} on (an evaluated outcome differed from evaluation "
        "{outcome} on)"
    ),
    exempt=("tuning_history.csv:*",),
    measured="vff_crowds",
    figures=(
        ("first", "first", "tuning_history.csv:k[135]"),
        ("outcome", "first", "tuning_history.csv:*"),
    ),
)

#: The Ch. 3 claims: certified metrics, and the lever arm where a maximum is reached.
CH3_CLAIMS = Reproduction(
    rtol=2e-8,
    atol=1e-12,
    why=(
        "each impact metric is certified to 1e-8 relative (docs/impact.md, 'Self-check'); "
        "the lever arm at which a maximum over the arm is reached is not: a smooth maximum "
        "is flat, so its argument is known only to about the square root of that (it "
        "moved by {lever} relative on a plain x86-64 CPU)"
    ),
    exempt=("fig_3_16.csv:worst_l_m",),
    measured="zeng_ch3_claims",
    figures=(("lever", "rel", "fig_3_16.csv:worst_l_m"),),
)
