"""Filling the hits database: the machine's settings grid, flown in chunks.

The grid is the machine's own (Wojcicki et al. 2010 section 2: height 0.1 m, speed 1 km/h,
elevation, heading and spin-axis rotation 1 deg, spin 1 rpm steps), restricted
to the ranges asked for and optionally coarsened by an integer stride.  Rows
are enumerated lazily by index arithmetic (:class:`TableGrid`, the same C order
as :class:`tennislab.batch.grid.GridSpec`), in the order :data:`AXES` (height
slowest, heading fastest), so that one chunk holds neighbouring elevations and
headings of one speed and spin: compact landing patches, which keeps the
R*Tree tight.

Each chunk is flown with :func:`tennislab.core.flight.fly_batch` on
:func:`tennislab.launcher.machine.machine_states` (:func:`fly_chunk`, through
:func:`tennislab.batch.run_batch` on any of its schedulers); :func:`select_hits` keeps a row
when the ball lands (status 0), clears the net (``net_status`` over) and lands
in the doubles area of the half opposite the machine plus
:data:`KEEP_MARGIN_M` (a controller never aims elsewhere; the optional Parquet
output keeps every row).  With zero spin every spin-axis rotation is the same
flight, so only the rotation nearest 0 deg is stored.  Each landed flight that
clears the net is flown a second time 0.01 deg higher: whether it lands farther
(the rising, ``low`` branch) or nearer (the falling, ``high`` branch, lobs) is
stored as ``branch`` for the trajectory preferences of a lookup.

A row's ``id`` packs its per-setting grid indices in mixed radix
(:func:`pack_ids`): stable for a machine spec, so a resumed or overlapping fill
inserts each setting once.
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
import os
import sqlite3
import time
from dataclasses import dataclass

import numpy as np

import tennislab.launcher.db as _db
from tennislab.batch import run_batch
from tennislab.batch.grid import GridSpec
from tennislab.core.events import NET_OVER, STATUS_OK
from tennislab.errors import InputError, check_finite
from tennislab.launcher.machine import machine_states
from tennislab.launcher.preferences import BRANCH_HIGH, BRANCH_LOW
from tennislab.results import Result, jsonable
from tennislab.units import RPM

#: Elevation step [deg] of the second flight that tells a hit's branch (low: it lands farther).
BRANCH_STEP_DEG = 0.01

#: Setting order of the grid (first slowest) and of the packed id.
AXES = ("height_m", "speed_kmh", "spin_rpm", "spin_axis_deg", "elevation_deg", "heading_deg")
#: Kept landing area: the doubles court of the half opposite the machine plus this margin [m].
KEEP_MARGIN_M = 1.0
#: Default rows per chunk (one transaction each; ~0.1-0.3 s of fly_batch on 2 cores).
DEFAULT_CHUNK = 20_000


def axis_size(rng) -> int:
    """Number of steps of a machine :class:`~tennislab.launcher.machine.Range`."""
    return int(math.floor((rng.hi - rng.lo) / rng.step + 1e-9)) + 1


def axis_values(rng, idx) -> np.ndarray:
    """Setting values at grid indices ``idx`` (rounded like ``Range.quantise``)."""
    return np.round(rng.lo + np.asarray(idx, dtype=np.int64) * rng.step, 9)


def machine_sizes(spec) -> dict[str, int]:
    return {f: axis_size(spec.range_of(f)) for f in AXES}


def pack_ids(indices: dict, sizes: dict) -> np.ndarray:
    """Row ids: the per-setting grid indices (arrays) in mixed radix, order :data:`AXES`."""
    out = np.zeros(np.shape(indices[AXES[0]]), dtype=np.int64)
    for f in AXES:
        out = out * int(sizes[f]) + np.asarray(indices[f], dtype=np.int64)
    return out


def unpack_ids(ids, sizes: dict) -> dict:
    """Inverse of :func:`pack_ids`."""
    rem = np.asarray(ids, dtype=np.int64).copy()
    out = {}
    for f in reversed(AXES):
        out[f] = rem % int(sizes[f])
        rem //= int(sizes[f])
    return {f: out[f] for f in AXES}


def axis_indices(spec, field: str, lo=None, hi=None, stride: int = 1) -> np.ndarray:
    """Machine grid indices of ``field`` within [lo, hi] (edge units), every ``stride``-th step.

    The bounds must lie within the machine's range; they are widened to the
    enclosing steps.  The last step within [lo, hi] is always included.
    """
    rng = spec.range_of(field)
    lo = rng.lo if lo is None else rng.check(f"{field} min", lo)
    hi = rng.hi if hi is None else rng.check(f"{field} max", hi)
    if lo > hi:
        raise InputError(f"{field}: min {lo:g} > max {hi:g} {rng.unit}")
    if int(stride) < 1:
        raise InputError(f"{field} stride: must be >= 1, got {stride}")
    k0 = int(math.floor((lo - rng.lo) / rng.step + 1e-9))
    k1 = int(math.floor((hi - rng.lo) / rng.step + 1e-9))
    k1 = min(k1, axis_size(rng) - 1)
    idx = np.arange(k0, k1 + 1, int(stride), dtype=np.int64)
    if idx[-1] != k1:
        idx = np.append(idx, k1)
    return idx


@dataclass(frozen=True)
class TableGrid:
    """A sub-grid of the machine's settings grid: per setting, sorted machine grid indices."""

    indices: dict

    @property
    def shape(self) -> tuple:
        return tuple(len(self.indices[f]) for f in AXES)

    @property
    def size(self) -> int:
        return math.prod(self.shape)

    def to_json(self) -> str:
        return json.dumps({f: np.asarray(self.indices[f]).tolist() for f in AXES}, separators=(",", ":"))

    def grid_spec(self) -> GridSpec:
        """The lazy :class:`tennislab.batch.grid.GridSpec` over the indices."""
        return GridSpec({f: np.asarray(self.indices[f], dtype=np.int64) for f in AXES})

    def chunk(self, i: int, chunk_size: int) -> dict:
        """Index arrays of chunk ``i`` (rows [i c, (i+1) c), first axis slowest)."""
        lo = int(i) * int(chunk_size)
        hi = min(self.size, lo + int(chunk_size))
        rem = np.arange(lo, max(lo, hi), dtype=np.int64)
        out = {}
        for f in reversed(AXES):
            a = np.asarray(self.indices[f])
            out[f] = a[rem % a.size]
            rem //= a.size
        return {f: out[f] for f in AXES}


