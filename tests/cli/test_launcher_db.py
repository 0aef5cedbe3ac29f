"""``tennislab launcher table | lookup | drills``: contract keys, agreement with ``aim``, one-line errors."""

from __future__ import annotations

import json
import sqlite3

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
        "--json",
    )
    assert rc == 0, err
    d = json.loads(out)
    for k in AIM_KEYS + ("lookup_ms",):
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
        ["--db", built, "--target", "8", "1", "--speed-kmh", "150"],
        ["--db", built, "--target", "8", "1", "--speed-kmh", "250"],
        ["--db", built, "--target", "0.2", "0", "--speed-kmh", "110", "--max-miss-m", "0.05"],
    ]
    for argv in cases:
        rc, out, err = run(capsys, "launcher", "lookup", *argv)
        _one_line_error(rc, err)
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
    d = json.loads(out)["drills"]
    assert [(x["name"], x["revision"], x["n_shots"]) for x in d] == [("cli-drill", 1, 2)]
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
