"""How a long solver tells its caller how far it has got (the library never prints).

An optimiser, a tuner or a batch loop takes ``progress: ProgressHook | None``
and calls it with a :class:`Progress` after each step (a generation, a
candidate, a scenario). The study runner turns the calls into a tqdm bar on
stderr (:meth:`designlab.study.runner.RunContext.bar`); a program can log them.

Examples
--------
>>> seen = []
>>> def solver(progress=None):
...     for gen in range(3):
...         report(progress, Progress(step=gen + 1, total=3, best=1.0 / (gen + 1),
...                                   label="generation"))
>>> solver(seen.append)
>>> [(p.step, round(p.best, 2)) for p in seen]
[(1, 1.0), (2, 0.5), (3, 0.33)]
>>> solver()  # no hook: nothing happens
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

__all__ = ["Progress", "ProgressHook", "report"]


@dataclass(frozen=True)
class Progress:
    """One step of a long computation.

    Attributes
    ----------
    step
        Steps done so far (1-based count).
    total
        Steps expected in all (``None`` when not known in advance).
    best
        The best objective found so far (``None`` when there is none).
    label
        What a step is (``"generation"``, ``"scenario"``, ``"path"``).
    note
        A short text for the bar (the current item's name), or ``""``.
    """

    step: int
    total: int | None = None
    best: float | None = None
    label: str = "step"
    note: str = ""


#: A callable that receives each :class:`Progress`.
ProgressHook = Callable[[Progress], None]


def report(hook: ProgressHook | None, info: Progress) -> None:
    """Call ``hook(info)`` if there is a hook.

    Parameters
    ----------
    hook
        The caller's hook, or ``None``.
    info
        The step just finished.
    """
    if hook is not None:
        hook(info)
