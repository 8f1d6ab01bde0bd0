"""One runner for every experiment: impacts in, outcomes out, in order, wherever they run.

    with Runner(workers=2) as runner:                    # or scheduler="local" / "tcp://host:8786"
        fired = runner.fire([Job(engine=name, settings=s, case=c) for c in cases])

(``experiments.core.fire`` fires them in a process.)
Serial, local processes (``workers`` > 1) and a Dask cluster (``scheduler``) give the same rows:
an adapter holds no state from one impact to the next, so where an impact runs cannot change
its bits. The first impact always runs here; it times the work, and the rest goes to the workers
only when it is worth their start-up (MIN_PARALLEL_S), in chunks of about CHUNK_S each so the
workers stay balanced.
"""

from __future__ import annotations

import contextlib
import math
import multiprocessing
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import adapters

from ..errors import UserError
from . import watchdog
from .boundary import STOP
from .endings import Physics
from .fire import Fired, Job, Jobs, fire_jobs
from .fired import FiredSeq, unmeasured
from .hosting import close_engines
from .workers import dask_results, pool_results, worker_start

#: Below this much estimated work (s) the rest of a run stays in this process: starting workers
#: and shipping the work costs more than it saves.
MIN_PARALLEL_S = 0.25
#: Target wall time of one chunk of impacts sent to a worker (s): long against the ~1 ms a Dask
#: task costs, short enough that two workers finish together.
CHUNK_S = 0.02
#: How long a scheduler address may take to answer (s) before the run is refused.
CONNECT_TIMEOUT_S = 5.0


def _import_engines(names: Sequence[str]) -> None:
    """In a worker: import these engines now, so that no job pays for it; their own threads
    one each (the workers fill the cores)."""
    adapters.set_engine_threads(1)
    for name in names:
        adapters.engine_class(name)


def _call(task: tuple[Callable, tuple]) -> Any:
    fn, args = task
    return fn(*args)


