"""A bounded pool of worker processes that run the app's physics: cancellable, with deadlines.

Why processes: a Python thread cannot be stopped, and Numba's ``workqueue`` threading layer must
not be entered from two threads at once (the app used one lock for all physics, so one slow or
abandoned request held up every other).  Each worker is a process that runs one job at a time; a
job whose client has gone, or that passes its deadline, is stopped by killing its worker.  Workers
are *spawned* (a fresh interpreter: forking a process that has loaded Numba's parallel kernels
aborts with GNU OpenMP, and ``tennislab.core`` loads them at import), which takes about a second,
so the pool keeps one spare worker started: a killed worker is replaced at once by the spare, and a
new spare starts in the background.

Rules (``docs/app.md``, "How requests are run"):

* ``workers`` processes (default 2); *heavy* jobs (the serve window, line calls, drills) may use at
  most ``workers - 1`` of them, so a light job (one flight, serve or aim) always finds a worker
  within one light job's time;
* at most ``max_waiting`` requests wait for a worker; more are refused at once (HTTP 503), and a
  request waits at most ``wait_s``;
* while a request waits or computes, its connection is checked every ``poll_s``: a client that has
  gone (closed tab, aborted fetch, timed-out script) cancels its job (a job that finishes within
  ``grace_s`` of its client leaving is let finish: cheaper than a new worker);
* every job has a deadline (seconds, per job name; a worker's first job of a kind gets
  :data:`FIRST_RUN_EXTRA_S` more, for its kernels to load or compile); past it the worker is killed
  and the client told so (HTTP 503).

Jobs are named (:data:`tennislab.app.features.JOBS`); a request never sends code.
"""

from __future__ import annotations

import asyncio
import logging
import multiprocessing
import signal
import threading
import time
import traceback
from collections.abc import Awaitable, Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import tennislab.app.features as features
from tennislab.errors import InputError, TennisLabError
from tennislab.results import jsonable

log = logging.getLogger("tennislab.app")

#: jobs that may take seconds (never more than ``workers - 1`` at once)
HEAVY_JOBS = frozenset({"window", "linecall", "drill"})
#: deadline of each job [s] (measured worst cases at the request limits on one core: window at the
#: finest step 0.1 s, a 1 MB track 0.3-1 s, a 50-shot drill 0.3 s; see docs/app.md)
DEADLINES_S = {"flight": 20.0, "serve": 20.0, "aim": 20.0, "sample": 20.0, "window": 60.0, "linecall": 60.0}
DEFAULT_DEADLINE_S = 60.0
#: added to the deadline of a worker's first job of each kind: it loads (and, the first time after an
#: install, compiles) the job's Numba kernels, which took over 20 s for the first aim of a fresh clone
#: while the whole test suite ran on the shared 2-core machine; later jobs of that kind keep the deadline
FIRST_RUN_EXTRA_S = 120.0


class PoolError(TennisLabError):
    """A job that could not be run or finished: ``status`` is the HTTP status to answer."""

    def __init__(self, message: str, status: int = 503):
        super().__init__(message)
        self.status = status


class ClientGone(PoolError):
    """The client closed its connection: the job was cancelled (nobody reads the answer)."""


def _worker_main(conn) -> None:  # pragma: no cover - runs in the worker process
    """Run named jobs from ``conn`` until it closes: ``(job, values, extra)`` -> ``(kind, payload)``."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C in the terminal: the server shuts us down
    while True:
        try:
            msg = conn.recv()
        except (EOFError, OSError):
            return
        if msg is None:
            return
        job, values, extra = msg
        try:
            out = ("ok", None if job == "ping" else jsonable(features.JOBS[job](values, **extra)))
        except InputError as exc:
            out = ("input", " ".join(str(exc).split()))
        except Exception as exc:  # a bug: log it here, answer one line
            traceback.print_exc()
            out = ("error", f"{job}: internal error ({type(exc).__name__})")
        try:
            conn.send(out)
        except (BrokenPipeError, OSError):
            return


class _Worker:
    """One worker process and the parent's end of its pipe."""

    def __init__(self, ctx):
        self.conn, child = ctx.Pipe()
        self.proc = ctx.Process(target=_worker_main, args=(child,), daemon=True, name="tennislab-app-worker")
        self.proc.start()
        child.close()
        self.seen: set[str] = set()  # the jobs this worker has run (their kernels are loaded)

    def call(self, job: str, values: dict, extra: dict):
        """Send a job and wait for its answer (blocking: runs in a thread of the pool)."""
        self.conn.send((job, values, extra))
        return self.conn.recv()

    def kill(self) -> None:
        if self.proc.is_alive():
            self.proc.kill()
        self.proc.join(5)
        self.conn.close()

    def stop(self) -> None:
        try:
            self.conn.send(None)
        except OSError:
            pass
        self.proc.join(2)
        self.kill()


