"""Executors: run plain-dict tasks serially, in local processes or on Dask.

An executor maps a picklable top-level function over a list of tasks (plain
dictionaries) and yields ``(index, result)`` pairs as tasks finish, in
completion order. The function must build its models inside the worker:
CasADi objects with free symbols do not pickle. Tasks may be a lazy iterable:
the process and Dask executors keep at most :attr:`Executor.window` tasks in
flight and draw the next one as one finishes, so a million-point sweep holds
only a few chunks in memory at a time.

``serial``
    In this process, in order (the default; no start-up cost).
``processes``
    A :class:`concurrent.futures.ProcessPoolExecutor` of ``workers`` local
    processes (``forkserver`` start on POSIX, with designlab preloaded). Each
    worker watches its client: when the client dies (even by SIGKILL) the
    workers exit, and with them the fork server and resource tracker. A worker
    that dies (killed, out of memory) raises :class:`WorkerLostError`.
``dask``
    A :class:`distributed.Client` connected to ``scheduler`` (e.g.
    ``tcp://host:8786``) or, without an address, to a new
    :class:`distributed.LocalCluster` of ``workers`` single-threaded
    processes. An unreachable scheduler raises :class:`ExecutorError` after
    ``timeout`` seconds; a scheduler lost during the run (its connection closed,
    or no answer within ``worker_timeout`` seconds), or no sign of a live worker
    for ``worker_timeout`` seconds (default :data:`WORKER_TIMEOUT`; a sign is a
    finished task or a worker's heartbeat reaching the scheduler), raises
    :class:`WorkerLostError`. Heartbeats matter where a killed worker's
    connections stay open (a process it forked holds them): the scheduler then
    keeps it in its list, but its heartbeats stop. A worker whose event loop is
    blocked for longer (importing for many seconds on a busy machine) looks
    lost too: keep ``worker_timeout`` well above that.

Whatever the executor, the sweep engine stores every chunk as it comes back,
so after a :class:`WorkerLostError` the finished chunks are in the result
store and ``designlab run ... --resume`` computes only the rest.

Examples
--------
>>> with make_executor("serial") as ex:
...     sorted(ex.map_unordered(abs, [-1, -2]))
[(0, 1), (1, 2)]
"""

from __future__ import annotations

import logging
import multiprocessing
import os
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import FIRST_COMPLETED, CancelledError, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from itertools import islice
from multiprocessing.connection import Connection
from types import TracebackType
from typing import Any

from designlab.errors import DesignlabError

__all__ = [
    "EXECUTORS",
    "DaskExecutor",
    "Executor",
    "ExecutorError",
    "ProcessExecutor",
    "SerialExecutor",
    "WorkerLostError",
    "check_scheduler_address",
    "make_executor",
]

logger = logging.getLogger(__name__)

#: Names accepted by :func:`make_executor` (and ``designlab run --executor``).
EXECUTORS = ("serial", "processes", "dask")
#: Seconds a Dask run waits with no live worker before it fails (``--worker-timeout``).
WORKER_TIMEOUT = 60.0
#: Exit status of a worker process whose client has gone.
_ORPHANED = 70
#: Seconds between checks of the Dask cluster while no task finishes.
_POLL = 1.0
#: Seconds without a worker's heartbeat (about one a second) before the run warns.
_SILENT = 5.0
#: Seconds to wait for a Dask client or cluster to close.
_CLOSE_TIMEOUT = 10.0


def check_scheduler_address(address: str) -> str:
    """``""`` if ``address`` looks like a Dask scheduler address, else what is wrong.

    Parameters
    ----------
    address
        For example ``tcp://10.0.0.5:8786`` or ``scheduler:8786``.

    Examples
    --------
    >>> check_scheduler_address("tcp://127.0.0.1:8786")
    ''
    >>> check_scheduler_address("nonsense")
    'give PROTOCOL://HOST:PORT, e.g. tcp://127.0.0.1:8786'
    >>> check_scheduler_address("tcp://host:99999")
    'the port must be 1-65535'
    """
    from urllib.parse import urlsplit

    text = address.strip()
    if "://" not in text:
        text = "tcp://" + text
    try:
        parts = urlsplit(text)
        port = parts.port
    except ValueError:
        return "the port must be 1-65535"
    if parts.scheme == "inproc":
        return ""
    if parts.scheme not in ("tcp", "tls", "ucx", "ws", "wss"):
        return f"unknown protocol {parts.scheme!r} (tcp, tls, ucx, ws, wss)"
    if not parts.hostname or port is None:
        return "give PROTOCOL://HOST:PORT, e.g. tcp://127.0.0.1:8786"
    if not 0 < port < 65536:
        return "the port must be 1-65535"
    return ""


class ExecutorError(DesignlabError, RuntimeError):
    """An executor cannot start (no Dask installed, scheduler unreachable, ...)."""


