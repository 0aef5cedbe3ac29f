"""Benchmark: ``launcher lookup`` on a hits table of 10^7 rows (target: < 10 ms per lookup, every form).

Builds (once; reused if the file is there, migrated if its schema is older) an
SQLite table of ~10^7 hits laid out exactly like a real fill (ids, grid order,
R*Tree over landing x, y, speed and spin, band indexes, trajectory branch), then
times every form of lookup (speed and spin, speed only, spin only, neither,
height only; each with the default trajectory ``low``, and speed and spin with
``high``, ``any``, a maximum apex, a net-clearance band and a longest flight) on
the path of ``launcher lookup`` (:meth:`tennislab.launcher.HitsDB.lookup`) against
a full-scan baseline measured in the same run on the same file, checks the
answers against the scan (the same query and tie rule), and prints median /
95th percentile [ms].

Rows are synthetic by default: the landing point of each setting comes from a
closed-form flight (projectile with a linear-drag range factor and a Magnus
term scaling gravity), which gives the same smooth landing "sheets" per speed
and spin as real flights, so the R*Tree holds the same structure -- lookup
timing depends on that layout, not on the physics.  ``--real`` fills the table
with ``fly_batch`` flights instead (slower: ~10^8 flights for 10^7 kept hits).

Usage:  python benchmarks/bench_db.py [--rows 1e7] [--db PATH] [--lookups 500] [--scans 5]
"""

from __future__ import annotations

import argparse
import math
import os
import sqlite3
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "src"))

from tennislab.errors import InputError  # noqa: E402
from tennislab.launcher import HitsDB, db  # noqa: E402
from tennislab.launcher import lookup as lk  # noqa: E402
from tennislab.launcher import table as T  # noqa: E402
from tennislab.launcher.aim import launcher_params  # noqa: E402
from tennislab.launcher.machine import DEFAULT_SPEC  # noqa: E402
from tennislab.launcher.preferences import Preferences  # noqa: E402
from tennislab.units import DEG, KMH  # noqa: E402


def _closed_form_range(v, a, h, g):
    vz, vh = v * np.sin(a), v * np.cos(a)
    t = (vz + np.sqrt(vz * vz + 2 * g * h)) / g
    drag = 1.0 / (1.0 + 0.012 * v * np.sqrt(t))  # shortens fast, long flights
    return vh * t * drag


def _synthetic_rows(indices: dict, spec, params) -> dict:
    """Closed-form stand-in for :func:`tennislab.launcher.table.fly_chunk` (same columns, same ids)."""
    sizes = T.machine_sizes(spec)
    vals = {f: T.axis_values(spec.range_of(f), indices[f]) for f in T.AXES}
    v = vals["speed_kmh"] * KMH
    a = vals["elevation_deg"] * DEG
    b = vals["heading_deg"] * DEG
    h = vals["height_m"]
    # Magnus: topspin (axis 0) pulls down, backspin (axis 180) holds up: g_eff = g (1 + m cos(axis))
    g = 9.81 * (1.0 + 0.35 * vals["spin_rpm"] / 2000.0 * np.cos(vals["spin_axis_deg"] * DEG))
    vz, vh = v * np.sin(a), v * np.cos(a)
    t = (vz + np.sqrt(vz * vz + 2 * g * h)) / g
    drag = 1.0 / (1.0 + 0.012 * v * np.sqrt(t))  # shortens fast, long flights
    r = vh * t * drag
    px, py = spec.position
    x, y = px + r * np.cos(b), py + r * np.sin(b)
    tn = np.where(np.cos(b) > 0, -px / np.maximum(vh * np.cos(b) * drag, 1e-9), np.inf)
    zn = h + vz * tn - 0.5 * g * tn * tn
    n = len(x)
    out = {
        "id": T.pack_ids({f: indices[f] for f in T.AXES}, sizes),
        **vals,
        "land_x": x,
        "land_y": y,
        "net_clearance_m": zn - 0.914 - params.ball.radius,
        "flight_time_s": t,
        "bounce_speed_ms": v * 0.7,
        "bounce_spin_rpm": vals["spin_rpm"] * 0.98,
        "apex_z_m": h + np.where(vz > 0, vz * vz / (2 * g), 0.0),
        "status": np.zeros(n, np.int8),
        "net_status": np.where(zn - 0.914 - 0.0335 > 0, 1, 2).astype(np.int8),
        # the branch as a fill stores it: does the same shot 0.01 deg higher land farther (low) or nearer (high)?
        "branch": np.where(_closed_form_range(v, a + 0.01 * DEG, h, g) >= r, 0, 1).astype(np.int8),
    }
    return out


