"""``tennislab launcher table | lookup | drills``: contract keys, agreement with ``aim``, one-line errors."""

from __future__ import annotations

import json
import os
import sqlite3

import numpy as np
import pytest

from tennislab.cli import main

GRID = [
    "--height",
    "1",
    "--speed-kmh",
    "90",
    "110",
    "--step",
    "speed",
    "10",
    "--spin-rpm",
    "0",
    "1000",
    "--step",
    "spin",
    "1000",
    "--spin-axis-deg",
    "0",
    "0",
    "--chunk-size",
    "8181",
    "--no-progress",
]
AIM_KEYS = (
    "settings.height_m",
    "settings.speed_kmh",
    "settings.elevation_deg",
    "settings.heading_deg",
    "settings.spin_rpm",
    "settings.spin_axis_deg",
    "rollers.rpm1",
    "rollers.rpm2",
    "landing.x",
    "landing.y",
    "miss_mm",
    "net_clearance_m",
)


def _get(d, dotted):
    for k in dotted.split("."):
        d = d[k]
    return d


def run(capsys, *argv):
    try:
        rc = main(list(argv))
    except SystemExit as exc:  # argparse errors
        rc = exc.code
    out, err = capsys.readouterr()
    return rc, out, err


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    path = str(tmp_path_factory.mktemp("cli") / "hits.sqlite")
    assert main(["launcher", "table", "--db", path, *GRID]) == 0
    return path


def test_table_then_lookup_json_keys(built, capsys):
    rc, out, err = run(
        capsys,
        "launcher",
        "lookup",
        "--db",
        built,
        "--target",
        "9",
        "2",
        "--speed-kmh",
        "100",
        "--spin-rpm",
        "1000",
        "--no-fallback",
        "--json",
    )
    assert rc == 0, err
    d = json.loads(out)
    assert d["source"] == "table" and d["fallback_ms"] is None
    for k in AIM_KEYS + ("lookup_ms", "branch", "apex_z_m", "flight_time_s", "db.hash"):
        assert _get(d, k) is not None, k
    assert d["settings"]["speed_kmh"] == 100.0 and d["settings"]["spin_rpm"] == 1000.0
    assert 0 <= d["lookup_ms"] < 1000
    assert d["miss_mm"] < 1000


@pytest.mark.parametrize(
    "target,speed,spin",
    [((9.0, 2.0), 100, 1000), ((5.5, -2.5), 90, 0), ((10.5, -3.0), 110, 1000), ((7.0, 3.5), 100, 0)],
)
def test_lookup_agrees_with_aim(built, capsys, target, speed, spin):
    tx, ty = map(str, target)
    rc, out, err = run(
        capsys,
        "launcher",
        "lookup",
        "--db",
        built,
        "--target",
        tx,
        ty,
        "--speed-kmh",
        str(speed),
        "--spin-rpm",
        str(spin),
        "--speed-tolerance-kmh",
        "0",
        "--spin-tolerance-rpm",
        "0",
        "--trajectory",
        "any",
        "--json",
    )
    assert rc == 0, err
    look = json.loads(out)
    aims = []
    for sol in ("low", "high"):
        rc, out, err = run(
            capsys,
            "launcher",
            "aim",
            "--target",
            tx,
            ty,
            "--speed-kmh",
            str(speed),
            "--spin-rpm",
            str(spin),
            "--solution",
            sol,
            "--height",
            "1",
            "--speed-tolerance-kmh",
            "0",
            "--spin-tolerance-rpm",
            "0",
            "--spin-axis-tolerance-deg",
            "0",
            "--json",
        )
        if rc == 0:
            aims.append(json.loads(out))
    assert aims
    best = min(aims, key=lambda a: a["miss_mm"])
    # the aim's quantised settings are a row of the table, so the table's nearest is at least as near
    assert look["miss_mm"] <= best["miss_mm"] + 0.05
    same = [a for a in aims if a["settings"] == look["settings"]]
    if abs(look["miss_mm"] - best["miss_mm"]) > 1.0:
        assert same
    for a in same:
        assert look["landing"]["x"] == pytest.approx(a["landing"]["x"], abs=1e-5)
        assert look["rollers"] == pytest.approx(a["rollers"])


