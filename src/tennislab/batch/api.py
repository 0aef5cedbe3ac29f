"""``map_chunks``: one call for batch work in process, on local cores or on a Dask cluster.

The job is ``fn`` applied to the input rows chunk by chunk.  Per-row results
depend only on the row (the compiled kernels are deterministic per row, and
random draws come from :mod:`tennislab.batch.rng` keyed by (seed, row)), so the
scheduler, the chunk size and resuming never change a single bit of the
output; chunks are always concatenated in row order.

``on_chunk`` hands each chunk's outputs to the caller as it finishes (e.g. to
insert rows into a database); ``skip`` and ``max_chunks`` let such a caller
resume from its own record of finished chunks and stop early.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import os
import time
from dataclasses import dataclass

import numpy as np

from tennislab.batch.progress import ProgressBar, progress_mode
from tennislab.batch.schedulers import check_scheduler, get_runner
from tennislab.batch.sources import as_source, default_chunk_size, hash_arrays, is_indexable
from tennislab.batch.store import MANIFEST, ChunkStore, load_manifest
from tennislab.errors import InputError


@dataclass
class BatchResult:
    """What a batch run did.  ``data`` holds the concatenated outputs (None if ``collect=False``).

    ``computed``: chunks run by ``fn`` in this call; ``skipped``: chunks not run
    because they were finished (in ``out`` or in ``skip``), including the
    ``restored`` ones: read back from ``out`` and passed to ``on_chunk``.
    ``complete``: False when ``max_chunks`` stopped the run with chunks left.
    """

    data: dict | None
    n_rows: int
    n_chunks: int
    computed: int
    skipped: int
    seconds: float
    chunk_size: int | None
    out: str | None
    scheduler: str
    restored: int = 0
    complete: bool = True


# ------------------------------------------------------------------ the task
def execute_chunk(fn, payload, row0: int, row_key, include_inputs: bool):
    """Run ``fn`` on one chunk (on a worker or in process) and check its outputs.

    ``payload`` is either the chunk's input dict or ``(source, i, chunk_size)``
    for sources that workers materialise themselves (e.g. a GridSpec).
    """
    chunk = payload[0].chunk(payload[1], payload[2]) if isinstance(payload, tuple) else payload
    n = len(next(iter(chunk.values())))
    if row_key is not None and row_key not in chunk:
        chunk = dict(chunk)
        chunk[row_key] = np.arange(row0, row0 + n, dtype=np.int64)
    out = fn(chunk)
    if not isinstance(out, dict):
        raise TypeError(f"batch fn {_name(fn)} returned {type(out).__name__}, expected a dict of arrays")
    clean = {}
    for k, v in out.items():
        a = np.asarray(v)
        if not isinstance(k, str) or a.ndim == 0 or a.shape[0] != n:
            raise TypeError(f"batch fn {_name(fn)}: output {k!r} has shape {a.shape}, expected {n} rows")
        clean[k] = a
    if include_inputs:
        both = set(chunk) & set(clean)
        if both:
            raise TypeError(f"batch fn {_name(fn)}: outputs {sorted(both)} clash with input names")
        clean = {**chunk, **clean}
    return clean


# ------------------------------------------------------------ job identity
def _name(fn) -> str:
    f = fn.func if isinstance(fn, functools.partial) else fn
    f = getattr(f, "py_func", f)
    mod = getattr(f, "__module__", None) or type(f).__module__
    qual = getattr(f, "__qualname__", None) or type(f).__qualname__
    return f"{mod}.{qual}"


def describe(obj, depth: int = 0):
    """A stable, JSON-able description of a function and its bound parameters.

    Used to fingerprint the job in the manifest (a partial with other physics
    parameters is another job).  Arrays are hashed; objects without a stable
    description fall back to their type name (add a ``tag`` to be safe).
    """
    if depth > 8:
        return "..."
    if isinstance(obj, functools.partial):
        return {
            "partial": describe(obj.func, depth + 1),
            "args": [describe(a, depth + 1) for a in obj.args],
            "kwargs": {k: describe(v, depth + 1) for k, v in sorted(obj.keywords.items())},
        }
    if obj is None or isinstance(obj, (bool, int, float, str)):
        return obj if not isinstance(obj, float) else repr(obj)
    if isinstance(obj, np.generic):
        return repr(obj.item())
    if isinstance(obj, np.ndarray):
        return "array:" + hash_arrays({"a": obj})
    if isinstance(obj, (list, tuple)):
        return [describe(v, depth + 1) for v in obj]
    if isinstance(obj, dict):
        return {str(k): describe(v, depth + 1) for k, v in sorted(obj.items(), key=lambda kv: str(kv[0]))}
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {
            "type": type(obj).__qualname__,
            **{f.name: describe(getattr(obj, f.name), depth + 1) for f in dataclasses.fields(obj)},
        }
    if callable(obj):
        return _name(obj)
    r = repr(obj)
    return type(obj).__qualname__ if " at 0x" in r else r


def _digest(obj) -> str:
    return hashlib.blake2b(json.dumps(obj, sort_keys=True).encode(), digest_size=12).hexdigest()


# ------------------------------------------------------------------ the API
def run_batch(
    fn,
    inputs,
    *,
    scheduler="local",
    chunk_size: int | None = None,
    out: str | None = None,
    progress="auto",
    desc: str = "",
    n_workers: int | None = None,
    collect: bool = True,
    tag=None,
    include_inputs: bool = False,
    row_key: str | None = None,
    max_inflight: int | None = None,
    on_chunk=None,
    skip=None,
    max_chunks: int | None = None,
    unit: str = "rows",
    count=None,
    total_units: int | None = None,
) -> BatchResult:
    """Like :func:`map_chunks` but always returns a :class:`BatchResult` (counts, timing, data)."""
    t0 = time.perf_counter()
    source = as_source(inputs)
    scheduler = check_scheduler(scheduler)
    if on_chunk is not None and not callable(on_chunk):
        raise InputError(f"on_chunk: expected a callable (chunk_index, row0, outputs), got {type(on_chunk).__name__}")
    if not collect and out is None and on_chunk is None:
        raise InputError("collect: collect=False needs an output directory (out=...) or an on_chunk callback")
    if n_workers is not None and int(n_workers) < 1:
        raise InputError(f"n_workers: {n_workers} is outside the allowed range [1, inf]")
    indexable = is_indexable(source)
    if skip is not None:
        skip = {int(i) for i in skip}
        if collect and out is None:
            raise InputError("skip: skipped chunks cannot be collected without out=...; pass collect=False")
    if max_chunks is not None:
        if int(max_chunks) < 1:
            raise InputError(f"max_chunks: {max_chunks} is outside the allowed range [1, inf]")
        if collect or not indexable:
            raise InputError("max_chunks: needs collect=False and an indexable source (dict of arrays, GridSpec, ...)")
        max_chunks = int(max_chunks)
    if chunk_size is not None and int(chunk_size) < 1:
        raise InputError(f"chunk_size: {chunk_size} is outside the allowed range [1, inf]")
    store = None
    if out is not None:
        manifest = {
            "fn": {"name": _name(fn), "config": _digest(describe(fn))},
            "tag": describe(tag),
            "source": source.kind,
            "fingerprint": source.fingerprint(),
            "n_rows": source.n_rows,
            "row_key": row_key,
            "include_inputs": bool(include_inputs),
        }
        if indexable and chunk_size is None:  # resume with the chunking found on disk
            chunk_size = _existing_chunk_size(out) or default_chunk_size(source.n_rows)
        manifest["chunk_size"] = int(chunk_size) if (indexable and chunk_size) else None
        store = ChunkStore(out, manifest, lock=True)
    if indexable:
        chunk_size = int(chunk_size or default_chunk_size(source.n_rows))
    else:
        chunk_size = None
    ok = False
    try:
        res = _run(
            fn,
            source,
            scheduler,
            n_workers,
            store,
            indexable,
            chunk_size,
            {"progress": progress, "desc": desc, "unit": unit, "count": count, "total_units": total_units},
            collect,
            row_key,
            include_inputs,
            max_inflight,
            t0,
            on_chunk,
            skip,
            max_chunks,
        )
        ok = True
        return res
    finally:
        if store is not None:
            store.close()
            if not ok:  # a run that failed before writing any part leaves no directory it created
                store.discard_if_unused()


def _run(
    fn,
    source,
    scheduler,
    n_workers,
    store,
    indexable,
    chunk_size,
    show,
    collect,
    row_key,
    include_inputs,
    max_inflight,
    t0,
    on_chunk=None,
    skip=None,
    max_chunks=None,
) -> BatchResult:
    if indexable:
        n_total = source.n_chunks(chunk_size)
    else:
        n_total = source.n_chunks()
    done = store.done() if store is not None else set()
    skip = skip or set()
    # not computed: the store's parts, or (without a store) the caller's finished chunks; with a store,
    # chunks in `skip` but not on disk are computed so that the output directory is complete
    have = done if store is not None else skip

    def restore(i: int) -> bool:  # (for i in have) a part on disk the caller lacks: read back for on_chunk
        return on_chunk is not None and store is not None and i not in skip

    count = show["count"]
    total_units = show["total_units"]
    if total_units is None and count is None and indexable:
        total_units = source.n_rows  # the rows are the units
    per_row = (total_units / source.n_rows) if (total_units and indexable and source.n_rows) else 1.0
    mode = progress_mode(show["progress"])
    bar = ProgressBar(
        n_total, desc=show["desc"], enabled=mode is not None, mode=mode, unit=show["unit"], total_units=total_units
    )

    def skipped(i: int) -> None:  # a chunk not computed here: its units count toward completion
        lo, hi, _ = row_range(i)
        bar.skip(n_units=round((hi - lo) * per_row))

    results: dict[int, dict] = {}
    schema: dict = {}
    counts = {"computed": 0, "skipped": 0, "seen": 0, "restored": 0, "taken": 0, "cut": False}
    if indexable:  # counted up front: a max_chunks run stops scanning early
        counts["skipped"] = sum(1 for i in have if 0 <= i < n_total)

    def deliver_restored(i: int, lo: int) -> None:
        res = store.read(i)
        counts["restored"] += 1
        if collect:
            results[i] = res
        on_chunk(i, lo, res)

    stream_ranges: dict[int, tuple[int, int, str | None]] = {}  # (lo, hi, input hash) of stream chunks

    def row_range(i: int) -> tuple[int, int, str | None]:
        if indexable:  # by arithmetic: no per-chunk bookkeeping for 10^5-chunk grids
            return i * chunk_size, min(source.n_rows, (i + 1) * chunk_size), None
        return stream_ranges[i]

    def payloads(shared_fn, shared_src):
        if indexable:
            for i in range(n_total):
                lo = i * chunk_size
                counts["seen"] = i + 1
                if i in have and not restore(i):
                    skipped(i)
                    continue
                if max_chunks is not None and counts["taken"] >= max_chunks:
                    counts["cut"] = True  # work left for a rerun
                    return
                counts["taken"] += 1
                if i in have:
                    skipped(i)
                    deliver_restored(i, lo)
                    continue
                payload = (shared_src, i, chunk_size) if source.remote else source.chunk(i, chunk_size)
                yield i, (shared_fn, payload, lo, row_key, include_inputs)
            return
        lo = 0
        for i, chunk in enumerate(source):
            n = len(next(iter(chunk.values())))
            h = hash_arrays(chunk)
            stream_ranges[i] = (lo, lo + n, h)
            counts["seen"] = i + 1
            if i in have:
                if store is not None:
                    old = store.read_meta(i).get("input_hash")
                    if old != h:
                        raise InputError(
                            f"out: {store.path} holds another job (input chunk {i} differs); "
                            "use a new --out-dir or delete the old one"
                        )
                counts["skipped"] += 1
                skipped(i)
                if store is not None and restore(i):
                    deliver_restored(i, lo)
            else:
                yield i, (shared_fn, chunk, lo, row_key, include_inputs)
            lo += n

    all_done = indexable and have.issuperset(range(n_total))
    with get_runner("local" if all_done else scheduler, n_workers) as runner:  # no cluster to read parts
        shared_fn = runner.share(fn)
        shared_src = runner.share(source) if (indexable and source.remote) else source
        try:
            for i, res in runner.run(
                execute_chunk,
                payloads(shared_fn, shared_src),
                **({"max_inflight": max_inflight} if max_inflight else {}),
            ):
                _check_schema(schema, res, fn)
                lo, hi, h = row_range(i)
                if store is not None:
                    store.write(i, res, {"rows": [lo, hi], "input_hash": h})
                if collect:
                    results[i] = res
                counts["computed"] += 1
                bar.update(hi - lo if count is None else int(count(res)))
                if on_chunk is not None:
                    on_chunk(i, lo, res)
        finally:
            bar.close()
    n_chunks = n_total if indexable else counts["seen"]
    n_rows = row_range(n_chunks - 1)[1] if n_chunks else 0
    extra = sorted(i for i in done if i >= n_chunks)
    if extra:  # a stream that is shorter than the one that made this output
        raise InputError(
            f"out: {store.path} holds another job (it has chunk {extra[0]}, "
            f"the inputs have only {n_chunks} chunks); use a new --out-dir or delete the old one"
        )
    if store is not None and not counts["cut"]:
        store.finish(n_chunks, n_rows)
    data = None
    if collect:
        data = _concatenate(results, store, n_chunks, fn, source, chunk_size, row_key, include_inputs)
    return BatchResult(
        data,
        n_rows,
        n_chunks,
        counts["computed"],
        counts["skipped"],
        time.perf_counter() - t0,
        chunk_size,
        store.path if store else None,
        scheduler if isinstance(scheduler, str) else "client",
        counts["restored"],
        not counts["cut"],
    )


def map_chunks(
    fn,
    inputs,
    *,
    scheduler="local",
    chunk_size: int | None = None,
    out: str | None = None,
    progress="auto",
    desc: str = "",
    n_workers: int | None = None,
    collect: bool = True,
    tag=None,
    include_inputs: bool = False,
    row_key: str | None = None,
    on_chunk=None,
    skip=None,
    max_chunks: int | None = None,
    unit: str = "rows",
    count=None,
    total_units: int | None = None,
):
    """Apply ``fn`` to ``inputs`` chunk by chunk on a scheduler; return the concatenated outputs.

    Parameters
    ----------
    fn : picklable function ``dict[str, ndarray] -> dict[str, ndarray]`` (one
        chunk in, one output row per input row out).  Bind parameters with
        ``functools.partial`` (they are part of the job's fingerprint).
    inputs : dict of equal-length arrays (N rows), an indexable chunk source
        (e.g. :class:`~tennislab.batch.grid.GridSpec`) or an iterable of chunk dicts.
    scheduler : ``"local"`` (in process), ``"processes"`` (a LocalCluster),
        ``"tcp://HOST:PORT"`` (a running Dask scheduler) or a ``distributed.Client``.
    chunk_size : rows per chunk (default ~N/64 clamped to [1024, 65536]; on a
        resume, the chunk size of the existing output).
    out : directory for ``part-NNNNN.parquet`` + ``manifest.json``; a rerun skips
        finished chunks, another job in the same directory is an ``InputError``.
    progress : ``"auto"`` (default: a bar on stderr when it is a terminal and the work takes over
        ~5 s), True (on a terminal, from the start), ``"always"`` (on any stream: a bar on a terminal,
        a line every few seconds in a log), or False (:mod:`tennislab.batch.progress`).
    desc : text shown after the progress.
    unit, count, total_units : what progress counts, in the user's units: ``unit`` names them
        ("serves"), ``count(outputs) -> int`` the units a chunk's outputs stand for (default: its
        rows) and ``total_units`` the job's (default: its rows, when known).
    n_workers : worker processes for ``"processes"`` (default: number of cores).
    collect : False returns a :class:`BatchResult` without data (needs ``out``
        or ``on_chunk``): memory stays bounded by a few chunks however large the job.
    tag : anything JSON-able identifying the job beyond ``fn`` and ``inputs``.
    include_inputs : also return/store the input columns next to the outputs.
    row_key : add the global row index (int64) to every chunk under this name.
    on_chunk : ``callable(chunk_index, row0, outputs)``, called in this (the
        parent) process once per chunk of the job that is not in ``skip``, with
        the chunk's outputs (``dict[str, ndarray]``, as stored; rows
        [row0, row0 + n)), after its Parquet part (if ``out``) is written.
        Order: completion order -- any order on a Dask scheduler, chunk order
        on ``local``.  On a resume, finished parts found in ``out`` are read
        back and passed to it too (as the scan reaches them), so every chunk
        reaches the callback once per call.  An exception raised in it stops
        the run (chunks in flight are cancelled; parts already written stay).
    skip : chunk indices the caller already has (e.g. recorded in its own
        database): not run and not passed to ``on_chunk``.  With ``out``, a
        chunk of ``skip`` without a part on disk is still computed (and passed
        to ``on_chunk``) so that the output directory is complete; without
        ``out`` it needs ``collect=False``.
    max_chunks : stop after this many chunks were computed or restored for
        ``on_chunk`` (the rest is left for a rerun; ``out`` is then not marked
        complete).  Needs ``collect=False`` and an indexable source.

    Returns the outputs as ``dict[str, ndarray]`` in row order (or a
    :class:`BatchResult` if ``collect=False``).
    """
    res = run_batch(
        fn,
        inputs,
        scheduler=scheduler,
        chunk_size=chunk_size,
        out=out,
        progress=progress,
        desc=desc,
        n_workers=n_workers,
        collect=collect,
        tag=tag,
        include_inputs=include_inputs,
        row_key=row_key,
        on_chunk=on_chunk,
        skip=skip,
        max_chunks=max_chunks,
        unit=unit,
        count=count,
        total_units=total_units,
    )
    return res.data if collect else res


def _existing_chunk_size(out) -> int | None:
    """The chunk size recorded in ``out``'s manifest, if it has a readable one (else the store refuses it)."""
    if not os.path.isfile(os.path.join(os.fspath(out), MANIFEST)):
        return None
    try:
        size = load_manifest(out).get("chunk_size")
    except InputError:
        return None
    return size if isinstance(size, int) and size >= 1 else None


def _check_schema(schema: dict, res: dict, fn) -> None:
    # strings may be wider in one chunk than in another: compare their kind only
    sig = {k: (v.dtype.kind if v.dtype.kind in "USO" else v.dtype.str, v.shape[1:]) for k, v in res.items()}
    if not schema:
        schema.update(sig)
    elif sig != schema:
        raise TypeError(f"batch fn {_name(fn)}: chunk outputs differ in names/dtypes ({sig} vs {schema})")


def _concatenate(results, store, n_chunks, fn, source, chunk_size, row_key, include_inputs):
    parts = []
    for i in range(n_chunks):
        parts.append(results.pop(i) if i in results else store.read(i))
    if not parts:  # zero rows: run fn on the empty chunk for the output names and dtypes
        if is_indexable(source):
            parts = [execute_chunk(fn, source.chunk(0, chunk_size or 1), 0, row_key, include_inputs)]
        else:
            return {}
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
