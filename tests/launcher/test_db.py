"""The launcher's SQLite database: schema, migrations, hash, fill, R*Tree lookup, drills."""

from __future__ import annotations

import json
import os
import sqlite3
import subprocess
import sys
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import tennislab.launcher._dbdrills as dd
from tennislab.errors import InputError
from tennislab.launcher import HitsDB, db
from tennislab.launcher import lookup as lk
from tennislab.launcher import table as T
from tennislab.launcher.aim import aim_all, launcher_params
from tennislab.launcher.drill_schema import drill_record, parse_drill
from tennislab.launcher.machine import DEFAULT_SPEC
from tennislab.launcher.preferences import EXACT, Preferences


def _import(conn, path):
    """Store a drill file as ``launcher drills import`` does."""
    data = open(path, "rb").read()
    return dd.import_drill(conn, drill_record(parse_drill(data, str(path))), data, str(path))


SPEEDS = (80.0, 120.0)
EXACT_KW = {"speed_tolerance_kmh": 0, "spin_tolerance_rpm": 0}
SPINS = (0.0, 1500.0)
RANGES = {"height_m": (1.0, 1.0), "speed_kmh": SPEEDS, "spin_rpm": SPINS, "spin_axis_deg": (0.0, 0.0)}
STRIDES = {"speed_kmh": 10, "spin_rpm": 1500}


@pytest.fixture(scope="module")
def params():
    return launcher_params()


@pytest.fixture(scope="module")
def grid():
    return T.make_grid(DEFAULT_SPEC, RANGES, STRIDES)


@pytest.fixture(scope="module")
def table_db(tmp_path_factory, params, grid):
    """A small real table: height 1 m, 80-120 km/h by 10, spin 0 and 1500 rpm topspin, every angle."""
    path = str(tmp_path_factory.mktemp("db") / "hits.sqlite")
    rep = T.fill_table(path, DEFAULT_SPEC, params, grid, chunk_size=8181)
    assert rep.hits_total > 5_000
    return path


# ------------------------------------------------------------------ schema
def test_new_file_has_schema_wal_and_rtree(tmp_path):
    path = str(tmp_path / "a.sqlite")
    conn = db.open_db(path)
    assert conn.execute("PRAGMA user_version").fetchone()[0] == db.SCHEMA_VERSION
    assert conn.execute("PRAGMA application_id").fetchone()[0] == db.APPLICATION_ID
    assert conn.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    names = {r[0] for r in conn.execute("SELECT name FROM sqlite_master")}
    assert {
        "machine",
        "hits",
        "hits_rtree",
        "hits_cell",
        "hits_speed_cell",
        "hits_spin_cell",
        "fills",
        "fill_chunks",
        "drills",
        "drill_shots",
    } <= names
    assert "hits_xy" not in names  # schema 3's 2-D R*Tree, replaced by hits_cell in schema 4
    sql = conn.execute("SELECT sql FROM sqlite_master WHERE name = 'hits_rtree'").fetchone()[0]
    assert "rtree" in sql.lower()
    conn.close()


def test_migration_from_version_1_and_newer_refused(tmp_path, params):
    path = str(tmp_path / "old.sqlite")
    conn = db.open_db(path, target_version=1)
    cfg = db.config_dict(DEFAULT_SPEC, params)
    db.bind_config(conn, cfg)
    names = {r[0] for r in conn.execute("SELECT name FROM sqlite_master")}
    assert "drills" not in names and "hits" in names and "hits_xy" not in names
    conn.executemany("INSERT INTO hits VALUES (?,1,100,10,0,0,0,?,?,0.5,1,20,0,2)", [(7, 8.0, 1.0), (9, 9.0, -2.0)])
    conn.executemany("INSERT INTO hits_rtree VALUES (?,?,?,?,?,100,100,0,0)", [(7, 8, 8, 1, 1), (9, 9, 9, -2, -2)])
    conn.close()
    with pytest.raises(InputError, match="older"):
        db.open_readonly(path)  # a reader never migrates
    conn = db.open_db(path)  # a writer does
    assert conn.execute("PRAGMA user_version").fetchone()[0] == db.SCHEMA_VERSION
    assert "drills" in {r[0] for r in conn.execute("SELECT name FROM sqlite_master")}
    # v3 indexed the hits already stored, v4 replaced that index by the band indexes
    assert "hits_xy" not in {r[0] for r in conn.execute("SELECT name FROM sqlite_master")}
    assert conn.execute("SELECT id FROM hits INDEXED BY hits_cell WHERE land_x > 8.5").fetchall() == [(9,)]
    for kw in ({}, {"speed_kmh": 100.0}, {"spin_rpm": 0.0}):  # the band indexes, built by the migration
        assert lk.nearest_hit(conn, 8.1, 1.0, **kw)["id"] == 7
    assert db.check_config(conn, cfg) == db.config_hash(cfg)  # a migration keeps the table valid
    assert db.has_column(conn, "hits", "branch")
    conn.execute("PRAGMA user_version = 99")
    conn.close()
    with pytest.raises(InputError, match="newer"):
        db.open_db(path)