def _one_line_error(rc, err):
    assert rc == 2
    assert "Traceback" not in err
    assert len(err.strip().splitlines()) == 1 and "error" in err


def test_errors_are_one_line_exit_2(built, tmp_path, capsys):
    cases = []
    # truncated copy of the table
    src, trunc = sqlite3.connect(built), tmp_path / "trunc.sqlite"
    dst = sqlite3.connect(trunc)
    src.backup(dst)
    src.close()
    dst.close()
    data = trunc.read_bytes()
    trunc.write_bytes(data[: len(data) // 4])
    cases.append(["--db", str(trunc), "--target", "8", "1", "--speed-kmh", "100", "--spin-rpm", "0"])
    # foreign files: another application's SQLite, and plain text
    foreign = tmp_path / "foreign.sqlite"
    c = sqlite3.connect(foreign)
    c.execute("CREATE TABLE notes (t TEXT)")
    c.commit()
    c.close()
    text = tmp_path / "text.sqlite"
    text.write_text("not a database\n" * 200)
    cases += [
        ["--db", str(foreign), "--target", "8", "1"],
        ["--db", str(text), "--target", "8", "1"],
        ["--db", str(tmp_path / "missing.sqlite"), "--target", "8", "1"],
    ]
    # stale hash: other physics, other machine
    cases += [
        ["--db", built, "--target", "8", "1", "--aero", "stepanek1988"],
        ["--db", built, "--target", "8", "1", "--mass", "0.058"],
        ["--db", built, "--target", "8", "1", "--machine-position", "-12", "1"],
    ]
    # off the court; no hit in range
    cases += [
        ["--db", built, "--target", "12.5", "0"],
        ["--db", built, "--target", "-3", "0"],
        ["--db", built, "--target", "8", "1", "--speed-kmh", "150", "--no-fallback"],
        ["--db", built, "--target", "8", "1", "--speed-kmh", "250"],
        ["--db", built, "--target", "0.2", "0", "--speed-kmh", "110", "--max-miss-m", "0.05"],
    ]
    for argv in cases:
        rc, out, err = run(capsys, "launcher", "lookup", *argv)
        _one_line_error(rc, err)
    # a speed the table does not hold: the machine's aim answers (its reach map), and says so
    rc, out, err = run(capsys, "launcher", "lookup", "--db", built, "--target", "8", "1", "--speed-kmh", "150")
    assert rc == 0 and "source: inverse-map (no stored hit; the machine's aim from its reach map" in out, err
    for argv in (
        ["--db", built, *GRID, "--aero", "stepanek1988"],
        ["--db", str(foreign), *GRID],
        ["--db", str(text), *GRID],
        ["--db", built, *GRID, "--speed-kmh", "20", "40"],
        ["--db", built, *GRID, "--step", "bogus", "2"],
    ):
        rc, out, err = run(capsys, "launcher", "table", *argv)
        _one_line_error(rc, err)
    # nothing was written into the foreign file
    c = sqlite3.connect(foreign)
    assert [r[0] for r in c.execute("SELECT name FROM sqlite_master")] == ["notes"]
    assert c.execute("PRAGMA journal_mode").fetchone()[0] == "delete"
    assert c.execute("PRAGMA user_version").fetchone()[0] == 0
    c.close()


def test_table_resumes(tmp_path, capsys):
    path = str(tmp_path / "r.sqlite")
    small = [
        "--height",
        "1",
        "--speed-kmh",
        "100",
        "100",
        "--spin-rpm",
        "0",
        "0",
        "--spin-axis-deg",
        "0",
        "0",
        "--chunk-size",
        "1000",
        "--no-progress",
        "--json",
    ]
    rc, out, err = run(capsys, "launcher", "table", "--db", path, *small, "--max-chunks", "2")
    assert rc == 0, err
    first = json.loads(out)
    assert first["chunks_run"] == 2 and first["n_chunks"] == 9
    rc, out, err = run(capsys, "launcher", "table", "--db", path, *small)
    second = json.loads(out)
    assert second["chunks_done_before"] == 2 and second["chunks_run"] == 7
    assert second["hits_total"] == first["hits_inserted"] + second["hits_inserted"]


DRILL = b"""# kept byte for byte
name: cli-drill
defaults: {speed_kmh: 100, spin_rpm: 1000, interval_s: 3}
shots:
  a: {target: [9.0, 2.0]}
  b: {target: [9.0, -2.0]}
program:
  - {shot: a}
  - {shot: b,  repeats: 2}
"""


def test_drills_import_export_list(tmp_path, capsys, monkeypatch):
    path = str(tmp_path / "d.sqlite")
    f = tmp_path / "cli-drill.yaml"
    f.write_bytes(DRILL)
    rc, out, err = run(capsys, "launcher", "drills", "import", "--db", path, str(f))
    assert rc == 0, err
    rc, out, err = run(capsys, "launcher", "drills", "list", "--db", path, "--json")
    d = [x for x in json.loads(out)["drills"] if x["source"] == "stored"]
    assert [(x["name"], x["revision"], x["n_shots"], x["n_distinct"]) for x in d] == [("cli-drill", 1, 3, 2)]
    back = tmp_path / "out" / "back.yaml"
    rc, out, err = run(capsys, "launcher", "drills", "export", "--db", path, "cli-drill", str(back))
    assert rc == 0, err
    assert back.read_bytes() == DRILL
    monkeypatch.chdir(tmp_path / "out")
    rc, out, err = run(capsys, "launcher", "drills", "export", "--db", path, "cli-drill.yaml")
    assert rc == 0, err
    assert (tmp_path / "out" / "cli-drill.yaml").read_bytes() == DRILL
    rc, out, err = run(capsys, "launcher", "drills", "export", "--db", path, "nothing-here.yaml")
    _one_line_error(rc, err)
    rc, out, err = run(capsys, "launcher", "drills", "import", "--db", path, str(tmp_path / "nope.yaml"))
    _one_line_error(rc, err)


# ------------------------------------------------------------ the cases
def _lookup(capsys, db, *args):
    rc, out, err = run(capsys, "launcher", "lookup", "--db", db, *map(str, args), "--json")
    return rc, (json.loads(out) if rc == 0 else None), err


def test_lookup_prefers_a_drive_and_meets_preferences(built, capsys):
    """The issue's moonball: 9 2 at 100 km/h, 1000 rpm gave a 70 deg lob; the default is now the low branch."""
    rc, d, err = _lookup(capsys, built, "--target", 9, 2, "--speed-kmh", 100, "--spin-rpm", 1000)
    assert rc == 0, err
    assert d["branch"] == "low" and d["settings"]["elevation_deg"] < 30 and d["apex_z_m"] < 5
    rc, hi, err = _lookup(
        capsys, built, "--target", 9, 2, "--speed-kmh", 100, "--spin-rpm", 1000, "--trajectory", "high"
    )
    assert rc == 0 and hi["branch"] == "high" and hi["settings"]["elevation_deg"] > 45
    rc, capped, err = _lookup(
        capsys,
        built,
        "--target",
        9,
        2,
        "--speed-kmh",
        100,
        "--max-apex-m",
        2.5,
        "--net-clearance-m",
        0.3,
        2.0,
        "--trajectory",
        "any",
    )
    assert rc == 0, err
    assert capped["apex_z_m"] <= 2.5 and 0.3 <= capped["net_clearance_m"] <= 2.0
    rc, t, err = _lookup(capsys, built, "--target", 9, 2, "--max-flight-time-s", 1.0, "--trajectory", "any")
    assert rc == 0 and t["flight_time_s"] <= 1.0
    for args, flag in (
        (["--max-apex-m", 1.05], "--max-apex-m"),
        (["--max-flight-time-s", 0.05], "--max-flight-time-s"),
        (["--speed-tolerance-kmh", -1], "--speed-tolerance-kmh"),
        (["--net-clearance-m", 2, 1], "--net-clearance-m"),
    ):
        rc, _, err = _lookup(capsys, built, "--target", 9, 2, "--speed-kmh", 100, "--trajectory", "any", *args)
        _one_line_error(rc, err)
        assert err.split("error: ")[1].startswith(flag), err


def test_lookup_and_play_need_no_machine_flags_and_refuse_different_ones(built, capsys):
    rc, d, err = _lookup(capsys, built, "--target", 9, 2)
    assert rc == 0, err
    rc, same, err = _lookup(capsys, built, "--target", 9, 2, "--machine-position", -12.385, 0, "--mass", 0.0577)
    assert rc == 0 and same["settings"] == d["settings"]
    rc, _, err = _lookup(capsys, built, "--target", 9, 2, "--mass", 0.06, "--roller-radius", 0.12)
    _one_line_error(rc, err)
    assert "physics.ball.mass" in err and "machine.roller_radius" in err


def test_info_describes_the_file(built, capsys):
    rc, out, err = run(capsys, "launcher", "info", "--db", built, "--json")
    assert rc == 0, err
    d = json.loads(out)
    assert d["schema_version"] == 5 and len(d["hash"]) == 64 and d["hits"] > 1000
    assert d["ranges"]["speed_kmh"] == {"min": 90.0, "max": 110.0, "count": 3}
    assert d["machine"]["position"] == [-12.385, 0.0] and d["physics"]["aero"]["name"] == "choppin2018"
    assert d["physics_preset"] == "standard"  # built with every command's default physics
    assert d["quick_check"] == "ok" and d["fills"][0]["finished_utc"]
    rc, out, err = run(capsys, "launcher", "info", "--db", built)
    assert rc == 0 and "hash" in out and "speed_kmh: 90 .. 110" in out


def test_table_refuses_the_whole_grid_and_estimates_every_fill(tmp_path, capsys):
    path = tmp_path / "t.sqlite"
    rc, out, err = run(capsys, "launcher", "table", "--db", str(path))
    _one_line_error(rc, err)
    assert "3.03e+13 settings" in err and "--height 1" in err and not path.exists()
    rc, out, err = run(capsys, "launcher", "table", "--db", str(path), "--height", "1", "--no-progress")
    assert rc == 2 and "estimated" in err and "--yes" in err and not path.exists()
    rc, out, err = run(capsys, "launcher", "table", "--db", str(path), *GRID)
    assert rc == 0, err
    assert err.startswith("table: 49,086 settings (1 x 3 x 2 x 1 x 101 x 81)") and "estimated" in err
    rc, out, err = run(capsys, "launcher", "table", "--db", str(path), *GRID, "--json")  # resumed: nothing left
    assert rc == 0 and "0 to fly" in err and json.loads(out)["chunks_run"] == 0


def test_play_emits_the_timed_settings_without_flying(tmp_path, capsys, monkeypatch):
    import importlib

    import tennislab.core.flight as F  # the table imports core's fly_batch where it flies

    A = importlib.import_module("tennislab.launcher.aim")  # the module (tennislab.launcher.aim is the function)

    path = str(tmp_path / "play.sqlite")
    drill = tmp_path / "two.yaml"
    drill.write_text(
        "name: Two corners\ndefaults: {speed_kmh: 100, spin_rpm: 1000, interval_s: 3}\n"
        "shots:\n  a: {target: [9.0, 2.0]}\n  b: {target: [9.0, -2.0], interval_s: 5}\n"
        "program: [{shot: a}, {shot: b, repeats: 2}]\n"
    )
    rc, out, err = run(capsys, "launcher", "table", "--db", path, "--drill", str(drill), "--no-progress")
    assert rc == 0, err
    rc, out, err = run(capsys, "launcher", "drills", "import", "--db", path, str(drill))
    assert rc == 0, err

    def no_flight(*a, **k):
        raise AssertionError("play flew a ball")

    monkeypatch.setattr(F, "fly_batch", no_flight)
    monkeypatch.setattr(A, "fly_batch", no_flight)
    rc, out, err = run(capsys, "launcher", "play", "--db", path, "--drill", "two_corners", "--jsonl")
    assert rc == 0, err
    lines = [json.loads(x) for x in out.splitlines()]
    assert [x["shot"] for x in lines] == ["a", "b", "b"]
    assert [x["time_s"] for x in lines] == [0, 3, 8] and [x["interval_s"] for x in lines] == [3, 5, 5]
    for x in lines:
        for k in ("height_m", "speed_kmh", "elevation_deg", "heading_deg", "spin_rpm", "spin_axis_deg", "rpm1", "rpm2"):
            assert isinstance(x[k], float), k
        assert x["miss_mm"] < 500 and x["in_zone"]
    rc, out, err = run(capsys, "launcher", "play", "--db", path, "--drill", "no_such", "--json")
    _one_line_error(rc, err)
    assert "--drill: 'no_such'" in err


def test_drill_counts_agree_and_shipped_drills_are_listed(tmp_path, capsys):
    rc, out, err = run(capsys, "launcher", "drills", "list", "--json")
    shipped = {d["key"]: d for d in json.loads(out)["drills"]}
    assert {"baseline_rally", "lobs", "return_of_serve", "approach_and_volley"} <= set(shipped)
    path = str(tmp_path / "d.sqlite")
    rc, out, err = run(capsys, "launcher", "drills", "import", "--db", path, "lobs")
    assert rc == 0, err
    rc, out, err = run(capsys, "launcher", "drills", "list", "--db", path, "--json")
    rows = json.loads(out)["drills"]
    stored = [d for d in rows if d["source"] == "stored"]
    assert [d["key"] for d in stored] == ["lobs"] and len(rows) == len(shipped) + 1
    rc, out, err = run(capsys, "launcher", "drill", "--drill", "Lobs", "--db", path, "--json")
    assert rc == 0, err
    compiled = json.loads(out)
    assert compiled["n_shots"] == stored[0]["n_shots"] == shipped["lobs"]["n_shots"] == 10
    assert compiled["n_distinct"] == stored[0]["n_distinct"] == 4


def test_export_never_follows_a_stored_path(tmp_path, capsys, monkeypatch):
    """A database from someone else names its drills' files '/abs/path.yaml', '../x.yaml': written here, base names."""
    path = str(tmp_path / "crafted.sqlite")
    f = tmp_path / "src" / "a.yaml"
    f.parent.mkdir()
    f.write_bytes(DRILL)
    assert main(["launcher", "drills", "import", "--db", path, str(f)]) == 0
    f.write_bytes(DRILL.replace(b"cli-drill", b"second"))
    assert main(["launcher", "drills", "import", "--db", path, str(f)]) == 0
    victim = tmp_path / "victim.yaml"
    c = sqlite3.connect(path)
    c.execute("UPDATE drills SET filename = ? WHERE name = 'cli-drill'", (str(victim),))
    c.execute("UPDATE drills SET filename = '../../escape.yaml' WHERE name = 'second'")
    c.commit()
    c.close()
    work = tmp_path / "work" / "deep"
    work.mkdir(parents=True)
    monkeypatch.chdir(work)
    capsys.readouterr()
    rc, out, err = run(capsys, "launcher", "drills", "export", "--db", path, "--json")
    assert rc == 0, err
    written = sorted(p.name for p in work.iterdir())
    assert written == ["escape.yaml", "victim.yaml"]
    assert not victim.exists() and not (tmp_path / "escape.yaml").exists()
    assert {os.path.dirname(d["path"]) for d in json.loads(out)["exported"]} == {""}


def test_failed_starts_create_nothing(tmp_path, capsys):
    path = tmp_path / "new.sqlite"
    blocker = tmp_path / "afile"
    blocker.write_text("x")
    for extra in (["--out-dir", str(blocker / "parts")], ["--scheduler", "tcp://127.0.0.1:9"]):
        rc, out, err = run(capsys, "launcher", "table", "--db", str(path), *GRID, *extra)
        lines = err.strip().splitlines()  # the size and time estimate, then the error
        assert rc == 2 and "Traceback" not in err and lines[-1].startswith("tennislab launcher"), err
        assert ": error: " in lines[-1], err
        assert all(x.startswith("table: ") for x in lines[:-1]) and len(lines) <= 2
        assert not path.exists() and not (tmp_path / "new.sqlite-wal").exists(), extra
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: x\nprogram: []\n")
    rc, out, err = run(capsys, "launcher", "drills", "import", "--db", str(path), str(bad))
    _one_line_error(rc, err)
    assert not path.exists()


def test_read_only_commands_touch_nothing(built, tmp_path, capsys, monkeypatch):
    import shutil

    copy = tmp_path / "ro" / "hits.sqlite"
    copy.parent.mkdir()
    src = sqlite3.connect(built)
    dst = sqlite3.connect(copy)
    src.backup(dst)
    src.close()
    dst.close()
    before = copy.read_bytes()
    monkeypatch.chdir(tmp_path)
    for argv in (
        ["info", "--db", str(copy)],
        ["lookup", "--db", str(copy), "--target", "9", "2"],
        ["drills", "list", "--db", str(copy)],
        ["play", "--db", str(copy), "--drill", "lobs"],  # fails (no hits for lobs): still nothing written
    ):
        run(capsys, "launcher", *argv)
        assert sorted(p.name for p in copy.parent.iterdir()) == ["hits.sqlite"], argv
    assert copy.read_bytes() == before
    shutil.rmtree(copy.parent)


def test_foreign_file_with_a_pending_wal_is_left_alone(tmp_path, capsys):
    path = tmp_path / "foreign.sqlite"
    w = sqlite3.connect(path, isolation_level=None)
    w.execute("PRAGMA journal_mode=WAL")
    w.execute("PRAGMA wal_autocheckpoint=0")
    w.execute("CREATE TABLE notes (t TEXT)")
    w.execute("INSERT INTO notes VALUES ('keep me')")
    wal = tmp_path / "foreign.sqlite-wal"
    snapshot = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    assert wal.exists() and wal.stat().st_size > 0
    for argv in (
        ["lookup", "--db", str(path), "--target", "9", "2"],
        ["info", "--db", str(path)],
        ["table", "--db", str(path), *GRID],
        ["drills", "import", "--db", str(path), "lobs"],
        ["drills", "list", "--db", str(path)],
    ):
        rc, out, err = run(capsys, "launcher", *argv)
        _one_line_error(rc, err)
        assert "another application" in err or "not a tennislab" in err, err
        assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == snapshot, argv
    w.close()


def test_bit_flips_are_reported_as_damaged(built, tmp_path, capsys):
    src = sqlite3.connect(built)
    clean = tmp_path / "clean.sqlite"
    dst = sqlite3.connect(clean)
    src.backup(dst)
    src.close()
    dst.close()
    data = bytearray(clean.read_bytes())
    rng = np.random.default_rng(5)
    outcomes = {"ok": 0, "error": 0}
    for i in range(24):
        flipped = bytearray(data)
        pos = int(rng.integers(100, len(data)))
        flipped[pos] ^= 1 << int(rng.integers(0, 8))
        f = tmp_path / f"flip{i}.sqlite"
        f.write_bytes(bytes(flipped))
        for argv in (
            ["lookup", "--db", str(f), "--target", "9", "2", "--no-fallback", "--json"],
            ["info", "--db", str(f)],
        ):
            rc, out, err = run(capsys, "launcher", *argv)
            assert "Traceback" not in err and rc in (0, 2), (pos, err)
            if rc == 2:
                _one_line_error(rc, err)
                outcomes["error"] += 1
            else:
                outcomes["ok"] += 1
                if argv[0] == "lookup":
                    d = json.loads(out)
                    assert 0 <= d["miss_mm"] < 1000 and d["settings"]["speed_kmh"] in (90.0, 100.0, 110.0)
    assert outcomes["error"] >= 1  # structural flips are caught by quick_check


def test_quick_check_failure_names_the_damage(built, tmp_path, capsys):
    src = sqlite3.connect(built)
    f = tmp_path / "broken.sqlite"
    dst = sqlite3.connect(f)
    src.backup(dst)
    src.close()
    dst.close()
    data = bytearray(f.read_bytes())
    page = int.from_bytes(data[16:18], "big")
    for p in range(2, len(data) // page):  # scramble the b-tree header of every other page
        if p % 2 == 0:
            data[(p - 1) * page] = 0x99
    f.write_bytes(bytes(data))
    rc, out, err = run(capsys, "launcher", "lookup", "--db", str(f), "--target", "9", "2")
    _one_line_error(rc, err)
    assert "damaged" in err or "not a usable" in err
