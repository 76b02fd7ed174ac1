"""How a long solver tells its caller how far it has got (the library never prints).

An optimiser, a tuner or a batch loop takes ``progress: ProgressHook | None``
and calls it with a :class:`Progress` after each step (a generation, a
candidate, a scenario). The study runner turns the calls into a tqdm bar on
stderr (:meth:`designlab.study.runner.RunContext.bar`); a program can log them.

Without a hook (``progress=None``, the default), a solver run from a terminal shows a
tqdm bar on stderr, like the study runner's, and stays silent otherwise (stderr not a
terminal: a pipe, a file, a notebook's captured stream, CI). ``DESIGNLAB_PROGRESS=off``
silences the bar, ``on`` shows it whatever stderr is (:data:`ENV`).

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

import os
import sys
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

__all__ = ["ENV", "Progress", "ProgressHook", "default_hook", "report"]

#: The environment variable choosing the default bar: ``auto`` (a terminal), ``on``, ``off``.
ENV = "DESIGNLAB_PROGRESS"


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


class _TerminalBar:
    """The default hook: one tqdm bar per run of a solver, on stderr."""

    def __init__(self) -> None:
        self.bar: Any = None
        self.label = ""

    def __call__(self, info: Progress) -> None:
        from tqdm.auto import tqdm

        if self.bar is None or info.label != self.label or info.step <= self.bar.n:
            self.close()  # a new run (or a new solver) starts a new bar
            self.bar = tqdm(total=info.total, desc=info.label, file=sys.stderr, leave=False,
                            dynamic_ncols=True)  # fmt: skip
            self.label = info.label
        postfix = {"best": f"{info.best:.4g}"} if info.best is not None else {}
        if info.note:
            postfix["at"] = info.note
        if postfix:
            self.bar.set_postfix(postfix, refresh=False)
        self.bar.update(info.step - self.bar.n)
        if info.total is not None and info.step >= info.total:
            self.close()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None


_TERMINAL = _TerminalBar()


def default_hook() -> ProgressHook | None:
    """The hook of a solver called without one: a bar on a terminal, else ``None``.

    ``DESIGNLAB_PROGRESS`` (:data:`ENV`): ``auto`` (the default: a bar when stderr is a
    terminal), ``on`` (always) or ``off`` (never).

    Examples
    --------
    >>> import os
    >>> os.environ[ENV] = "off"
    >>> default_hook() is None
    True
    >>> del os.environ[ENV]
    """
    mode = os.environ.get(ENV, "auto").strip().lower()
    if mode in ("off", "0", "false", "no"):
        return None
    stream = sys.stderr
    terminal = stream is not None and hasattr(stream, "isatty") and stream.isatty()
    if mode in ("on", "1", "true", "yes") or terminal:
        return _TERMINAL
    return None


def report(hook: ProgressHook | None, info: Progress) -> None:
    """Call ``hook(info)``, or without a hook the default one (:func:`default_hook`).

    Parameters
    ----------
    hook
        The caller's hook, or ``None`` (a bar on a terminal, else nothing).
    info
        The step just finished.
    """
    hook = hook if hook is not None else default_hook()
    if hook is not None:
        hook(info)