class WorkerLostError(ExecutorError):
    """The executor lost its workers or scheduler during a run (finished chunks are stored)."""


_RESUME_HINT = (
    "the chunks finished before are kept in the result store: run the same command with "
    "--resume to compute the rest"
)


def _watch_client(alive: Connection) -> None:
    """Worker initializer: exit as soon as the client process is gone.

    ``alive`` is the reading end of a pipe whose only writer is the client:
    when the client exits, however it dies, the read sees end-of-file.
    """

    def wait_for_client() -> None:
        try:
            alive.recv_bytes()
        except (EOFError, OSError):
            pass
        os._exit(_ORPHANED)

    threading.Thread(target=wait_for_client, name="designlab-watchdog", daemon=True).start()


class Executor:
    """Base class: a context manager with :meth:`map_unordered`."""

    name = "executor"
    workers = 1

    @property
    def window(self) -> int:
        """Tasks kept in flight at once: four per worker (at least two)."""
        return max(2, 4 * int(self.workers))

    def __enter__(self) -> Executor:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    def close(self) -> None:
        """Release workers (idempotent)."""

    def map_unordered(
        self, fn: Callable[[Any], Any], tasks: Iterable[Any]
    ) -> Iterator[tuple[int, Any]]:  # pragma: no cover - abstract
        """Yield ``(index, fn(tasks[index]))`` as tasks finish.

        Parameters
        ----------
        fn
            A picklable top-level function of one task.
        tasks
            The tasks (plain, picklable values; a lazy iterable is drawn from
            as workers become free).
        """
        raise NotImplementedError

    def describe(self) -> str:
        """A short description for logs and reports."""
        return f"{self.name} ({self.workers} worker{'s' if self.workers != 1 else ''})"


class SerialExecutor(Executor):
    """Run tasks one after another in this process."""

    name = "serial"

    def map_unordered(
        self, fn: Callable[[Any], Any], tasks: Iterable[Any]
    ) -> Iterator[tuple[int, Any]]:
        """Yield ``(index, fn(tasks[index]))`` as tasks finish.

        Parameters
        ----------
        fn
            A picklable top-level function of one task.
        tasks
            The tasks (plain, picklable values; a lazy iterable is drawn from
            as workers become free).
        """
        for i, task in enumerate(tasks):
            yield i, fn(task)


def _failed(fut: Future[Any]) -> bool:
    return fut.cancelled() or fut.exception() is not None


def _yield_futures(
    submit: Callable[[Any], Future[Any]], tasks: Iterable[Any], window: int
) -> Iterator[tuple[int, Any]]:
    """Submit ``tasks`` keeping at most ``window`` in flight; yield results as they finish."""
    source = enumerate(tasks)
    index: dict[Future[Any], int] = {}

    def top_up(k: int) -> None:
        for i, task in islice(source, k):
            index[submit(task)] = i

    top_up(window)
    pending = set(index)
    try:
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for fut in sorted(done, key=_failed):  # results first
                i = index.pop(fut)
                result = fut.result()
                before = set(index)
                top_up(1)
                pending |= set(index) - before
                yield i, result
    finally:
        for fut in pending:
            fut.cancel()


class ProcessExecutor(Executor):
    """A pool of local worker processes.

    Parameters
    ----------
    workers
        Worker processes (default: the CPU count).
    """

    name = "processes"

    def __init__(self, workers: int | None = None) -> None:
        self.workers = workers or os.cpu_count() or 1
        if sys.platform != "win32":
            ctx = multiprocessing.get_context("forkserver")
            ctx.set_forkserver_preload(["designlab.analysis.engine"])
        else:  # pragma: no cover
            ctx = multiprocessing.get_context("spawn")
        # the workers get the reading end only: it reaches end-of-file when this process dies
        self._alive_r, self._alive_w = ctx.Pipe(duplex=False)
        self._pool = ProcessPoolExecutor(
            max_workers=self.workers,
            mp_context=ctx,
            initializer=_watch_client,
            initargs=(self._alive_r,),
        )

    def close(self) -> None:
        self._pool.shutdown(wait=True, cancel_futures=True)
        self._alive_w.close()
        self._alive_r.close()

    def map_unordered(
        self, fn: Callable[[Any], Any], tasks: Iterable[Any]
    ) -> Iterator[tuple[int, Any]]:
        """Yield ``(index, fn(tasks[index]))`` as tasks finish.

        Parameters
        ----------
        fn
            A picklable top-level function of one task.
        tasks
            The tasks (plain, picklable values; a lazy iterable is drawn from
            as workers become free).
        """
        try:
            yield from _yield_futures(lambda task: self._pool.submit(fn, task), tasks, self.window)
        except BrokenProcessPool as exc:
            raise WorkerLostError(
                "a worker process died during the run (killed by a signal or the "
                f"out-of-memory killer?); {_RESUME_HINT}"
            ) from exc