class Runner:
    """Runs work serially, in ``workers`` local processes, or on a Dask cluster (``scheduler``:
    an address such as tcp://host:8786, or "local" for a LocalCluster of ``workers`` processes).
    Impacts go to the workers only when their estimated time exceeds ``min_parallel_s``. Use it
    as a context manager; its pool or client lives until the block ends."""

    def __init__(
        self,
        workers: int = 1,
        scheduler: str | None = None,
        progress: Callable[[int], None] | None = None,
        min_parallel_s: float = MIN_PARALLEL_S,
    ) -> None:
        self.workers = workers
        self.scheduler = scheduler
        self.progress = progress
        self.min_parallel_s = min_parallel_s
        self._pool: ProcessPoolExecutor | None = None
        self._client = None
        self._cluster = None

    @property
    def parallel(self) -> bool:
        return self.scheduler is not None or self.workers > 1

    def __enter__(self) -> Runner:
        return self

    def __exit__(self, kind, *exc) -> None:
        self.close(abort=kind is not None)

    def close(self, abort: bool = False) -> None:
        """Stop the workers (if any; with ``abort``, at once: a run stopped or failed waits
        for no impact) and close this process's engines."""
        self._stop_pool(abort)
        if self._client is not None:
            self._client.close()
            self._client = None
        if self._cluster is not None:
            self._cluster.close()
            self._cluster = None
        close_engines()

    def _stop_pool(self, abort: bool) -> None:
        if self._pool is None:
            return
        with STOP.deferred():  # a second stop must not leave workers running
            pool, self._pool = self._pool, None
            workers = list((getattr(pool, "_processes", None) or {}).values())
            pool.shutdown(wait=not abort, cancel_futures=True)
            for process in workers if abort else ():
                process.terminate()
                process.join(timeout=5.0)
                if process.is_alive():
                    process.kill()

    def _map_remote(
        self,
        fn: Callable,
        items: list,
        lost: Callable | None = None,
        limit_s: Callable | None = None,
    ) -> Iterable:
        """Results of fn over items from the workers, in order, as they come (``workers``:
        a worker lost, or an item past ``limit_s(item)``, gives ``lost(item, physics, why)``)."""
        if self.scheduler is None:
            return pool_results(self, fn, items, lost, limit_s)
        return dask_results(self._dask(), fn, items, lost, limit_s)

    def pool(self) -> ProcessPoolExecutor:
        """The local worker processes, started if need be (each dies with this process)."""
        if self._pool is None:
            context = _pool_context()
            forked = context.get_start_method() == "fork"  # (else a fork server's children)
            self._pool = ProcessPoolExecutor(
                self.workers,
                mp_context=context,
                initializer=worker_start,
                initargs=(os.getpid() if forked else None,),
            )
        return self._pool

    def renew_pool(self) -> ProcessPoolExecutor:
        """New worker processes in place of a broken (or stopped) pool's."""
        self._stop_pool(abort=True)
        return self.pool()

    def _dask(self):
        if self._client is None:
            self._client = _dask_client(self.scheduler, self.workers)
            self._cluster = getattr(self._client, "_batsim_cluster", None)
        return self._client

    def call_all(
        self, calls: Sequence[tuple[Callable, tuple]], engines: Sequence[str] | None = None
    ) -> list:
        """The results of independent calls fn(*args), in order, run side by side if possible
        (``engines``: the engine each call fires, as for ``submit_all``)."""
        return self.submit_all(calls, engines=engines)()

    def submit_all(
        self,
        calls: Sequence[tuple[Callable, tuple]],
        estimate_s: float = math.inf,
        engines: Sequence[str] | None = None,
        progress: Callable[[int], None] | None = None,
    ) -> Callable[[], list]:
        """Start independent calls fn(*args) on the workers and return a function that waits
        for their results (in order); serially, or when their estimated total time is below
        ``min_parallel_s``, the calls run here when it is called. This process is free for
        other work meanwhile. ``engines`` names the engine each call fires: a batched engine's
        calls run here, as its jobs do in ``fire``. ``progress(1)`` follows each call done."""
        calls = list(calls)
        tick = progress or (lambda n: None)

        def counted(results: Iterable) -> Iterable:
            for r in results:
                tick(1)
                yield r

        here = [adapters.record(e).batched for e in engines] if engines else [False] * len(calls)
        there = [c for c, h in zip(calls, here) if not h]
        if not self.parallel or len(there) <= 1 or estimate_s < self.min_parallel_s:
            return lambda: list(counted(_call(c) for c in calls))
        results = self._map_remote(_call, there)  # both backends submit everything at once

        def wait() -> list:
            mine = iter(list(counted(_call(c) for c, h in zip(calls, here) if h)))
            theirs = counted(results)
            return [next(mine) if h else next(theirs) for h in here]

        return wait

    def fire(self, jobs: Sequence[Job]) -> Sequence[Fired]:
        """Every job fired, results in the order of ``jobs``."""
        if not len(jobs):
            return []
        if isinstance(jobs, Jobs) and adapters.record(jobs.engine).batched:
            return fire_jobs(jobs, self.progress)  # one batch, in this process
        jobs = list(jobs)
        kind = {n: adapters.record(n).batched for n in {j.engine for j in jobs}}
        batched = [kind[j.engine] for j in jobs]
        # nothing to decide, or nothing to spread: no probe
        if not self.parallel or all(batched):
            return fire_jobs(jobs, self.progress)
        # a batched engine's worlds run side by side in its own call: its jobs stay here, as
        # one batch per scene (JAX, moreover, deadlocks in a forked worker); the probe that
        # prices a job is a single-world one (a batched one would split its batch)
        p = batched.index(False)
        t0 = time.perf_counter()
        probe = fire_jobs([jobs[p]])
        self._tick(1)
        per_job = time.perf_counter() - t0
        here = [i for i, b in enumerate(batched) if b]
        there = [i for i, b in enumerate(batched) if not b and i != p]
        if per_job * len(there) < self.min_parallel_s:  # (no batch straddles the probe)
            return FiredSeq(
                [fire_jobs(jobs[:p], self.progress), probe, fire_jobs(jobs[p + 1 :], self.progress)]
            )
        if self.scheduler is not None:  # spawned workers: every one imports the engines first
            self._dask().run(_import_engines, sorted({jobs[i].engine for i in there}))
        size = max(
            1,
            min(
                round(CHUNK_S / max(per_job, 1e-9)),
                math.ceil(len(there) / (4 * max(self.workers, 1))),
            ),
        )
        parts = self._map_remote(
            fire_jobs,
            [[jobs[i] for i in there[k : k + size]] for k in range(0, len(there), size)],
            lost=_lost_chunk,
            limit_s=_chunk_limit_s,
        )
        out: list = [None] * len(jobs)
        out[p] = probe[0]
        remote = iter(there)
        for part in parts:
            for f in part:
                out[next(remote)] = f
            self._tick(len(part))
        # then the batched ones: stepping them beside the workers would slow the workers'
        # timed impacts (the workers fill the cores)
        for i, f in zip(here, fire_jobs([jobs[i] for i in here], self.progress)):
            out[i] = f
        return out

    def _tick(self, n: int) -> None:
        if self.progress is not None:
            self.progress(n)