@dataclass
class Stats:
    """Counters shown in ``/api/meta`` (``pool``) and used by the tests."""

    done: int = 0
    cancelled: int = 0
    timed_out: int = 0
    refused: int = 0
    replaced: int = 0
    running: dict = field(default_factory=dict)


class Pool:
    """``await pool.run(job, values, extra, gone=...)`` runs a job in a worker process (module docstring)."""

    def __init__(
        self,
        workers: int = 2,
        *,
        spares: int = 1,
        max_waiting: int = 32,
        wait_s: float = 30.0,
        poll_s: float = 0.05,
        grace_s: float = 0.5,
        deadlines_s: dict | None = None,
        deadline_s: float | None = None,
    ):
        if not 1 <= workers <= 16:
            raise InputError(f"workers: {workers} is outside the allowed range [1, 16]")
        self.n = workers
        self.n_spares = spares
        self.heavy_limit = max(1, workers - 1)
        self.max_waiting = max_waiting
        self.wait_s = wait_s
        self.poll_s = poll_s
        self.grace_s = grace_s
        self.deadlines_s = dict(DEADLINES_S, **(deadlines_s or {}))
        self.deadline_s = deadline_s  # one deadline for every job (tests)
        self.stats = Stats()
        self._ctx = multiprocessing.get_context("spawn")
        self._free: list[_Worker] = []
        self._spares: list[_Worker] = []
        self._all: set[_Worker] = set()
        self._heavy = 0
        self._waiting = 0
        self._starting = 0
        self._changed: asyncio.Event | None = None
        self._threads = ThreadPoolExecutor(max_workers=workers + spares + 2, thread_name_prefix="tennislab-pool")
        self._lock = threading.Lock()
        self._closed = False

    # ---------------------------------------------------------------- life cycle
    def _spawn(self) -> _Worker:
        """Start a worker and wait until it answers (it has imported the physics)."""
        w = _Worker(self._ctx)
        try:
            w.call("ping", {}, {})
        except (EOFError, OSError) as exc:
            w.kill()
            raise PoolError(f"server: a worker process did not start ({type(exc).__name__})") from None
        with self._lock:
            if self._closed:
                w.kill()
                raise PoolError("server: shutting down")
            self._all.add(w)
        return w

    async def start(self) -> None:
        """Start the workers and the spares (each a fresh interpreter importing the physics)."""
        self._changed = asyncio.Event()
        loop = asyncio.get_running_loop()
        started = await asyncio.gather(
            *(loop.run_in_executor(self._threads, self._spawn) for _ in range(self.n + self.n_spares))
        )
        self._free.extend(started[: self.n])
        self._spares.extend(started[self.n :])

    async def close(self) -> None:
        with self._lock:
            self._closed = True
            workers = list(self._all)
            self._all.clear()
        loop = asyncio.get_running_loop()
        await asyncio.gather(*(loop.run_in_executor(self._threads, w.stop) for w in workers))
        self._free.clear()
        self._spares.clear()
        self._threads.shutdown(wait=False, cancel_futures=True)

    def _start_spare(self) -> None:
        """Start one worker in the background; it becomes a spare (or a worker, if one is missing)."""
        self._starting += 1
        fut = asyncio.get_running_loop().run_in_executor(self._threads, self._spawn)

        def _ready(f) -> None:
            self._starting -= 1
            if f.cancelled() or f.exception() is not None:
                if not self._closed:
                    log.error("cannot start a worker: %s", None if f.cancelled() else f.exception())
                return
            if len(self._free) + self._busy() < self.n:
                self._free.append(f.result())
                self._notify()
            else:
                self._spares.append(f.result())

        fut.add_done_callback(_ready)

    def _busy(self) -> int:
        return len(self.stats.running)

    def _replace(self, w: _Worker) -> None:
        """Kill a worker (its job is abandoned); a spare takes its place and a new spare starts."""
        with self._lock:
            self._all.discard(w)
        w.kill()
        self.stats.replaced += 1
        if self._closed:
            return
        if self._spares:
            self._free.append(self._spares.pop())
        self._start_spare()

    def _notify(self) -> None:
        if self._changed is not None:
            self._changed.set()

    # ---------------------------------------------------------------- running a job
    def deadline_of(self, job: str, worker=None) -> float:
        """The deadline [s] of ``job`` (on ``worker``: more for its first job of that kind)."""
        if self.deadline_s is not None:
            return self.deadline_s
        first = worker is not None and job not in worker.seen
        return self.deadlines_s.get(job, DEFAULT_DEADLINE_S) + (FIRST_RUN_EXTRA_S if first else 0.0)

    def _take(self, heavy: bool) -> _Worker | None:
        if not self._free or (heavy and self._heavy >= self.heavy_limit):
            return None
        if heavy:
            self._heavy += 1
        return self._free.pop()

    async def _acquire(self, heavy: bool, gone: Callable[[], Awaitable[bool]]) -> _Worker:
        w = self._take(heavy)
        if w is not None:
            return w
        if self._waiting >= self.max_waiting:
            self.stats.refused += 1
            raise PoolError(f"server: busy ({self._waiting} requests are waiting); try again in a moment")
        self._waiting += 1
        t0 = time.monotonic()
        try:
            while True:
                assert self._changed is not None, "Pool.start() was not awaited"
                self._changed.clear()
                try:
                    await asyncio.wait_for(self._changed.wait(), self.poll_s)
                except TimeoutError:
                    pass
                w = self._take(heavy)
                if w is not None:
                    return w
                if await gone():
                    self.stats.cancelled += 1
                    raise ClientGone("request: the client went away")
                if time.monotonic() - t0 > self.wait_s:
                    self.stats.refused += 1
                    raise PoolError(f"server: busy (no worker free within {self.wait_s:g} s); try again")
        finally:
            self._waiting -= 1

    def _release(self, w: _Worker, heavy: bool, *, reuse: bool) -> None:
        if heavy:
            self._heavy -= 1
        if reuse:
            self._free.append(w)
        else:
            self._replace(w)
        self._notify()

    async def run(
        self,
        job: str,
        values: dict,
        extra: dict | None = None,
        *,
        gone: Callable[[], Awaitable[bool]],
    ):
        """Run ``job`` in a worker; returns its JSON-able result.

        Raises :class:`InputError` (the job's own, one line), :class:`ClientGone` when ``gone()``
        turns true, :class:`PoolError` when busy, past the deadline or when the worker died.
        """
        if job not in features.JOBS:
            raise PoolError(f"job: unknown {job!r}", 404)
        heavy = job in HEAVY_JOBS
        w = await self._acquire(heavy, gone)
        deadline = self.deadline_of(job, w)  # a first job of its kind loads (or compiles) its kernels
        loop = asyncio.get_running_loop()
        fut = loop.run_in_executor(self._threads, w.call, job, values, extra or {})
        t0 = time.monotonic()
        self.stats.running[id(fut)] = job
        reuse = False
        left_at = None  # when the client was seen gone
        try:
            while True:
                done, _ = await asyncio.wait({fut}, timeout=self.poll_s)
                if done:
                    break
                now = time.monotonic()
                if now - t0 > deadline:
                    self.stats.timed_out += 1
                    raise PoolError(f"{job}: stopped after {deadline:g} s (the time limit of this computation)")
                if left_at is None and await gone():
                    left_at = now
                if left_at is not None and now - left_at >= self.grace_s:
                    self.stats.cancelled += 1
                    raise ClientGone("request: the client went away")
            try:
                kind, payload = fut.result()
            except (EOFError, OSError) as exc:
                raise PoolError(f"{job}: the worker stopped ({type(exc).__name__})", 500) from None
            reuse = True
            w.seen.add(job)
            self.stats.done += 1
        finally:
            self.stats.running.pop(id(fut), None)
            if not reuse:
                fut.add_done_callback(lambda f: f.exception())  # the killed worker's recv fails: ignore
            self._release(w, heavy, reuse=reuse)
        if kind == "ok":
            return payload
        if kind == "input":
            raise InputError(payload)
        raise PoolError(payload, 500)

    def snapshot(self) -> dict:
        """Workers, jobs running and waiting, and the counters (for ``/api/meta``)."""
        s = self.stats
        return {
            "workers": self.n,
            "heavy_limit": self.heavy_limit,
            "free": len(self._free),
            "spares": len(self._spares),
            "running": sorted(s.running.values()),
            "waiting": self._waiting,
            "done": s.done,
            "cancelled": s.cancelled,
            "timed_out": s.timed_out,
            "refused": s.refused,
            "replaced": s.replaced,
        }
