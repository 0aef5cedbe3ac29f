"""Where chunks run: schedulers chosen by name through a registry.

``local``
    In this process, chunk after chunk (the compiled kernels use their own
    threads, e.g. ``fly_batch(parallel=True)`` runs on all cores).
``processes``
    A ``dask.distributed.LocalCluster`` of worker processes started for the
    job (``n_workers``, default: the number of cores; one thread each, and
    ``NUMBA_NUM_THREADS=1`` so the workers do not oversubscribe the cores).
``tcp://HOST:PORT`` (also ``tls://``)
    Connect a ``dask.distributed.Client`` to a running scheduler
    (``dask scheduler`` / ``dask worker``, see docs/batch.md).
a ``distributed.Client``
    Use that client (not closed afterwards) -- handy in notebooks and tests.

All schedulers run the same task function on the same chunks, so results are
identical to the bit.  Dask runners keep at most ``2 x threads`` chunks in
flight, so memory stays bounded however many chunks the job has.
"""

from __future__ import annotations

import contextlib
import logging
import os
import uuid
from collections.abc import Callable, Iterable, Iterator

from tennislab.errors import InputError

_SCHEDULERS: dict[str, Callable] = {}
_URL_SCHEMES: dict[str, Callable] = {}


def register_scheduler(name: str):
    """Decorator: register ``factory(n_workers) -> runner`` under ``name``."""

    def deco(factory):
        _SCHEDULERS[name] = factory
        return factory

    return deco


def register_url_scheme(scheme: str):
    """Decorator: register ``factory(address, n_workers) -> runner`` for ``scheme://...`` addresses."""

    def deco(factory):
        _URL_SCHEMES[scheme] = factory
        return factory

    return deco


def scheduler_names() -> list[str]:
    return sorted(_SCHEDULERS) + [f"{s}://HOST:PORT" for s in sorted(_URL_SCHEMES)]


def check_scheduler(scheduler) -> str | object:
    """Validate a scheduler spec (name, address or Client); return it or raise InputError."""
    if not isinstance(scheduler, str):
        if _is_client(scheduler):
            return scheduler
        raise InputError(
            f"scheduler: expected a name, an address or a distributed.Client, got {type(scheduler).__name__}"
        )
    if scheduler in _SCHEDULERS:
        return scheduler
    scheme, sep, rest = scheduler.partition("://")
    if sep and scheme in _URL_SCHEMES:
        host, colon, port = rest.rpartition(":")
        if not (colon and host and port.isdigit() and 0 < int(port) < 65536):
            raise InputError(f"scheduler: {scheduler!r} is not an address {scheme}://HOST:PORT")
        return scheduler
    raise InputError(f"scheduler: {scheduler!r} is not one of {', '.join(scheduler_names())}")


def _is_client(obj) -> bool:
    try:
        from distributed import Client
    except ImportError:  # pragma: no cover
        return False
    return isinstance(obj, Client)


def get_runner(scheduler, n_workers: int | None = None):
    """A runner (context manager with ``run``/``share``/``close``) for a scheduler spec."""
    scheduler = check_scheduler(scheduler)
    if not isinstance(scheduler, str):
        return DaskRunner(scheduler, owned=())
    if scheduler in _SCHEDULERS:
        return _SCHEDULERS[scheduler](n_workers)
    scheme = scheduler.partition("://")[0]
    return _URL_SCHEMES[scheme](scheduler, n_workers)


class LocalRunner:
    """Run chunks in this process, in order."""

    name = "local"
    nthreads = 1

    def share(self, obj):
        return obj

    def run(self, func, payloads: Iterable[tuple[int, tuple]]) -> Iterator[tuple[int, object]]:
        for i, args in payloads:
            yield i, func(*args)

    def close(self):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


@register_scheduler("local")
def _local(n_workers=None):
    return LocalRunner()


def _distributed():
    try:
        import distributed
    except ImportError:  # pragma: no cover - depends on the environment
        raise InputError("scheduler: Dask schedulers need dask.distributed (pip install 'tennislab[batch]')") from None
    return distributed