def test_foreign_and_truncated_files_refused(tmp_path, table_db):
    other = tmp_path / "other.sqlite"
    c = sqlite3.connect(other)
    c.execute("CREATE TABLE t (x)")
    c.commit()
    c.close()
    for opener in (db.open_db, db.open_readonly):
        with pytest.raises(InputError, match="another application|not a tennislab"):
            opener(str(other))
    text = tmp_path / "notes.sqlite"
    text.write_text("hello, not a database\n" * 100)
    with pytest.raises(InputError, match="not a usable"):
        db.open_readonly(str(text))
    trunc = tmp_path / "trunc.sqlite"
    # checkpoint the WAL of the fixture file into a copy, then cut it
    src = sqlite3.connect(table_db)
    dst = sqlite3.connect(trunc)
    src.backup(dst)
    src.close()
    dst.close()
    data = trunc.read_bytes()
    trunc.write_bytes(data[: len(data) * 9 // 10])
    for opener in (db.open_db, db.open_readonly):
        with pytest.raises(InputError, match="truncated"):
            opener(str(trunc))
    trunc.write_bytes(data[: len(data) // 3])
    with pytest.raises(InputError):
        conn = db.open_readonly(str(trunc))
        lk.nearest_hit(conn, 6.0, 0.0)
        conn.execute("SELECT count(*), sum(land_x) FROM hits").fetchone()


# -------------------------------------------------------------------- hash
def test_hash_is_stable_and_sees_every_constant(params):
    from tennislab.launcher.aim import launcher_params as lp

    base = db.config_hash(db.config_dict(DEFAULT_SPEC, params))
    assert base == db.config_hash(db.config_dict(DEFAULT_SPEC, lp()))
    assert len(base) == 64
    others = [
        db.config_dict(DEFAULT_SPEC.with_position(-12.0, 0.0), params),
        db.config_dict(DEFAULT_SPEC, lp(mass=0.058)),
        db.config_dict(DEFAULT_SPEC, lp(cd=params.aero.params[0] + 0.05)),
        db.config_dict(DEFAULT_SPEC, lp(aero="stepanek1988")),
        db.config_dict(DEFAULT_SPEC, lp(air_density=1.22)),
        db.config_dict(DEFAULT_SPEC, lp(spin_decay=0.02)),
        db.config_dict(DEFAULT_SPEC, lp(wind=(1.0, 0.0, 0.0))),
    ]
    hashes = {db.config_hash(c) for c in others}
    assert base not in hashes and len(hashes) == len(others)


def test_a_files_physics_is_rebuilt_with_its_court():
    """The lookup's fallback aims with the physics the file was filled with, its court included (the
    table kept the hits landing in that court; the rebuilt physics had taken the ITF court)."""
    import dataclasses

    from tennislab.core import Court

    for p in (launcher_params(), dataclasses.replace(launcher_params(), court=Court(net_center_height=1.2))):
        assert lk.params_from_physics(db._stored_physics(p)) == p


def test_canonical_json_ignores_key_order():
    a = {"b": 1.0, "a": [1, 2, {"y": 0.1, "x": np.float64(0.2)}]}
    b = {"a": [1, 2, {"x": 0.2, "y": 0.1}], "b": 1.0}
    assert db.canonical_json(a) == db.canonical_json(b)


def test_fill_for_another_machine_or_physics_refused(table_db, params, grid):
    with pytest.raises(InputError, match=r"another machine/physics.*position"):
        T.fill_table(table_db, DEFAULT_SPEC.with_position(-12.0, 1.0), params, grid)
    with pytest.raises(InputError, match=r"physics\.aero\.name"):
        T.fill_table(table_db, DEFAULT_SPEC, launcher_params(aero="stepanek1988"), grid)
    conn = db.open_readonly(table_db)
    with pytest.raises(InputError, match=r"physics\.ball\.mass"):
        db.check_config(conn, db.config_dict(DEFAULT_SPEC, launcher_params(mass=0.058)))
    conn.close()


# -------------------------------------------------------------------- grid
@given(st.lists(st.integers(0, 10**6), min_size=6, max_size=6))
@settings(max_examples=50, deadline=None)
def test_pack_unpack_ids_round_trip(raw):
    sizes = T.machine_sizes(DEFAULT_SPEC)
    idx = {f: np.array([r % sizes[f]]) for f, r in zip(T.AXES, raw)}
    ids = T.pack_ids(idx, sizes)
    back = T.unpack_ids(ids, sizes)
    assert all(back[f][0] == idx[f][0] for f in T.AXES)
    assert 0 <= ids[0] < np.prod([sizes[f] for f in T.AXES], dtype=float)


def test_grid_ranges_and_strides():
    g = T.make_grid(DEFAULT_SPEC, {"speed_kmh": (100, 125), "elevation_deg": (-20, 80)}, {"speed_kmh": 10})
    speeds = T.axis_values(DEFAULT_SPEC.speed, g.indices["speed_kmh"])
    assert speeds.tolist() == [100.0, 110.0, 120.0, 125.0]  # the last step of the range is always in
    assert len(g.indices["elevation_deg"]) == 101 and len(g.indices["height_m"]) == 30
    with pytest.raises(InputError, match="speed_kmh min"):
        T.make_grid(DEFAULT_SPEC, {"speed_kmh": (10, 50)})
    full = T.make_grid(DEFAULT_SPEC)
    assert full.size == 30 * 171 * 2001 * 361 * 101 * 81


def test_spin_zero_stored_once(params, tmp_path):
    g = T.make_grid(
        DEFAULT_SPEC,
        {
            "height_m": (1, 1),
            "speed_kmh": (100, 100),
            "spin_rpm": (0, 0),
            "spin_axis_deg": (-10, 10),
            "elevation_deg": (10, 10),
            "heading_deg": (0, 0),
        },
    )
    hits = T.fill_chunk(g.chunk(0, 1000), DEFAULT_SPEC, params)
    assert len(hits["id"]) == 1 and hits["spin_axis_deg"][0] == 0.0
    # a grid without the 0 deg rotation still stores its zero-spin flight once
    g = T.make_grid(
        DEFAULT_SPEC,
        {
            "height_m": (1, 1),
            "speed_kmh": (100, 100),
            "spin_rpm": (0, 0),
            "spin_axis_deg": (85, 95),
            "elevation_deg": (10, 10),
            "heading_deg": (0, 0),
        },
    )
    rep = T.fill_table(str(tmp_path / "z.sqlite"), DEFAULT_SPEC, params, g)
    assert rep.grid_rows == 11 and rep.hits_total == 1


# ------------------------------------------------------------------ lookup
def test_lookup_equals_full_scan(table_db):
    conn = db.open_readonly(table_db)
    rng = np.random.default_rng(1)
    n_rows = db.count_hits(conn)
    for _ in range(40):
        x, y = rng.uniform(0.5, 11.5), rng.uniform(-5.0, 5.0)
        sp = [None, *np.arange(80.0, 121.0, 10.0)][rng.integers(6)]
        sw = [None, *SPINS][rng.integers(3)]
        a = lk.nearest_hit(conn, x, y, speed_kmh=sp, spin_rpm=sw)
        b = lk.scan_nearest(conn, x, y, speed_kmh=sp, spin_rpm=sw)
        assert a["id"] == b["id"], (x, y, sp, sw)
        assert a["miss_m"] == pytest.approx(b["miss_m"], abs=1e-12)
        assert a["n_candidates"] < n_rows / 20  # an index query, not a scan
    conn.close()


def test_ties_go_to_larger_net_clearance(tmp_path, params):
    path = str(tmp_path / "tie.sqlite")
    conn = db.open_db(path)
    db.bind_config(conn, db.config_dict(DEFAULT_SPEC, params))
    base = {
        "height_m": 1.0,
        "speed_kmh": 100.0,
        "heading_deg": 0.0,
        "spin_rpm": 0.0,
        "spin_axis_deg": 0.0,
        "flight_time_s": 1.0,
        "bounce_speed_ms": 10.0,
        "bounce_spin_rpm": 0.0,
        "apex_z_m": 2.0,
    }
    rows = {k: np.full(3, v) for k, v in base.items()}
    rows.update(
        {
            "id": np.array([1, 2, 3]),
            "elevation_deg": np.array([5.0, 40.0, 6.0]),
            "land_x": np.array([8.0, 8.0005, 9.0]),
            "land_y": np.array([0.0, 0.0, 0.0]),
            "net_clearance_m": np.array([0.3, 5.0, 0.4]),
        }
    )
    conn.execute("BEGIN")
    db.insert_hits(conn, rows)
    conn.execute("COMMIT")
    hit = lk.nearest_hit(conn, 8.0, 0.0)
    assert hit["id"] == 2  # 0.5 mm farther but 5 m over the net: a tie within 1 mm
    hit = lk.nearest_hit(conn, 8.0, 0.0, tie_m=1e-4)
    assert hit["id"] == 1
    conn.close()


def test_lookup_agrees_with_aim_on_random_targets(table_db, params):
    """The table's answer is the best grid point: never farther than ``launcher aim``'s quantised answer."""
    hdb = HitsDB(table_db)
    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(10):
        x, y = rng.uniform(3.0, 11.5), rng.uniform(-4.0, 4.0)
        sp = float(rng.choice([80.0, 100.0, 120.0]))
        sw = float(rng.choice(SPINS))
        sols, _ = aim_all((x, y), sp, sw, 0.0, 1.0, DEFAULT_SPEC, params, tolerances=EXACT)
        if not sols:
            continue
        hit = hdb.lookup((x, y), sp, sw, trajectory="any", max_miss_m=5.0, **EXACT_KW).hit
        best = min(sols.values(), key=lambda s: s.miss_mm)
        # aim's quantised settings are a grid point of the table: lookup can only be as near or nearer
        assert hit["miss_m"] * 1e3 <= best.miss_mm + 0.05
        assert hit["miss_m"] * 1e3 <= best.quantisation_bound_mm + 0.05
        same = [
            s
            for s in sols.values()
            if abs(s.settings.elevation_deg - hit["elevation_deg"]) < 1e-9
            and abs(s.settings.heading_deg - hit["heading_deg"]) < 1e-9
        ]
        if abs(hit["miss_m"] * 1e3 - best.miss_mm) > 1.0:  # not a near-tie: the same settings
            assert same, (x, y, sp, sw, hit, sols)
        if same:
            assert hit["land_x"] == pytest.approx(same[0].landing[0], abs=1e-5)
            assert hit["land_y"] == pytest.approx(same[0].landing[1], abs=1e-5)
        checked += 1
    assert checked >= 6


def test_lookup_errors(table_db):
    """The table's own answers and refusals (the fallback to the machine's aim off: tests/launcher/test_reach.py)."""
    hdb = HitsDB(table_db)
    with pytest.raises(InputError, match="^speed_kmh: no hit with speed 150"):
        hdb.lookup((6.0, 0.0), 150.0, 0.0, fallback=False)
    with pytest.raises(InputError, match="^target: no hit in range"):
        hdb.lookup((0.3, 0.0), 120.0, 0.0, max_miss_m=0.01, trajectory="any", fallback=False)
    a = hdb.lookup((8.0, 1.0), 100.0, 0.0, fallback=False)
    b = hdb.lookup((8.0, 1.0), 100.0, 0.0, height_m=1.0, fallback=False)
    assert a.hit["id"] == b.hit["id"]
    with pytest.raises(InputError, match="height_m 2"):
        hdb.lookup((8.0, 1.0), 100.0, height_m=2.0, fallback=False)
    with pytest.raises(InputError, match="^max_miss_m: "):
        hdb.lookup((8.0, 1.0), 100.0, max_miss_m=0, fallback=False)
    with pytest.raises(InputError, match="^target: \\(13, 0\\) m is off the court"):
        hdb.lookup((13.0, 0.0), 100.0, fallback=False)
    with pytest.raises(InputError, match="off the court"):
        lk.check_target(13.0, 0.0)
    with pytest.raises(InputError, match="off the court"):
        lk.check_target(-5.0, 0.0)
    assert lk.check_target(-5.0, 0.0, machine_x=12.0) == (-5.0, 0.0)


# -------------------------------------------------------------- fill/resume
def test_resume_gives_the_same_table(tmp_path, params):
    g = T.make_grid(
        DEFAULT_SPEC,
        {"height_m": (1, 1), "speed_kmh": (100, 100), "spin_rpm": (0, 0), "spin_axis_deg": (0, 0)},
        {"elevation_deg": 2},
    )
    a, b = str(tmp_path / "a.sqlite"), str(tmp_path / "b.sqlite")
    r1 = T.fill_table(a, DEFAULT_SPEC, params, g, chunk_size=500, max_chunks=3)
    assert r1.chunks_run == 3 and r1.n_chunks == -(-g.size // 500)
    r2 = T.fill_table(a, DEFAULT_SPEC, params, g, chunk_size=500)
    assert r2.chunks_done_before == 3 and r2.chunks_run == r2.n_chunks - 3
    T.fill_table(b, DEFAULT_SPEC, params, g, chunk_size=500)
    ca, cb = db.open_readonly(a), db.open_readonly(b)
    qa = ca.execute("SELECT * FROM hits ORDER BY id").fetchall()
    qb = cb.execute("SELECT * FROM hits ORDER BY id").fetchall()
    assert qa == qb and len(qa) > 100
    assert ca.execute("SELECT count(*) FROM hits_rtree").fetchone()[0] == len(qa)
    assert ca.execute("SELECT finished_utc IS NOT NULL FROM fills").fetchone()[0] == 1
    with pytest.raises(InputError, match="chunk"):
        T.fill_table(a, DEFAULT_SPEC, params, g, chunk_size=700)
    # an overlapping grid adds only the new settings
    g2 = T.make_grid(
        DEFAULT_SPEC, {"height_m": (1, 1), "speed_kmh": (100, 100), "spin_rpm": (0, 0), "spin_axis_deg": (0, 0)}
    )
    r3 = T.fill_table(a, DEFAULT_SPEC, params, g2, chunk_size=500)
    assert r3.hits_total == r3.hits_inserted + len(qa)
    ca.close()
    cb.close()


def test_parquet_out_dir_beside_the_db(tmp_path, params):
    from tennislab.batch import read_output

    g = T.make_grid(
        DEFAULT_SPEC,
        {"height_m": (1, 1), "speed_kmh": (90, 90), "spin_rpm": (0, 0), "spin_axis_deg": (0, 0)},
        {"heading_deg": 10},
    )
    path, out = str(tmp_path / "h.sqlite"), str(tmp_path / "parts")
    rep = T.fill_table(path, DEFAULT_SPEC, params, g, chunk_size=300, out_dir=out)
    rows = read_output(out)
    assert len(rows["id"]) == g.size
    kept = T.select_hits(rows, DEFAULT_SPEC, params.court)
    assert len(kept["id"]) == rep.hits_total
    assert np.all(rows["elevation_deg"] >= -20) and set(np.unique(rows["net_status"])) <= {0, 1, 2}
    assert rep.chunks_restored == 0
    # a new database beside the same parts: every chunk is read back, none flown, same hits
    again = T.fill_table(str(tmp_path / "h2.sqlite"), DEFAULT_SPEC, params, g, chunk_size=300, out_dir=out)
    assert again.chunks_restored == again.chunks_run == again.n_chunks and again.hits_total == rep.hits_total


def test_lookup_while_table_fills(tmp_path, params, capsys):
    """WAL: `launcher lookup` (read-only) answers while `launcher table` in another process fills the file."""
    from tennislab.cli import main

    path = str(tmp_path / "live.sqlite")
    T.fill_table(
        path,
        DEFAULT_SPEC,
        params,
        T.make_grid(
            DEFAULT_SPEC, {"height_m": (1, 1), "speed_kmh": (100, 100), "spin_rpm": (0, 0), "spin_axis_deg": (0, 0)}
        ),
        chunk_size=4000,
    )
    cmd = [
        sys.executable,
        "-m",
        "tennislab",
        "launcher",
        "table",
        "--db",
        path,
        "--height",
        "1",
        "--speed-kmh",
        "80",
        "120",
        "--step",
        "speed",
        "4",
        "--spin-rpm",
        "0",
        "0",
        "--spin-axis-deg",
        "0",
        "0",
        "--chunk-size",
        "1500",
        "--no-progress",
    ]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    answers, counts = 0, []
    deadline = time.time() + 120
    try:
        while proc.poll() is None and time.time() < deadline:
            conn = db.open_readonly(path)
            conn.execute("BEGIN")  # one snapshot: hits and chunk marks agree
            n = db.count_hits(conn)
            marked = conn.execute("SELECT coalesce(sum(n_hits), 0) FROM fill_chunks").fetchone()[0]
            assert n == marked == conn.execute("SELECT count(*) FROM hits_rtree").fetchone()[0]
            conn.execute("COMMIT")
            conn.close()
            rc = main(
                [
                    "launcher",
                    "lookup",
                    "--db",
                    path,
                    "--target",
                    "8",
                    "1",
                    "--speed-kmh",
                    "100",
                    "--spin-rpm",
                    "0",
                    "--json",
                ]
            )
            out, err = capsys.readouterr()
            assert rc == 0, err
            assert json.loads(out)["miss_mm"] < 500
            answers += 1
            counts.append(n)
            time.sleep(0.02)
    finally:
        if proc.poll() is None:
            proc.kill()
        err = proc.communicate()[1].decode()
    assert proc.returncode == 0, err
    assert answers >= 3 and counts == sorted(counts) and counts[-1] > counts[0]


# ------------------------------------------------------------------ drills
DRILL = """# a drill with comments, odd spacing and flow style: export must give these bytes back
name: deep-corners
defaults: {speed_kmh: 90, spin_rpm: 1200,   interval_s: 4}
shots:
  left:  {target: [10.0,  3.5]}
  right:
    target: [10.0, -3.5]    # other corner
program:
  - sequence: [{shot: left}, {shot: right}]
    repeats: 3
"""


def test_drill_round_trip_and_revisions(tmp_path):
    path = str(tmp_path / "d.sqlite")
    f = tmp_path / "deep-corners.yaml"
    f.write_bytes(DRILL.encode())
    conn = db.open_db(path)
    info = _import(conn, f)
    assert info["revision"] == 1 and info["n_distinct"] == 2 and info["n_shots"] == 6 and info["name"] == "deep-corners"
    assert dd.drill_source(conn, "deep-corners") == DRILL.encode()
    shots = dd.drill_shots(conn, "deep-corners")
    assert [s["name"] for s in shots] == ["left", "right"]
    assert shots[1]["target"] == [10.0, -3.5] and shots[1]["speed_kmh"] == 90.0
    assert dd.drill_sequence(conn, "deep-corners") == ["left", "right"] * 3
    assert _import(conn, f)["revision"] == 1  # identical: unchanged
    f.write_bytes(DRILL.replace("repeats: 3", "repeats: 4").encode())
    assert _import(conn, f)["revision"] == 2
    assert dd.drill_sequence(conn, "deep-corners") == ["left", "right"] * 4
    assert [d["name"] for d in dd.list_drills(conn)] == ["deep-corners"]
    with pytest.raises(InputError, match="not in the database"):
        dd.drill_source(conn, "nope")
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: x\nprogram: []\n")
    with pytest.raises(InputError, match="program"):
        _import(conn, bad)
    assert [d["name"] for d in dd.list_drills(conn)] == ["deep-corners"]  # nothing half-imported
    conn.close()


def test_shipped_drills_round_trip_exactly(tmp_path):
    from importlib import resources

    from tennislab.launcher.drill_schema import shipped_drills

    path = str(tmp_path / "s.sqlite")
    conn = db.open_db(path)
    d = resources.files("tennislab") / "data" / "drills"
    files = sorted(p for p in d.iterdir() if p.name.endswith((".yaml", ".yml", ".json")))
    assert len(files) == len(shipped_drills()) >= 1
    for p in files:
        info = _import(conn, str(p))
        raw = p.read_bytes()
        assert dd.drill_source(conn, info["name"]) == raw
        parsed = drill_record(parse_drill(raw, str(p)))
        assert dd.drill_shots(conn, info["name"]) == json.loads(db.canonical_json(parsed["shots"]))
        assert dd.drill_sequence(conn, info["name"]) == parsed["sequence"]
    assert len(dd.list_drills(conn)) == len(files)
    conn.close()


def test_fill_on_a_dask_cluster_equals_local(tmp_path, params):
    """Chunks come back in any order from a Dask runner; the table is the same row for row."""
    distributed = pytest.importorskip("distributed")
    from tennislab.batch.schedulers import DaskRunner

    g = T.make_grid(
        DEFAULT_SPEC,
        {"height_m": (1, 1), "speed_kmh": (95, 105), "spin_rpm": (500, 500), "spin_axis_deg": (0, 0)},
        {"speed_kmh": 5, "heading_deg": 3},
    )
    a, b = str(tmp_path / "local.sqlite"), str(tmp_path / "dask.sqlite")
    T.fill_table(a, DEFAULT_SPEC, params, g, chunk_size=700)
    with (
        distributed.LocalCluster(
            n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None, silence_logs=40
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        rep = T.fill_table(b, DEFAULT_SPEC, params, g, chunk_size=700, runner=DaskRunner(client))
    assert rep.chunks_run == rep.n_chunks > 3
    ca, cb = db.open_readonly(a), db.open_readonly(b)
    assert (
        ca.execute("SELECT * FROM hits ORDER BY id").fetchall()
        == cb.execute("SELECT * FROM hits ORDER BY id").fetchall()
    )
    ca.close()
    cb.close()


@pytest.fixture(scope="module")
def lattice_db(tmp_path_factory, params):
    """Synthetic hits on a coarse lattice (many exact distance ties), unique clearances."""
    path = str(tmp_path_factory.mktemp("lat") / "lattice.sqlite")
    conn = db.open_db(path)
    db.bind_config(conn, db.config_dict(DEFAULT_SPEC, params))
    rng = np.random.default_rng(3)
    n = 600
    rows = {
        "id": np.arange(n),
        "height_m": np.full(n, 1.0),
        "speed_kmh": rng.choice([60.0, 61.0, 62.0], n),
        "elevation_deg": np.zeros(n),
        "heading_deg": np.zeros(n),
        "spin_rpm": rng.choice([0.0, 100.0], n),
        "spin_axis_deg": np.zeros(n),
        "land_x": rng.integers(0, 24, n) * 0.5,
        "land_y": rng.integers(-10, 11, n) * 0.5,
        "net_clearance_m": rng.permutation(n) * 1e-3,
        "flight_time_s": np.ones(n),
        "bounce_speed_ms": np.ones(n),
        "bounce_spin_rpm": np.zeros(n),
        "apex_z_m": np.ones(n),
    }
    conn.execute("BEGIN")
    db.insert_hits(conn, rows)
    conn.execute("COMMIT")
    conn.close()
    return path


@given(
    x=st.floats(0.0, 11.885),
    y=st.floats(-5.485, 5.485),
    sp=st.sampled_from([None, 60.0, 61.0, 62.0]),
    sw=st.sampled_from([None, 0.0, 100.0]),
    on_lattice=st.booleans(),
)
@settings(max_examples=150, deadline=None)
def test_rtree_nearest_equals_scan_with_ties(lattice_db, x, y, sp, sw, on_lattice):
    if on_lattice:  # equidistant lattice points: ties resolved by clearance in both methods
        x, y = round(x * 2) / 2 + 0.25, round(y * 2) / 2 + 0.25
    conn = db.open_readonly(lattice_db)
    a = lk.nearest_hit(conn, x, y, speed_kmh=sp, spin_rpm=sw)
    b = lk.scan_nearest(conn, x, y, speed_kmh=sp, spin_rpm=sw)
    conn.close()
    assert (a is None) == (b is None)
    if a is not None:
        assert a["id"] == b["id"] and a["miss_m"] == pytest.approx(b["miss_m"], abs=1e-12)


def _ray_rows(n_speed=4, n_spin=3):
    """Synthetic hits on rays from the machine (one per heading; heading 0 is the line y = 0), dense along each
    ray, as in benchmarks/bench_db.py: lookups with an open speed or spin meet them by the hundred."""
    rng = np.random.default_rng(7)
    sp, sw, hd, r = np.meshgrid(
        60.0 + np.arange(n_speed),
        100.0 * np.arange(n_spin),
        np.arange(-6.0, 7.0),
        np.linspace(14.0, 24.0, 180),
        indexing="ij",
    )
    r = (r + rng.uniform(-0.05, 0.05, r.shape)).ravel()
    n = r.size
    heading = hd.ravel()
    x, y = -12.0 + r * np.cos(np.radians(heading)), r * np.sin(np.radians(heading))
    y[heading == 0] = 0.0
    return {
        "id": np.arange(n),
        "height_m": rng.choice([1.0, 2.0], n),
        "speed_kmh": sp.ravel(),
        "elevation_deg": np.zeros(n),
        "heading_deg": heading,
        "spin_rpm": sw.ravel(),
        "spin_axis_deg": rng.choice([0.0, 180.0], n),
        "land_x": x,
        "land_y": y,
        "net_clearance_m": rng.permutation(n) * 1e-4,
        "flight_time_s": np.ones(n),
        "bounce_speed_ms": np.ones(n),
        "bounce_spin_rpm": np.zeros(n),
        "apex_z_m": np.ones(n),
    }


@pytest.fixture(scope="module")
def ray_dbs(tmp_path_factory, params):
    """The same synthetic hits in a file of the current schema and one of schema 3 (R*Tree ``hits_xy``)."""
    rows = _ray_rows()
    paths = []
    for version in (db.SCHEMA_VERSION, 3):
        path = str(tmp_path_factory.mktemp("rays") / f"rays_v{version}.sqlite")
        conn = db.open_db(path, target_version=version)
        db.bind_config(conn, db.config_dict(DEFAULT_SPEC, params))
        conn.execute("BEGIN")
        db.insert_hits(conn, rows)
        conn.execute("COMMIT")
        conn.close()
        paths.append(path)
    return rows, paths


def _brute(rows, x, y, max_m=1.0, tie_m=lk.TIE_M, **eq):
    """Reference answer by numpy over every row: nearest, ties to the larger clearance, then the smaller id."""
    m = np.ones(len(rows["id"]), bool)
    for c, v in eq.items():
        m &= (rows[c] >= v[0]) & (rows[c] <= v[1]) if isinstance(v, tuple) else np.abs(rows[c] - v) <= 1e-3
    idx = np.flatnonzero(m)
    if idx.size == 0:
        return None
    miss = np.hypot(rows["land_x"][idx] - x, rows["land_y"][idx] - y)
    if miss.min() > max_m:
        return None
    cand = idx[miss <= miss.min() + tie_m]
    best = cand[rows["net_clearance_m"][cand] == rows["net_clearance_m"][cand].max()].min()
    return int(rows["id"][best])


FORMS = {
    "speed+spin": lambda s, w: {"speed_kmh": s, "spin_rpm": w},
    "speed only": lambda s, w: {"speed_kmh": s},
    "spin only": lambda s, w: {"spin_rpm": w},
    "any": lambda s, w: {},
    "any, height": lambda s, w: {"where": {"height_m": (1.9, 2.1)}},
    "speed, axis": lambda s, w: {"speed_kmh": s, "where": {"spin_axis_deg": (179.0, 181.0)}},
}


@pytest.mark.parametrize("form", FORMS)
def test_every_lookup_form_equals_brute_force(ray_dbs, form):
    """Band indexes (schema 4), R*Tree boxes (schema 3) and a brute force agree on random targets, targets on
    the ray y = 0 and on band edges (y a multiple of 1 cm), for every form of lookup."""
    rows, paths = ray_dbs
    conns = [db.open_readonly(p) for p in paths]
    rng = np.random.default_rng(11)
    targets = [(rng.uniform(1.0, 12.0), rng.uniform(-2.5, 2.5)) for _ in range(40)]
    targets += [(rng.uniform(2.0, 11.0), v) for v in (0.0, 1e-4, -0.01, 0.02, 0.3, -1.23)]
    for x, y in targets:
        s, w = float(rng.choice([60.0, 61.0, 63.0, 64.0])), float(rng.choice([0.0, 100.0, 200.0, 250.0]))
        kw = FORMS[form](s, w)
        eq = {k: v for k, v in kw.items() if k != "where"} | kw.get("where", {})
        want = _brute(rows, x, y, **eq)
        for conn in conns:
            hit = lk.nearest_hit(conn, x, y, max_m=1.0, **kw)
            assert (hit is None) == (want is None), (form, x, y, s, w)
            if hit is not None:
                assert hit["id"] == want, (form, x, y, s, w)
                assert hit["miss_m"] == np.hypot(hit["land_x"] - x, hit["land_y"] - y)
                assert hit["n_candidates"] < len(rows["id"]) / 10  # an index query, not a scan
        if want is not None and not kw.get("where"):  # the full scan of the benchmark agrees too
            assert lk.scan_nearest(conns[0], x, y, **kw)["id"] == want
    for conn in conns:
        conn.close()


def test_schema_3_file_stays_readable(ray_dbs):
    """A reader accepts a file of schema 3 (no band indexes) and answers from its R*Trees."""
    _, paths = ray_dbs
    conn = db.open_readonly(paths[1])
    assert conn.execute("PRAGMA user_version").fetchone()[0] == 3
    conn.close()
    hdb = HitsDB(paths[1])
    res = hdb.lookup((8.0, 0.05), trajectory="any")
    assert res.miss_mm < 100 and res.hits_read >= 1
    with pytest.raises(InputError, match="no trajectory branches.*migrate"):
        hdb.lookup((8.0, 0.05))


# ------------------------------------------------------- preferences in every form
def _rows_with_flights(seed=9):
    rows = _ray_rows()
    rng = np.random.default_rng(seed)
    n = len(rows["id"])
    rows["branch"] = rng.integers(0, 2, n)
    rows["apex_z_m"] = rng.uniform(1.0, 12.0, n)
    rows["flight_time_s"] = rng.uniform(0.6, 4.0, n)
    return rows


@pytest.fixture(scope="module")
def pref_db(tmp_path_factory, params):
    rows = _rows_with_flights()
    path = str(tmp_path_factory.mktemp("prefs") / "prefs.sqlite")
    conn = db.open_db(path)
    db.bind_config(conn, db.config_dict(DEFAULT_SPEC, params))
    conn.execute("BEGIN")
    db.insert_hits(conn, rows)
    conn.execute("COMMIT")
    conn.close()
    return rows, path


def _brute_query(rows, x, y, q, max_m=1.0, tie_m=lk.TIE_M):
    idx = np.flatnonzero(q.mask(rows))
    if idx.size == 0:
        return None
    miss = np.hypot(rows["land_x"][idx] - x, rows["land_y"][idx] - y)
    if miss.min() > max_m:
        return None
    cand = idx[miss <= miss.min() + tie_m]
    ds = np.abs(rows["speed_kmh"][cand] - q.speed_kmh) if q.speed_kmh is not None else np.zeros(cand.size)
    dw = np.abs(rows["spin_rpm"][cand] - q.spin_rpm) if q.spin_rpm is not None else np.zeros(cand.size)
    order = np.lexsort((rows["id"][cand], -rows["net_clearance_m"][cand], dw, ds))
    return int(rows["id"][cand[order[0]]])


PREF_FORMS = {
    "speed+spin low": lambda s, w: lk.HitQuery.exact(s, w, preferences=Preferences("low")),
    "speed high": lambda s, w: lk.HitQuery.exact(s, None, preferences=Preferences("high")),
    "spin, apex<=6": lambda s, w: lk.HitQuery.exact(None, w, preferences=Preferences("any", max_apex_m=6.0)),
    "any, band, time": lambda s, w: lk.HitQuery(
        preferences=Preferences("low", net_clearance_m=(0.02, 0.3), max_flight_time_s=2.5)
    ),
    "windows +-1.5/150": lambda s, w: lk.HitQuery(s, w, (s - 1.5, s + 1.5), (w - 150, w + 150), {}, Preferences("any")),
    "spin vector 60 rpm": lambda s, w: lk.HitQuery(
        s, w, (s - 0.4, s + 0.4), (w - 60, w + 60), {}, Preferences("any"), (w, 180.0, 60.0, 0.0)
    ),
    "axis tolerance": lambda s, w: lk.HitQuery(
        None, w, None, (w - 120, w + 120), {}, Preferences("low"), (w, 0.0, 120.0, 10.0)
    ),
}


@pytest.mark.parametrize("form", PREF_FORMS)
def test_every_preference_form_equals_brute_force(pref_db, form):
    """Trajectory branch, apex, net-clearance band, flight time, tolerance windows and the spin-vector rule:
    the index answer is the brute force's, ties included (the tie rule of lookup.py)."""
    rows, path = pref_db
    conn = db.open_readonly(path)
    rng = np.random.default_rng(13)
    found = 0
    for _ in range(40):
        x, y = rng.uniform(1.0, 12.0), rng.uniform(-2.5, 2.5)
        s, w = float(rng.choice([60.0, 61.0, 62.0, 63.0])), float(rng.choice([0.0, 100.0, 200.0]))
        q = PREF_FORMS[form](s, w)
        want = _brute_query(rows, x, y, q)
        hit = lk.nearest_hit(conn, x, y, query=q, max_m=1.0)
        assert (hit is None) == (want is None), (form, x, y, s, w)
        if hit is not None:
            found += 1
            assert hit["id"] == want, (form, x, y, s, w)
            assert q.mask({k: np.array([v]) for k, v in hit.items() if k in rows})[0]
            scan = lk.scan_nearest(conn, x, y, query=q)
            assert scan["id"] == want
    conn.close()
    assert found >= 10


def test_hitsdb_lookup_never_breaks_preferences(table_db):
    hdb = HitsDB(table_db)
    rng = np.random.default_rng(4)
    for _ in range(25):
        x, y = rng.uniform(4.0, 11.5), rng.uniform(-4.0, 4.0)
        kw = dict(
            trajectory=str(rng.choice(["low", "high", "any"])),
            max_apex_m=float(rng.choice([3.0, 6.0, 30.0])),
            max_flight_time_s=float(rng.choice([1.5, 5.0])),
        )
        try:
            res = hdb.lookup((x, y), float(rng.choice([80.0, 100.0, 120.0])), **kw)
        except InputError as exc:
            assert str(exc).split(":")[0] in ("trajectory", "max_apex_m", "max_flight_time_s", "target"), exc
            continue
        h = res.hit
        assert h["apex_z_m"] <= kw["max_apex_m"] and h["flight_time_s"] <= kw["max_flight_time_s"]
        if kw["trajectory"] != "any":
            assert res.branch == kw["trajectory"]


def test_stored_branches_match_the_aims(table_db, params):
    """A hit's branch is the aiming branch: aim's low and high solutions are stored as low and high."""
    conn = db.open_readonly(table_db)
    for target in ((9.0, 2.0), (6.0, -1.0), (10.5, 3.0)):
        sols, _ = aim_all(target, 100.0, 0.0, 0.0, 1.0, DEFAULT_SPEC, params, tolerances=EXACT)
        for name, sol in sols.items():
            s = sol.settings
            row = conn.execute(
                "SELECT branch FROM hits WHERE speed_kmh = 100 AND spin_rpm = 0 AND elevation_deg = ? "
                "AND heading_deg = ? AND height_m = 1",
                (s.elevation_deg, s.heading_deg),
            ).fetchone()
            assert row is not None and row[0] == (0 if name == "low" else 1), (target, name)
    conn.close()


def test_migration_5_gives_stored_hits_their_branch(tmp_path, params, table_db):
    """A schema-4 file migrated to 5 derives each hit's branch from its neighbours: the flown ones agree."""
    src = db.open_readonly(table_db)
    flown = {r[0]: r[1] for r in src.execute("SELECT id, branch FROM hits")}
    rows = src.execute(f"SELECT {', '.join(db.HIT_COLUMNS_V4)} FROM hits").fetchall()
    src.close()
    path = str(tmp_path / "v4.sqlite")
    conn = db.open_db(path, target_version=4)
    db.bind_config(conn, db.config_dict(DEFAULT_SPEC, params))
    conn.execute("BEGIN")
    conn.executemany(f"INSERT INTO hits VALUES ({','.join('?' * len(db.HIT_COLUMNS_V4))})", rows)
    conn.execute("COMMIT")
    conn.close()
    conn = db.open_db(path)  # migrates to 5
    derived = dict(conn.execute("SELECT id, branch FROM hits").fetchall())
    conn.close()
    agree = np.mean([derived[i] == b for i, b in flown.items()])
    assert agree > 0.99


def test_refusal_names_the_bound_that_excludes_the_asked_branch(table_db):
    """When low hits land there but peak too high, the refusal names max_apex_m (not the trajectory,
    even if the nearest hit of any branch is a high one)."""
    hdb = HitsDB(table_db)
    ok = hdb.lookup((9.0, 2.0), 100.0, trajectory="low")
    cap = 0.5 * (ok.hit["apex_z_m"] + 1.0)  # below that low flight's apex, above the launch height
    with pytest.raises(InputError, match=r"^max_apex_m: no hit within .* peaks higher") as exc:
        hdb.lookup((9.0, 2.0), 100.0, trajectory="low", max_apex_m=min(cap, 1.05))
    assert "only high ones" not in str(exc.value)


def test_a_failed_import_never_deletes_a_database_it_did_not_create(tmp_path, monkeypatch):
    """The database is created with O_EXCL: one another process made at the same moment (here: after a
    check that found nothing) is not ours and survives our failed import; a new one of ours is removed."""
    import sqlite3 as _sqlite3

    import tennislab.launcher._dbdrills as _dd
    import tennislab.launcher.hitsdb as H

    theirs = str(tmp_path / "theirs.sqlite")
    HitsDB(theirs).import_drills(["lobs"])
    before = open(theirs, "rb").read()

    def disk_full(*a, **k):
        raise _sqlite3.OperationalError("database or disk is full")

    monkeypatch.setattr(_dd, "import_drill", disk_full)
    monkeypatch.setattr(H.os.path, "lexists", lambda p: False)  # a check that raced with their creation
    with pytest.raises(InputError, match="disk is full"):
        HitsDB(theirs).import_drills(["lobs"])
    monkeypatch.undo()
    assert os.path.exists(theirs) and len(open(theirs, "rb").read()) >= len(before) > 0
    assert [d["name"] for d in HitsDB(theirs).list_drills(shipped=False).drills] == ["Lobs"]
    monkeypatch.setattr(_dd, "import_drill", disk_full)
    ours = tmp_path / "ours.sqlite"
    with pytest.raises(InputError, match="disk is full"):
        HitsDB(str(ours)).import_drills(["lobs"])
    assert not [p.name for p in tmp_path.iterdir() if p.name.startswith("ours")]