class DaskExecutor(Executor):
    """Tasks on a Dask distributed cluster (a new LocalCluster without ``scheduler``).

    Parameters
    ----------
    scheduler
        Scheduler address (``tcp://host:8786``); ``None`` starts a LocalCluster.
    workers
        LocalCluster worker processes (default: the CPU count); ignored with ``scheduler``.
    timeout
        Seconds to wait for the scheduler before raising :class:`ExecutorError`.
    processes
        LocalCluster only: worker processes (``False``: threads in this process).
    worker_timeout
        Seconds the run waits without a sign of a live worker (a finished task
        or a heartbeat), or for the scheduler to answer, or for a finished
        result, before raising :class:`WorkerLostError`.
    """

    name = "dask"

    def __init__(
        self,
        scheduler: str | None = None,
        workers: int | None = None,
        *,
        timeout: float = 5.0,
        processes: bool = True,
        worker_timeout: float = WORKER_TIMEOUT,
    ) -> None:
        if not worker_timeout > 0:
            raise ExecutorError(
                f"worker_timeout = {worker_timeout!r} s is not allowed: must be > 0"
            )
        self.worker_timeout = float(worker_timeout)
        try:
            from distributed import Client, LocalCluster
        except ImportError as exc:
            raise ExecutorError(
                "the dask executor needs dask[distributed]: pip install 'designlab[dask]'"
            ) from exc
        self.scheduler = scheduler
        self._cluster = None
        try:
            if scheduler is None:
                self.workers = workers or os.cpu_count() or 1
                self._cluster = LocalCluster(
                    n_workers=self.workers,
                    threads_per_worker=1,
                    processes=processes,
                    dashboard_address=None,
                    silence_logs=logging.ERROR,
                )
                self._client = Client(self._cluster, timeout=timeout)
            else:
                self._client = Client(scheduler, timeout=timeout)
                self.workers = len(self._client.scheduler_info().get("workers", {})) or 1
        except (OSError, TimeoutError) as exc:
            self.close()
            where = f"the Dask scheduler at {scheduler}" if scheduler else "a local Dask cluster"
            raise ExecutorError(
                f"cannot reach {where} within {timeout:g} s ({type(exc).__name__}: {exc}); "
                "check the address and that `dask scheduler` is running"
            ) from None

    def describe(self) -> str:
        where = self.scheduler or "LocalCluster"
        return f"dask {where} ({self.workers} worker{'s' if self.workers != 1 else ''})"

    def close(self) -> None:
        # bounded: after a lost scheduler, closing must not wait for it
        client, self._client = getattr(self, "_client", None), None
        cluster, self._cluster = self._cluster, None
        for part in (client, cluster):
            if part is None:
                continue
            try:
                part.close(timeout=_CLOSE_TIMEOUT)
            except Exception as exc:  # already lost: nothing left to release
                logger.info("closing %s: %s: %s", type(part).__name__, type(exc).__name__, exc)

    def map_unordered(
        self, fn: Callable[[Any], Any], tasks: Iterable[Any]
    ) -> Iterator[tuple[int, Any]]:
        """Yield ``(index, fn(tasks[index]))`` as tasks finish.

        Parameters
        ----------
        fn
            A picklable top-level function of one task.
        tasks
            The tasks (plain, picklable values; a lazy iterable is drawn from
            as workers become free).
        """
        from distributed import wait as wait_for

        source = enumerate(tasks)
        index: dict[Any, int] = {}

        def top_up(k: int) -> None:
            for i, task in islice(source, k):
                fut = self._client.submit(fn, task, pure=False)
                index[fut] = i

        top_up(self.window)
        watch = _Liveness()
        try:
            while index:
                try:
                    done = wait_for(list(index), timeout=_POLL, return_when="FIRST_COMPLETED").done
                except TimeoutError:
                    self._check_workers(watch)
                    continue
                watch.life()
                for fut in sorted(done, key=lambda f: f.status != "finished"):  # results first
                    i = index.pop(fut)
                    result = self._result(fut)
                    top_up(1)
                    yield i, result
        except WorkerLostError:
            raise
        except (CancelledError, OSError) as exc:
            raise self._lost(exc) from exc
        except Exception as exc:
            if type(exc).__name__ in ("KilledWorker", "CommClosedError", "FutureCancelledError"):
                raise self._lost(exc) from exc
            raise
        finally:
            for fut in index:
                if not fut.done():
                    fut.cancel()

    def _lost(self, exc: BaseException) -> WorkerLostError:
        where = f"the Dask scheduler at {self.scheduler}" if self.scheduler else "the Dask cluster"
        if not isinstance(exc, TimeoutError) and self._scheduler_answers():
            where = "a Dask worker"  # e.g. the one holding a finished result
        return WorkerLostError(
            f"lost {where} during the run ({type(exc).__name__}: "
            f"{(str(exc).strip().splitlines() or [''])[0]}); {_RESUME_HINT}"
        )

    def _result(self, fut: Any) -> Any:
        """The result of a finished task, fetched from its worker within ``worker_timeout``."""
        try:
            return fut.result(timeout=self.worker_timeout)
        except TimeoutError:
            where = f"the Dask scheduler at {self.scheduler}" if self.scheduler else "the scheduler"
            raise WorkerLostError(
                f"lost {where} or the Dask worker holding a finished result: the result did not "
                f"come within {self.worker_timeout:g} s (--worker-timeout); {_RESUME_HINT}"
            ) from None

    def _scheduler_answers(self) -> bool:
        client = self._client
        try:
            client.sync(
                client.scheduler.identity, n_workers=0, callback_timeout=self.worker_timeout
            )
        except Exception:
            return False
        return True

    def _check_workers(self, watch: _Liveness) -> None:
        """While no task finishes: raise :class:`WorkerLostError` after ``worker_timeout``
        seconds without a sign of life (a finished task or a worker's heartbeat).

        The scheduler is asked with a time limit (a scheduler that stopped answering is
        lost), and a worker counts as alive only while its heartbeats reach the scheduler:
        a worker killed while another process holds its connection open (a process it
        forked) stays in the scheduler's list, but its heartbeats stop.
        """
        client = self._client
        try:
            info = client.sync(
                client.scheduler.identity, n_workers=-1, callback_timeout=self.worker_timeout
            )
        except (OSError, TimeoutError) as exc:
            raise self._lost(exc) from exc
        except Exception as exc:
            if type(exc).__name__ in ("CommClosedError", "CancelledError"):
                raise self._lost(exc) from exc
            raise
        beats = {addr: w.get("last_seen") for addr, w in (info.get("workers") or {}).items()}
        silent = watch.heartbeats(beats)
        if not watch.warned and (not beats or silent >= min(_SILENT, self.worker_timeout)):
            watch.warned = True
            logger.warning(
                "no Dask worker is alive (%s): waiting up to %g s for one (--worker-timeout)",
                "none is connected" if not beats else "no heartbeat", self.worker_timeout,
            )  # fmt: skip
        if silent >= self.worker_timeout:
            raise WorkerLostError(
                f"no Dask worker has been alive for {self.worker_timeout:g} s (the last one "
                f"was lost; --worker-timeout); {_RESUME_HINT} once workers are running"
            )