def make_grid(spec, ranges: dict | None = None, strides: dict | None = None) -> TableGrid:
    """The sub-grid for ``ranges`` {field: (lo, hi)} and ``strides`` {field: int} (defaults: all, 1)."""
    ranges = ranges or {}
    strides = strides or {}
    for name in list(ranges) + list(strides):
        if name not in AXES:
            raise InputError(f"{name}: unknown setting; allowed: {', '.join(AXES)}")
    idx = {}
    for f in AXES:
        lo, hi = ranges.get(f) or (None, None)
        idx[f] = axis_indices(spec, f, lo, hi, strides.get(f, 1))
    return TableGrid(idx)


#: Per-row columns of a flown chunk (:func:`fly_chunk`), besides the settings of :data:`AXES`.
ROW_COLUMNS = (
    ("id",)
    + AXES
    + (
        "land_x",
        "land_y",
        "net_clearance_m",
        "flight_time_s",
        "bounce_speed_ms",
        "bounce_spin_rpm",
        "apex_z_m",
        "status",
        "net_status",
        "branch",
    )
)


def fly_chunk(indices: dict, spec, params) -> dict:
    """Fly one chunk of grid indices; per-row arrays named :data:`ROW_COLUMNS` (every row).

    ``status`` is :func:`fly_batch`'s (0 landed, 1 no landing within t_max);
    ``net_status`` 0 never reached the net, 1 over, 2 into the net; ``branch`` 0 low,
    1 high (:func:`flight_branch`; -1 for flights that do not land over the net).  Pure
    computation (no I/O), so it runs on worker processes or a cluster.
    """
    sizes = machine_sizes(spec)
    idx = {f: np.asarray(indices[f], dtype=np.int64) for f in AXES}
    vals = {f: axis_values(spec.range_of(f), idx[f]) for f in AXES}
    out = {"id": pack_ids(idx, sizes)}
    out.update(vals)
    n = len(out["id"])
    if n == 0:
        out.update({c: np.empty(0) for c in ROW_COLUMNS if c not in out})
        return out
    from tennislab.core.flight import fly_batch  # the compiled flight: loaded by what flies (not by readers)

    states = machine_states(
        spec,
        vals["height_m"],
        vals["speed_kmh"],
        vals["elevation_deg"],
        vals["heading_deg"],
        vals["spin_rpm"],
        vals["spin_axis_deg"],
    )
    tab = fly_batch(states, params, rtol=_db.FILL_RTOL, atol=_db.FILL_ATOL)
    vel = np.stack([tab["land_vx"], tab["land_vy"], tab["land_vz"]], axis=1)
    spin = np.stack([tab["land_wx"], tab["land_wy"], tab["land_wz"]], axis=1)
    out.update(
        {
            "land_x": tab["land_x"],
            "land_y": tab["land_y"],
            "net_clearance_m": tab.clearance,
            "flight_time_s": tab["land_t"],
            "bounce_speed_ms": np.linalg.norm(vel, axis=1),
            "bounce_spin_rpm": np.linalg.norm(spin, axis=1) / RPM,
            "apex_z_m": tab["apex_z"],
            "status": tab["status"].astype(np.int8),
            "net_status": tab["net_status"].astype(np.int8),
        }
    )
    branch = np.full(n, -1, dtype=np.int8)
    ok = (out["status"] == STATUS_OK) & (out["net_status"] == NET_OVER)
    if ok.any():
        branch[ok] = flight_branch({c: np.asarray(out[c])[ok] for c in out}, spec, params)
    out["branch"] = branch
    return out