#: Grid presets per table size: (spin step [rpm], spin-axis rotations [deg] (min, max, stride in 1-deg
#: steps), heights [m] (min, max, stride in 0.1-m steps)); every speed, elevation and heading step.
PRESETS = {
    1e5: (2000, (0, 180, 180), (1.0, 1.0, 1)),
    1e6: (500, (0, 180, 180), (1.0, 1.0, 1)),
    1e7: (100, (-90, 180, 90), (1.0, 2.0, 10)),
}


def bench_grid(spec, rows: float):
    """The preset grid nearest ``rows`` kept hits (about 5 % of the settings land in the far court)."""
    key = min(PRESETS, key=lambda k: abs(math.log10(rows / k)))
    spin_step, (a0, a1, ak), (h0, h1, hk) = PRESETS[key]
    return T.make_grid(
        spec,
        {"height_m": (h0, h1), "spin_axis_deg": (a0, a1)},
        {"spin_rpm": spin_step, "spin_axis_deg": ak, "height_m": hk},
    )


def build(path: str, rows: float, real: bool, chunk: int = 50_000) -> None:
    spec, params = DEFAULT_SPEC, launcher_params()
    grid = bench_grid(spec, rows)
    print(f"building {path}: grid {grid.size:,} settings, {'fly_batch' if real else 'synthetic'} rows ...", flush=True)
    t0 = time.perf_counter()
    if real:
        T.fill_table(path, spec, params, grid, chunk_size=chunk, progress="always")
    else:
        conn = db.open_db(path)
        db.bind_config(conn, db.config_dict(spec, params))
        fid, done = T.begin_fill(conn, grid.to_json(), grid.size, chunk)
        n_chunks = -(-grid.size // chunk)
        for i in range(n_chunks):
            if i in done:
                continue
            rows_i = _synthetic_rows(grid.chunk(i, chunk), spec, params)
            T.store_chunk(conn, fid, i, T.select_hits(rows_i, spec, params.court))
            if i % 50 == 0:
                print(
                    f"  chunk {i}/{n_chunks}: {db.count_hits(conn):,} hits, {time.perf_counter() - t0:.0f} s",
                    flush=True,
                )
        T.finish_fill(conn, fid)
        conn.execute("PRAGMA wal_checkpoint(TRUNCATE)")
        conn.close()
    print(f"built in {time.perf_counter() - t0:.0f} s; {os.path.getsize(path) / 1e9:.2f} GB", flush=True)


def _stats(ms):
    a = np.asarray(ms)
    return float(np.median(a)), float(np.percentile(a, 95))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--rows",
        type=float,
        default=float(os.environ.get("TENNISLAB_BENCH_DB_ROWS", 1e7)),
        help="approximate number of hits (default 1e7, or $TENNISLAB_BENCH_DB_ROWS)",
    )
    ap.add_argument("--db", default=None, help="database file (default out/bench_db_<rows>.sqlite; reused)")
    ap.add_argument("--lookups", type=int, default=500)
    ap.add_argument("--scans", type=int, default=5, help="full-scan baseline queries (slow)")
    ap.add_argument("--real", action="store_true", help="fill with fly_batch flights instead of synthetic rows")
    if argv is None:  # run_all.py calls main() with its own command line in sys.argv
        argv = sys.argv[1:] if __name__ == "__main__" else []
    args = ap.parse_args(argv)
    path = args.db or os.path.join(HERE, "..", "out", f"bench_db_{args.rows:.0e}{'_real' if args.real else ''}.sqlite")
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    if not os.path.exists(path):
        build(path, args.rows, args.real)
    c = sqlite3.connect(path)
    version = c.execute("PRAGMA user_version").fetchone()[0]
    c.close()
    if version < db.SCHEMA_VERSION:
        t0 = time.perf_counter()
        db.open_db(path, create=False).close()
        print(f"migrated {path} from schema {version} to {db.SCHEMA_VERSION} in {time.perf_counter() - t0:.0f} s")
    conn = db.open_readonly(path)
    n = db.count_hits(conn)
    rng = lk.table_ranges(conn)
    speeds = np.arange(rng["speed_kmh"][0], rng["speed_kmh"][1] + 1)
    sample = conn.execute(
        "SELECT DISTINCT spin_rpm, height_m FROM hits WHERE id IN (SELECT id FROM hits ORDER BY random() LIMIT 2000)"
    ).fetchall()
    spins = np.array(sorted({r[0] for r in sample}))
    height = max(r[1] for r in sample)
    print(
        f"table: {n:,} hits, {os.path.getsize(path) / 1e9:.2f} GB, speeds {speeds[0]:g}-{speeds[-1]:g} km/h, "
        f"{len(spins)} spin values"
    )
    r = np.random.default_rng(0)

    def targets(k):
        return r.uniform(1.0, 11.5, k), r.uniform(-5.0, 5.0, k), r.choice(speeds, k), r.choice(spins, k)

    conn.execute("SELECT count(*) FROM hits_rtree").fetchone()  # warm the page cache (both methods read the file)
    exact = {"speed_tolerance_kmh": 0, "spin_tolerance_rpm": 0}
    forms = {
        "speed+spin": lambda s, w: {"speed_kmh": s, "spin_rpm": w, **exact},
        "speed only": lambda s, w: {"speed_kmh": s, **exact},
        "spin only": lambda s, w: {"spin_rpm": w, **exact},
        "any speed/spin": lambda s, w: {},
        f"height {height:g} m": lambda s, w: {"height_m": height},
        "speed+spin, high": lambda s, w: {"speed_kmh": s, "spin_rpm": w, "trajectory": "high", **exact},
        "speed+spin, any": lambda s, w: {"speed_kmh": s, "spin_rpm": w, "trajectory": "any", **exact},
        "speed+spin +-3/100": lambda s, w: {"speed_kmh": s, "spin_rpm": w},
        "speed+spin+axis (vector)": lambda s, w: {"speed_kmh": s, "spin_rpm": w, "spin_axis_deg": 0.0},
        "speed, apex<=3 m": lambda s, w: {"speed_kmh": s, "max_apex_m": 3.0, **exact},
        "spin, net 0.3-1.5 m": lambda s, w: {"spin_rpm": w, "net_clearance_m": (0.3, 1.5), **exact},
        "any, flight<=1.2 s": lambda s, w: {"max_flight_time_s": 1.2},
    }
    results = {}
    with HitsDB(path) as hdb:
        hdb.lookup((8.0, 0.0), trajectory="any", fallback=False)  # statistics and the machine row, read once
        for label, kw in forms.items():
            xs, ys, ss, ws = targets(args.lookups)
            ms, reads, misses = [], [], 0
            for x, y, s, w in zip(xs, ys, ss, ws):
                t = time.perf_counter()
                try:  # the path of `launcher lookup --no-fallback` (max miss 1 m), errors included
                    res = hdb.lookup((x, y), fallback=False, **kw(float(s), float(w)))
                    reads.append(res.index_entries_read)
                except InputError:
                    misses += 1
                ms.append((time.perf_counter() - t) * 1e3)
            results[label] = _stats(ms)
            print(
                f"lookup ({label:24s}): median {results[label][0]:7.3f} ms, p95 {results[label][1]:7.3f} ms, "
                f"index entries read median {int(np.median(reads)) if reads else 0}, no hit within 1 m: {misses}  "
                f"[{args.lookups} lookups]",
                flush=True,
            )
    scan_ms = []
    checked = 0
    for label in ("speed+spin", "speed only", "spin only", "any speed/spin", "speed+spin, high", "speed, apex<=3 m"):
        xs, ys, ss, ws = targets(args.scans)
        for x, y, s, w in zip(xs, ys, ss, ws):
            kw = forms[label](float(s), float(w))
            p = Preferences(
                kw.get("trajectory", "low"),
                kw.get("max_apex_m"),
                kw.get("net_clearance_m"),
                kw.get("max_flight_time_s"),
            )
            sp, sw = kw.get("speed_kmh"), kw.get("spin_rpm")
            q = lk.HitQuery(
                sp,
                sw,
                None if sp is None else (sp - 0.4, sp + 0.4),
                None if sw is None else (sw - 0.4, sw + 0.4),
                {},
                p,
            )
            t = time.perf_counter()
            b = lk.scan_nearest(conn, x, y, query=q)
            scan_ms.append((time.perf_counter() - t) * 1e3)
            a = lk.nearest_hit(conn, x, y, query=q, max_m=64.0)
            assert (a is None and b is None) or (a["id"], a["miss_m"]) == (b["id"], b["miss_m"]), (
                f"lookup and scan disagree ({label}, target {x}, {y})"
            )
            checked += 1
    scan = _stats(scan_ms)
    print(f"full-scan baseline: median {scan[0]:9.1f} ms, p95 {scan[1]:9.1f} ms  [{len(scan_ms)} scans]")
    print(f"lookups agree with the full scan: {checked} targets over 6 forms")
    med = results["speed+spin"][0]
    worst = max(results, key=lambda k: results[k][1])
    print(
        f"speedup (median, speed+spin): {scan[0] / med:,.0f}x; target < 10 ms: "
        f"{'PASS' if results[worst][1] < 10 else 'FAIL'} (largest p95: {worst}, {results[worst][1]:.2f} ms)"
    )
    conn.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