class _Liveness:
    """Signs of life of a Dask run: finished tasks and changes of workers' heartbeats."""

    def __init__(self) -> None:
        self.last = time.monotonic()
        self.warned = False
        self._beats: dict[str, Any] = {}

    def life(self) -> None:
        """A task finished."""
        self.last = time.monotonic()
        self.warned = False

    def heartbeats(self, beats: dict[str, Any]) -> float:
        """Record the workers' last heartbeats (the scheduler's ``last_seen``); return the
        seconds since the last sign of life."""
        now = time.monotonic()
        if any(addr in self._beats and self._beats[addr] != beat for addr, beat in beats.items()):
            self.last = now
            self.warned = False
        self._beats = beats
        return now - self.last


def make_executor(
    name: str = "serial",
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    timeout: float = 5.0,
    processes: bool = True,
    worker_timeout: float = WORKER_TIMEOUT,
) -> Executor:
    """Create an executor by name (``serial``, ``processes`` or ``dask``).

    Parameters
    ----------
    name
        One of :data:`EXECUTORS`.
    workers
        Worker processes (default: the number of CPUs). Ignored by ``serial``
        and by ``dask`` with a scheduler address.
    scheduler
        Dask scheduler address; only with ``dask``.
    timeout
        Seconds to wait for the Dask scheduler.
    processes
        ``dask`` LocalCluster only: worker processes (``False``: threads in
        this process, for tests).
    worker_timeout
        ``dask`` only: seconds to wait while no worker is alive before failing.

    Raises
    ------
    ExecutorError
        Unknown name, an option that does not apply, or a cluster that cannot start.
    """
    if workers is not None and workers < 1:
        raise ExecutorError(f"workers = {workers} is not allowed: must be >= 1")
    if scheduler is not None and name != "dask":
        raise ExecutorError(f"--scheduler is only used by the dask executor, not {name!r}")
    if name == "serial":
        return SerialExecutor()
    if name == "processes":
        return ProcessExecutor(workers)
    if name == "dask":
        return DaskExecutor(
            scheduler, workers, timeout=timeout, processes=processes, worker_timeout=worker_timeout
        )
    raise ExecutorError(f"unknown executor {name!r} (known: {', '.join(EXECUTORS)})")