def flight_branch(rows: dict, spec, params) -> np.ndarray:
    """0 (low) or 1 (high) per row: does the same shot :data:`BRANCH_STEP_DEG` higher land farther or nearer?

    The distance is measured from the machine along the launch heading; "farther" is the rising
    branch of distance against elevation (a drive), "nearer" the falling one (a lob), the same
    split as ``launcher aim``'s low and high solutions.
    """
    from tennislab.core.flight import fly_batch  # the compiled flight: loaded by what flies (not by readers)

    st = machine_states(
        spec,
        rows["height_m"],
        rows["speed_kmh"],
        np.asarray(rows["elevation_deg"], float) + BRANCH_STEP_DEG,
        rows["heading_deg"],
        rows["spin_rpm"],
        rows["spin_axis_deg"],
    )
    tab = fly_batch(st, params, rtol=_db.FILL_RTOL, atol=_db.FILL_ATOL)
    b = np.radians(np.asarray(rows["heading_deg"], float))
    px, py = spec.position
    d0 = (np.asarray(rows["land_x"]) - px) * np.cos(b) + (np.asarray(rows["land_y"]) - py) * np.sin(b)
    d1 = (tab["land_x"] - px) * np.cos(b) + (tab["land_y"] - py) * np.sin(b)
    with np.errstate(invalid="ignore"):
        return np.where(d1 >= d0, BRANCH_LOW, BRANCH_HIGH).astype(np.int8)


def select_hits(
    rows: dict, spec, court, keep_margin: float = KEEP_MARGIN_M, axis0: float | None = None, params=None
) -> dict:
    """The rows of a flown chunk that go into ``hits`` (module docstring), as :data:`db.HIT_COLUMNS`.

    Kept: landed, cleared the net, landing in the doubles area of the half
    opposite the machine (the far half for a machine at x < 0) + margin;
    with zero spin only the spin-axis rotation ``axis0`` (default: the machine's
    step nearest 0 deg; a fill passes its grid's rotation nearest 0 deg).  Rows
    without ``branch`` (Parquet parts of an older fill) get it flown with ``params``.
    """
    if axis0 is None:
        ax = spec.range_of("spin_axis_deg")
        axis0 = float(axis_values(ax, int(np.clip(round((0.0 - ax.lo) / ax.step), 0, axis_size(ax) - 1))))
    side = 1.0 if spec.position[0] < 0 else -1.0  # the half opposite the machine
    x, y = side * np.asarray(rows["land_x"]), rows["land_y"]
    with np.errstate(invalid="ignore"):
        ok = (
            (rows["status"] == STATUS_OK)
            & (rows["net_status"] == NET_OVER)
            & (x > 0.0)
            & (x <= court.length / 2 + keep_margin)
            & (np.abs(y) <= court.doubles_width / 2 + keep_margin)
            & ~((rows["spin_rpm"] == 0.0) & (rows["spin_axis_deg"] != axis0))
        )
    out = {c: np.asarray(rows[c])[ok] for c in _db.HIT_COLUMNS if c in rows}
    if "branch" not in out:
        if params is None:
            raise InputError("rows: no branch column; pass params to fly it")
        out["branch"] = flight_branch(out, spec, params) if len(out["id"]) else np.empty(0, np.int8)
    return out