def _lost_chunk(chunk: list[Job], physics: Physics, why: str) -> list[Fired]:
    """The rows of a chunk of impacts its worker never gave back (``workers``)."""
    return [unmeasured(j.engine, [j.case], [j.settings], None, physics, why, 0.0)[0] for j in chunk]


def _chunk_limit_s(chunk: list[Job]) -> float:
    """How long a worker may take over a chunk before it is taken for hung (s): each impact's
    limit (``watchdog.limit_s``, no floor each) and one floor for the chunk. A hang in Python
    is caught in the worker, by its own limit per batch: this is for one in compiled code."""
    return watchdog.FLOOR_S + sum(
        watchdog.limit_s(adapters.record(j.engine), j.settings, 1, floor_s=0.0) for j in chunk
    )


def _pool_context():
    """How local workers start: forked, so that they inherit the imported engines and the
    registry (plug-ins registered in this process too), unless JAX runs here: a fork of a
    process with JAX's threads deadlocks, so the workers then come from a fork server (a
    clean process) and import what they fire."""
    return multiprocessing.get_context("forkserver" if "jax" in sys.modules else "fork")


def _dask_client(scheduler: str, workers: int):
    """A dask.distributed Client for an address, or for a new LocalCluster ("local")."""
    import logging

    import dask
    from dask.distributed import Client, LocalCluster

    if scheduler == "local":
        logging.getLogger("distributed").setLevel(logging.ERROR)
        # The workers' sampling profiler takes the GIL every 10 ms from the impacts, and with
        # queuing a worker waits a round trip to the scheduler for its next chunk.
        # Its processes start with Ctrl-C ignored (inherited): the run stops them itself, and
        # each would print its own traceback for the terminal's SIGINT.
        try:
            with (
                dask.config.set(
                    {
                        "distributed.worker.profile.enabled": False,
                        "distributed.scheduler.worker-saturation": math.inf,
                    }
                ),
                _ignoring(signal.SIGINT),
            ):
                cluster = LocalCluster(
                    n_workers=max(workers, 1),
                    threads_per_worker=1,
                    processes=True,
                    dashboard_address=None,
                    silence_logs=logging.ERROR,
                )
        except (OSError, RuntimeError, TimeoutError) as err:
            raise UserError(
                f"a local Dask cluster of {workers} workers could not start "
                f"({type(err).__name__}: {' '.join(str(err).split())[:200]}); "
                "allowed: fewer --workers, a higher ulimit -n, or --workers "
                "without --scheduler"
            ) from None
        client = Client(cluster)
        client._batsim_cluster = cluster
        return client
    return connect(scheduler)


@contextlib.contextmanager
def _ignoring(signum: int) -> Iterator[None]:
    """``signum`` ignored in this process meanwhile (in the main thread), and so in the
    processes it starts meanwhile."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signum, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signum, previous)


def connect(address: str, timeout_s: float = CONNECT_TIMEOUT_S):
    """A Client of the Dask scheduler at ``address``; OSError (one line) unless a Dask scheduler
    there answers a handshake within ``timeout_s`` (a silent listener or another service is
    refused, not waited on)."""
    from dask.distributed import Client

    handshake(address, timeout_s)
    try:
        return Client(address, timeout=timeout_s)
    except (OSError, TimeoutError) as err:
        raise OSError(
            f"no Dask scheduler answered at {address} within {timeout_s:g} s ({type(err).__name__})"
        ) from None


def handshake(address: str, timeout_s: float) -> None:
    """Ask whatever listens at ``address`` who it is (Dask's ``identity``), within ``timeout_s``
    all told; OSError unless a Dask scheduler answers."""
    import asyncio

    from distributed.comm import connect as open_comm

    async def ask() -> object:
        comm = await open_comm(address, timeout=timeout_s)
        try:
            await comm.write({"op": "identity"})
            return await comm.read()
        finally:
            comm.abort()

    try:
        reply = asyncio.run(asyncio.wait_for(ask(), timeout_s))
    except TimeoutError:
        raise OSError(f"nothing answered at {address} within {timeout_s:g} s") from None
    except Exception as err:  # noqa: BLE001 - a foreign service's bytes can fail any way
        raise OSError(f"no Dask scheduler answered at {address} ({type(err).__name__})") from None
    if not isinstance(reply, dict) or reply.get("type") != "Scheduler":
        raise OSError(f"{address} answered, but not as a Dask scheduler")
