"""One palette for the reports' figures: a colour per method, start and goal markers.

A navigation method (:data:`designlab.navigation.methods.METHODS`) or a tether law
(:data:`designlab.following.tether.laws.registry.LAWS`) has one colour, the same in every figure
of every report: the registry's order picks it from :data:`PALETTE` (nine distinct
colours, the grey of obstacles and walls left out), so two methods of one family never
share a colour. Two runs of one method in one figure (the new VFF with and without its
stabilising force) share the colour and differ by line style (:class:`MethodStyles`).

Examples
--------
>>> method_colour("vff") == PALETTE[0], method_colour("Ge & Cui") == method_colour("ge_cui")
(True, True)
>>> len({method_colour(m) for m in ("vff", "masoud", "ge_cui", "cbf", "vo", "nlvo")})
6
>>> styles = MethodStyles()
>>> styles("vff"), styles("vff"), styles("masoud")["ls"]
({'color': '#1f77b4', 'ls': '-'}, {'color': '#1f77b4', 'ls': '--'}, '-')
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = [
    "LINESTYLES",
    "PALETTE",
    "MethodStyles",
    "law_colour",
    "method_colour",
    "method_key",
    "start_and_goal",
]

#: Matplotlib's ``tab10`` without its grey: nine colours told apart in print and on screen.
PALETTE: tuple[str, ...] = (
    "#1f77b4",  # blue
    "#ff7f0e",  # orange
    "#2ca02c",  # green
    "#d62728",  # red
    "#9467bd",  # purple
    "#8c564b",  # brown
    "#e377c2",  # pink
    "#bcbd22",  # olive
    "#17becf",  # cyan
)

#: Line styles of repeated runs of one method in one figure, in turn.
LINESTYLES: tuple[str, ...] = ("-", "--", "-.", ":")

#: The colour of a run whose method is not in a registry (a user's own label).
OTHER = "#000000"


def _registries() -> list[Any]:
    from designlab.following.tether.laws.registry import LAWS
    from designlab.navigation.methods import METHODS

    return [METHODS, LAWS]


def method_key(label: str) -> tuple[int, int] | None:
    """``(registry, position)`` of the method or law named or labelled ``label``.

    A registry name (``"ge_cui"``), its report label (``"Ge & Cui"``), its short name
    (``"FTL"``) or a label that starts with a report label followed by a space, ``*`` or
    ``+`` (``"New VFF + F_L"``, ``"Masoud* K3=48"``) all find the method; the longest
    matching label wins (``"New VFF + CBF"`` is ``vff_cbf``, not ``vff``).

    Parameters
    ----------
    label
        A name or label of a run.

    Returns
    -------
    tuple of int or None
        The registry (0: navigation methods, 1: tether laws) and the method's position in
        it; ``None`` for a label of no registered method.
    """
    best: tuple[int, int, int] | None = None  # (length matched, registry, position)
    for r, registry in enumerate(_registries()):
        for i, name in enumerate(registry.choices()):
            variant = registry.get(name)
            names = {name, getattr(variant, "label", name), getattr(variant, "short", name)}
            for n in names:
                exact = label == n
                prefix = label.startswith(n) and label[len(n) : len(n) + 1] in (" ", "*", "+")
                if (exact or prefix) and (best is None or len(n) > best[0]):
                    best = (len(n) + (1000 if exact else 0), r, i)
    return None if best is None else (best[1], best[2])


def method_colour(label: str) -> str:
    """The colour of a navigation method or tether law (:func:`method_key`), else black.

    Parameters
    ----------
    label
        A name or label of a run.
    """
    key = method_key(label)
    return OTHER if key is None else PALETTE[key[1] % len(PALETTE)]


def law_colour(label: str) -> str:
    """The colour of a tether law: :func:`method_colour` (one palette for both families).

    Parameters
    ----------
    label
        A law's name, label or short name.
    """
    return method_colour(label)


class MethodStyles:
    """Colour and line style of each run of one figure: the method's colour, a new line
    style for each further run of the same method."""

    def __init__(self) -> None:
        self._seen: dict[str, int] = {}

    def __call__(self, label: str) -> dict[str, str]:
        """``{"color": ..., "ls": ...}`` for the next run labelled ``label``.

        Parameters
        ----------
        label
            A name or label of the run (:func:`method_key`).
        """
        colour = method_colour(label)
        n = self._seen.get(colour, 0)
        self._seen[colour] = n + 1
        return {"color": colour, "ls": LINESTYLES[n % len(LINESTYLES)]}


def start_and_goal(ax: Axes, start: Any, goal: Any, *, colour: str = "k") -> None:
    """Mark the start (a circle) and the goal (a star) with legend entries.

    Parameters
    ----------
    ax
        The axes of a path plot.
    start, goal
        ``(x, y)`` in m.
    colour
        The markers' colour (white on a dark map).
    """
    ax.plot(*start, "o", color=colour, mec="k", ms=6, ls="none", label="start")
    ax.plot(*goal, "*", color=colour, mec="k", ms=11, ls="none", label="goal")