def fill_chunk(indices: dict, spec, params, keep_margin: float = KEEP_MARGIN_M) -> dict:
    """:func:`fly_chunk` then :func:`select_hits`: the hits of one chunk."""
    return select_hits(fly_chunk(indices, spec, params), spec, params.court, keep_margin)


# ------------------------------------------------------------ fill bookkeeping
def begin_fill(
    conn: sqlite3.Connection, grid_json: str, n_rows: int, chunk_size: int, register: bool = True
) -> tuple[int | None, set]:
    """Register (or find) a fill of one settings grid; return (fill id, set of finished chunks).

    ``register=False`` only looks (and checks the chunk size): fill id None if the grid is new.
    """
    gh = hashlib.sha256(grid_json.encode()).hexdigest()
    n_chunks = -(-int(n_rows) // int(chunk_size))
    conn.execute("BEGIN IMMEDIATE")
    try:
        row = conn.execute("SELECT id, chunk_size FROM fills WHERE grid_hash = ?", (gh,)).fetchone()
        if row is None and not register:
            fid = None
        elif row is None:
            cur = conn.execute(
                "INSERT INTO fills (grid_hash, grid_json, n_rows, chunk_size, n_chunks, "
                "started_utc) VALUES (?, ?, ?, ?, ?, ?)",
                (gh, grid_json, int(n_rows), int(chunk_size), n_chunks, _db._now()),
            )
            fid = cur.lastrowid
        else:
            fid = row[0]
            if row[1] != chunk_size:
                raise InputError(
                    f"chunk_size: this grid was started with chunks of {row[1]} rows; "
                    f"resume with the same size (got {chunk_size})"
                )
        done = (
            {r[0] for r in conn.execute("SELECT chunk FROM fill_chunks WHERE fill_id = ?", (fid,))}
            if fid is not None
            else set()
        )
        conn.execute("COMMIT")
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    return fid, done


def store_chunk(conn: sqlite3.Connection, fill_id: int, chunk: int, hits: dict) -> int:
    """Insert one chunk's hits and mark the chunk finished, in one transaction."""
    conn.execute("BEGIN IMMEDIATE")
    try:
        n = _db.insert_hits(conn, hits)
        conn.execute("INSERT OR REPLACE INTO fill_chunks VALUES (?, ?, ?)", (fill_id, int(chunk), n))
        conn.execute("COMMIT")
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    return n


def finish_fill(conn: sqlite3.Connection, fill_id: int) -> None:
    with conn:
        conn.execute(
            "UPDATE fills SET finished_utc = ? WHERE id = ? AND "
            "(SELECT count(*) FROM fill_chunks WHERE fill_id = ?) = n_chunks",
            (_db._now(), fill_id, fill_id),
        )


@dataclass(frozen=True)
class FillReport(Result):
    """What a fill did (the JSON of ``launcher table``)."""

    path: str
    hash: str
    grid_rows: int
    n_chunks: int
    chunks_done_before: int
    chunks_run: int
    hits_inserted: int
    hits_total: int
    seconds: float
    chunks_restored: int = 0  #: of ``chunks_run``: read back from ``out_dir`` instead of flown


@dataclass(frozen=True)
class FillReports(Result):
    """The fills of one ``launcher table`` run (one per drill shot with ``--drill``): its JSON is the
    one report itself, or ``{"fills": [...], "hits_total": N}`` for several."""

    fills: tuple

    def to_dict(self) -> dict:
        if len(self.fills) == 1:
            return self.fills[0].to_dict()
        return jsonable({"fills": list(self.fills), "hits_total": self.fills[-1].hits_total if self.fills else 0})


@dataclass(frozen=True)
class FillPlan(Result):
    """Size and estimated time of a fill, measured on a sample of its grid before it starts.

    ``flights_per_s`` is timed on up to :data:`PLAN_SAMPLE` settings spread over the grid (the
    flights and their branch flights, this process); ``kept_fraction`` is the share of the sample
    that lands in the kept area; the estimate adds :data:`INSERT_RATE` hits/s for the single SQLite
    writer (measured: docs/database.md).  Already finished chunks are not counted.
    """

    grid_rows: int
    rows_to_fly: int
    n_chunks: int
    chunks_done: int
    flights_per_s: float
    kept_fraction: float
    estimated_hits: int
    estimated_s: float
    shape: dict


#: Settings flown to time a fill before it starts (:class:`FillPlan`).
PLAN_SAMPLE = 1500
#: Hits per second through the single SQLite writer, inserts and indexes (docs/database.md: 1-3 x 10^4).
INSERT_RATE = 1.5e4


def plan_fill(spec, params, grid: TableGrid, chunk_size: int = DEFAULT_CHUNK, done: int = 0) -> FillPlan:
    """Time a sample of the grid and estimate the fill (:class:`FillPlan`); flies nothing into any file."""
    n_chunks = -(-grid.size // int(chunk_size))
    rows_left = max(0, grid.size - done * int(chunk_size))
    m = int(min(PLAN_SAMPLE, grid.size))
    rng = np.random.default_rng(0)
    flat = np.unique(rng.integers(0, grid.size, m)) if grid.size > m else np.arange(grid.size)
    idx = _grid_rows(grid, flat)
    fly_chunk(idx, spec, params)  # compile / warm up
    t0 = time.perf_counter()
    rows = fly_chunk(idx, spec, params)
    dt = max(time.perf_counter() - t0, 1e-6)
    kept = len(select_hits(rows, spec, params.court)["id"]) / max(1, len(flat))
    rate = len(flat) / dt
    est_hits = int(rows_left * kept)
    return FillPlan(
        grid.size,
        rows_left,
        n_chunks,
        done,
        rate,
        kept,
        est_hits,
        rows_left / rate + est_hits / INSERT_RATE,
        dict(zip(AXES, grid.shape)),
    )


def _grid_rows(grid: TableGrid, flat: np.ndarray) -> dict:
    """Index arrays of the rows at flat positions of a grid (first axis slowest)."""
    rem = np.asarray(flat, dtype=np.int64).copy()
    out = {}
    for f in reversed(AXES):
        a = np.asarray(grid.indices[f])
        out[f] = a[rem % a.size]
        rem //= a.size
    return {f: out[f] for f in AXES}


@dataclass
class _Tally:
    """What a fill has done so far (chunks run, hits inserted, its fill id once registered)."""

    run: int = 0
    inserted: int = 0
    fid: int | None = None


def check_out_dir(path: str) -> None:
    """Refuse an output folder that is a file or lies under one (before anything is created)."""
    p = os.path.abspath(path)
    if os.path.exists(p) and not os.path.isdir(p):
        raise InputError(f"out_dir: {path} is a file, not a folder")
    d = os.path.dirname(p)
    while d and not os.path.exists(d):
        d = os.path.dirname(d)
    if d and not os.path.isdir(d):
        raise InputError(f"out_dir: {path} lies under {d}, which is a file")


def _remove_new_file(path: str) -> None:
    """Remove a database file this run created (and its -wal/-shm) after a failed start."""
    for p in (path, path + "-wal", path + "-shm"):
        try:
            os.unlink(p)
        except FileNotFoundError:
            pass


def fill_table(
    path: str,
    spec,
    params,
    grid: TableGrid,
    *,
    chunk_size: int = DEFAULT_CHUNK,
    scheduler="local",
    n_workers: int | None = None,
    runner=None,
    progress="auto",
    out_dir: str | None = None,
    keep_margin: float = KEEP_MARGIN_M,
    max_chunks: int | None = None,
    on_chunk=None,
) -> FillReport:
    """Fill (or resume filling) the database at ``path`` with ``grid`` for ``spec`` and ``params``.

    Refuses a file built for another machine or physics (hash).  The chunks are flown by
    :func:`tennislab.batch.run_batch` (:func:`fly_chunk` on the lazy :meth:`TableGrid.grid_spec`)
    on ``scheduler`` (``"local"``, ``"processes"`` with ``n_workers``, ``"tcp://HOST:PORT"`` or a
    ``distributed.Client``); its ``on_chunk`` hook inserts each chunk's hits, in this process, in
    one transaction together with the chunk's "done" mark (chunks come back in any order), so an
    interrupted fill resumes where it stopped: the chunks marked done are passed as ``skip``.
    ``runner`` is a :mod:`tennislab.batch.schedulers` runner whose Dask client is used (not
    closed).  ``out_dir`` also writes every row of every chunk (kept or not) as resumable Parquet
    parts of the batch layer (:func:`tennislab.batch.read_output`); a chunk missing there is flown
    again, one on disk but not in the database is read back instead of flown.  ``max_chunks``
    stops after that many chunks; ``on_chunk(i, n_hits)`` is called after each stored chunk.  A
    file this call creates is removed again when the run fails before its first chunk is stored
    (a bad ``out_dir``, an unreachable scheduler): nothing is left behind.
    """
    chunk_size = int(chunk_size)
    if chunk_size < 1:
        raise InputError(f"chunk_size: must be >= 1, got {chunk_size}")
    if max_chunks is not None and int(max_chunks) < 1:
        raise InputError(f"max_chunks: {max_chunks} is outside the allowed range [1, inf]")
    check_finite("keep_margin", keep_margin)
    if out_dir is not None:
        check_out_dir(out_dir)
    if runner is not None:
        scheduler = getattr(runner, "client", None) or "local"
    t0 = time.perf_counter()
    created = not os.path.exists(path)
    conn = None
    tally = _Tally()
    try:
        conn = _db.open_db(path)
        cfg = _db.config_dict(spec, params)
        h = _db.bind_config(conn, cfg)
        grid_json = grid.to_json()
        # a new grid is registered with its first stored chunk: a run that fails before (e.g. no
        # scheduler, another job in out_dir) leaves no trace in the file
        fid, done = begin_fill(conn, grid_json, grid.size, chunk_size, register=False)
        tally.fid = fid
        n_chunks = -(-grid.size // chunk_size)
        axes = axis_values(spec.range_of("spin_axis_deg"), grid.indices["spin_axis_deg"])
        axis0 = float(axes[np.argmin(np.abs(axes))])  # the one rotation stored for zero spin

        c = conn

        def insert(ci: int, row0: int, rows: dict) -> None:  # called by run_batch in this process
            hits = select_hits(rows, spec, params.court, keep_margin, axis0, params)
            fid = tally.fid if tally.fid is not None else begin_fill(c, grid_json, grid.size, chunk_size)[0]
            assert fid is not None  # registered now
            tally.fid = fid
            tally.inserted += store_chunk(c, fid, ci, hits)
            tally.run += 1
            if on_chunk is not None:
                on_chunk(ci, len(hits["id"]))

        res = run_batch(
            functools.partial(fly_chunk, spec=spec, params=params),
            grid.grid_spec(),
            scheduler=scheduler,
            n_workers=n_workers,
            chunk_size=chunk_size,
            out=out_dir,
            progress=progress,
            desc=f"launcher table -> {os.path.basename(path)}",
            unit="flights",
            collect=False,
            tag={"launcher_table": h},
            on_chunk=insert,
            skip=done,
            max_chunks=max_chunks,
        )
        if tally.fid is not None:
            finish_fill(conn, int(tally.fid))
        total = _db.count_hits(conn)
    except BaseException:
        if conn is not None:
            conn.close()
            conn = None
        if created and tally.run == 0:
            _remove_new_file(path)
        raise
    finally:
        if conn is not None:
            conn.close()
    return FillReport(
        path,
        h,
        grid.size,
        n_chunks,
        res.skipped - res.restored,
        tally.run,
        tally.inserted,
        total,
        time.perf_counter() - t0,
        res.restored,
    )