class DaskRunner:
    """Run chunks on a ``dask.distributed`` cluster with a bounded window of tasks in flight."""

    name = "dask"

    def __init__(self, client, owned=()):
        self.client = client
        self._owned = owned  # objects to close after the job (client, cluster)
        self.nthreads = max(1, sum(client.nthreads().values()))
        self._token = uuid.uuid4().hex[:12]

    def share(self, obj):
        """Send ``obj`` to every worker once; tasks get a reference instead of a copy."""
        return self.client.scatter([obj], broadcast=True, hash=False)[0]

    def run(self, func, payloads, max_inflight: int | None = None):
        distributed = _distributed()
        window = max_inflight or max(2, 2 * self.nthreads)
        it = iter(payloads)
        ac = distributed.as_completed(loop=self.client.loop)
        index = {}

        def submit_next() -> bool:
            try:
                i, args = next(it)
            except StopIteration:
                return False
            fut = self.client.submit(func, *args, key=f"tennislab-chunk-{self._token}-{i}")
            index[fut.key] = i
            ac.add(fut)
            return True

        for _ in range(window):
            if not submit_next():
                break
        try:
            for fut in ac:
                res = fut.result()
                i = index.pop(fut.key)
                fut.release()
                submit_next()
                yield i, res
        finally:
            pending = list(ac.futures) if hasattr(ac, "futures") else []
            for fut in pending:
                fut.cancel()

    def close(self):
        with _quiet_distributed():  # no INFO lines from the cluster shutting down
            for obj in self._owned:
                try:
                    obj.close()
                except Exception:  # pragma: no cover - best effort shutdown
                    pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


@contextlib.contextmanager
def _quiet_distributed(level: int = logging.ERROR):
    names = [n for n in logging.root.manager.loggerDict if n == "distributed" or n.startswith("distributed.")]
    old = {n: logging.getLogger(n).level for n in names}
    for n in names:
        logging.getLogger(n).setLevel(level)
    try:
        yield
    finally:
        for n, lv in old.items():
            logging.getLogger(n).setLevel(lv)


@contextlib.contextmanager
def worker_environment(**env: str):
    """Environment variables set *before* Dask spawns worker processes.

    (``LocalCluster(env=...)`` sets them after the worker has started, too late
    for ``NUMBA_NUM_THREADS`` if numba was already imported -- e.g. by the
    re-imported ``__main__`` module of a script -- which makes numba refuse to
    compile later.)
    """
    import dask

    key = "distributed.nanny.pre-spawn-environ"
    merged = dict(dask.config.get(key, default={}) or {}, **env)
    saved = {k: os.environ.get(k) for k in env}
    try:
        with dask.config.set({key: merged}):
            yield
    finally:
        # the nanny writes pre-spawn-environ into this process's os.environ too; restore it so
        # that numba in this process does not see a changed NUMBA_NUM_THREADS (it then refuses
        # to compile anything new)
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


@register_scheduler("processes")
def _processes(n_workers=None):
    distributed = _distributed()
    n = int(n_workers or os.cpu_count() or 1)
    if n < 1:
        raise InputError(f"n_workers: {n} is outside the allowed range [1, inf]")
    with worker_environment(NUMBA_NUM_THREADS="1"):
        cluster = distributed.LocalCluster(
            n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0", silence_logs=logging.ERROR
        )
    client = distributed.Client(cluster, set_as_default=False)
    return DaskRunner(client, owned=(client, cluster))


def _connect(address, n_workers=None):
    distributed = _distributed()
    try:
        client = distributed.Client(address, timeout="10s", set_as_default=False)
    except (OSError, TimeoutError) as exc:
        raise InputError(f"scheduler: cannot connect to {address} ({exc.__class__.__name__})") from None
    return DaskRunner(client, owned=(client,))


for _scheme in ("tcp", "tls"):
    register_url_scheme(_scheme)(_connect)
