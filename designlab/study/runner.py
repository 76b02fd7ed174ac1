"""Run a validated study: dispatch to its kind's runner.

:func:`run_study` computes, it does not write: the result goes to
:mod:`designlab.report`. Sweep kinds evaluate their points through an executor
and keep finished chunks in a result store that the caller (the CLI) opens and
hands in.

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: impact_cases
... name: demo
... cases:
...   - {label: fast, robot: MANIPULATOR_1, foam: FOAM_1, head: TEST_HEAD, v_r: 0.25, v_h: -1.0}
... ''')
>>> result = run_study(study)
>>> result.to_frame()[["case", "v_c_m_per_s", "a_h_max_g"]].round(2)
   case  v_c_m_per_s  a_h_max_g
0  fast         1.25       6.57
"""

from __future__ import annotations

import logging
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

from designlab.progress import Progress, ProgressHook
from designlab.study.base import StudyBase
from designlab.study.registry import kind_of

__all__ = ["RunContext", "run_study"]

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class RunContext:
    """How a study runs (the same for every kind).

    Attributes
    ----------
    progress
        Show tqdm progress bars on stderr (the CLI turns them on only when
        stderr is a terminal).
    executor
        An executor from :func:`designlab.analysis.executors.make_executor`
        (``None``: serial, in this process). The caller closes it.
    store
        A result store (:class:`designlab.analysis.store.ChunkStore`) where
        finished chunks are kept; ``None``: nothing is kept.
    resume
        Reuse chunks found in the store; compute only the missing ones.
    cache_only
        Compute nothing that a store could hold; raise
        :class:`~designlab.analysis.engine.CacheIncompleteError` if a chunk is
        missing (``designlab report``). Kinds without sweeps recompute.
    """

    progress: bool = False
    executor: Any = None
    store: Any = None
    resume: bool = False
    cache_only: bool = False

    @contextmanager
    def bar(self, desc: str, total: int | None = None) -> Iterator[ProgressHook]:
        """A progress hook drawing a tqdm bar on stderr while the block runs.

        Hand the hook to a solver's ``progress`` argument; each
        :class:`~designlab.progress.Progress` it receives advances the bar and
        shows the best objective. Off (a no-op hook) unless :attr:`progress`.

        Parameters
        ----------
        desc
            The bar's label (``"navigation_gains: optimise"``).
        total
            Steps expected, if known (a ``Progress.total`` replaces it).

        Examples
        --------
        >>> from designlab.progress import Progress
        >>> with RunContext().bar("demo", total=2) as hook:
        ...     hook(Progress(step=1, total=2, best=0.5))
        """
        from tqdm.auto import tqdm

        with tqdm(
            total=total, desc=desc, file=sys.stderr, disable=not self.progress, leave=False
        ) as bar:

            def hook(info: Progress) -> None:
                if info.total is not None and bar.total != info.total:
                    bar.total = info.total
                bar.n = info.step
                post = {} if info.best is None else {"best": f"{info.best:.4g}"}
                if info.note:
                    post["at"] = info.note
                bar.set_postfix(post, refresh=False)
                bar.refresh()

            yield hook


def run_study(study: StudyBase, context: RunContext | None = None, **options: Any) -> Any:
    """Compute every result of a study.

    Parameters
    ----------
    study
        A validated study (see :func:`designlab.study.load_study`).
    context
        How to run it (:class:`RunContext`; default: serially, no store).
    **options
        Shorthand for the fields of :class:`RunContext` (``progress``,
        ``executor``, ``store``, ``resume``, ``cache_only``).

    Returns
    -------
    Result
        The result object of the study's kind; every one has ``study``,
        ``status``, ``warnings``, ``to_frame()`` and ``summary()``.
    """
    if context is None:
        context = RunContext(**options)
    elif options:
        raise TypeError("give a RunContext or keyword options, not both")
    kind = kind_of(study.kind)
    logger.info("running study %r (kind %s)", study.name, study.kind)
    return kind.run(study, context)
