"""``tennislab calibrate``: sub-commands, JSON keys, the written aero table, bad input (exit 2, one line)."""

import json

import numpy as np
import pytest

from tennislab.calibrate import SpinAxis, serves_csv, synthetic_serves
from tennislab.cli import main
from tennislab.core.flight import FlightParams, fly_dense
from tennislab.io.track import track_to_csv


@pytest.fixture(scope="module")
def serves_file(tmp_path_factory):
    truth = FlightParams.from_options(aero="cross2014", cd=0.66, cl=0.45)
    s = synthetic_serves(120, truth, SpinAxis.angle(60.0), seed=5)
    p = tmp_path_factory.mktemp("cv") / "serves.csv"
    p.write_text(serves_csv(s))
    return str(p)


def run(capsys, *args):
    rc = main(list(args))
    out = capsys.readouterr()
    return rc, out.out, out.err


def test_validate_json(capsys, serves_file, tmp_path):
    csv_path = tmp_path / "rows.csv"
    rc, out, err = run(
        capsys,
        "calibrate",
        "validate",
        "--serves",
        serves_file,
        "--models",
        "cross2014",
        "--csv",
        str(csv_path),
        "--json",
    )
    assert rc == 0, err
    d = json.loads(out)
    for k in ("n_read", "n_used", "excluded", "spin_axis", "split", "models", "conventions", "physics"):
        assert k in d
    m = d["models"][0]
    assert m["model"] == "cross2014" and {"overall", "fit", "held_out", "groups"} <= set(m)
    assert csv_path.read_text().startswith("model,match,point_ID")


def test_serves_writes_a_table_every_command_reads(capsys, serves_file, tmp_path):
    table = tmp_path / "aero.csv"
    rc, out, err = run(
        capsys,
        "calibrate",
        "serves",
        "--serves",
        serves_file,
        "--cl",
        "0.45",
        "--out-table",
        str(table),
        "--json",
        "--quiet",
    )
    assert rc == 0, err
    assert err == ""
    d = json.loads(out)
    assert d["values"]["cd"] == pytest.approx(0.66, abs=0.01)
    assert d["free"] == ["cd"] and d["sd"]["cd"] > 0
    assert d["after"]["held_out"]["miss_median_m"] < 0.01
    rc, out, err = run(
        capsys,
        "fly",
        "--position",
        "-11.5",
        "0",
        "2.8",
        "--velocity",
        "50",
        "0",
        "-3",
        "--aero",
        "table",
        "--aero-table",
        str(table),
        "--json",
    )
    assert rc == 0, err
    assert json.loads(out)["bounce"]["x"] > 0


def test_sensitivity_and_text_output(capsys, serves_file):
    rc, out, err = run(
        capsys,
        "calibrate",
        "sensitivity",
        "--serves",
        serves_file,
        "--cd",
        "0.6,0.66",
        "--cl",
        "0.45",
        "--spin-axes",
        "60",
    )
    assert rc == 0, err
    assert "cd 0.66 cl 0.45 60" in out and "[2/2]" in err


def test_tracks_command(capsys, tmp_path):
    truth = FlightParams.from_options(aero="constant", cd=0.58, cl=0.0)
    files = []
    for i, (vx, vz) in enumerate(((30.0, 4.0), (22.0, 6.0), (40.0, 1.0))):
        tr = fly_dense((-11.5, 0.0, 1.0), (vx, 0.0, vz), (0.0, 0.0, 0.0), truth)
        t = np.arange(0.0, 0.9 * tr.landing.t, 0.01)
        p = tmp_path / f"t{i}.csv"
        p.write_text(track_to_csv(t, tr.sol(t).T[:, :3]))
        files.append(str(p))
    rc, out, err = run(capsys, "calibrate", "tracks", *files, "--fit", "cd", "--json", "--quiet")
    assert rc == 0, err
    d = json.loads(out)
    assert d["values"]["cd"] == pytest.approx(0.58, abs=2e-3) and d["free"] == ["cd"] and d["model"] == "family"


def _track_files(tmp_path, n=4):
    truth = FlightParams.from_options(aero="cross2014", cd=0.62, cl=0.6, spin_decay=0.5)
    files = []
    for i in range(n):
        vx, vz, w = 20.0 + 6 * i, 6.0 - i, (0.0, (-1) ** i * 250.0, 0.0)
        tr = fly_dense((-11.5, 0.3 * i, 1.0), (vx, 0.0, vz), w, truth)
        t = np.arange(0.0, 0.95 * tr.landing.t, 0.02)
        p = tmp_path / f"t{i}.csv"
        p.write_text(track_to_csv(t, tr.sol(t).T[:, :3]))
        files.append(str(p))
    return files


@pytest.mark.slow
def test_tracks_curves_command(capsys, tmp_path):
    """The default fit identifies the curves: the held-out (even-numbered) tracks, the table and a
    tennislab.toml that flies it."""
    files = _track_files(tmp_path)
    table, conf = tmp_path / "aero.csv", tmp_path / "tennislab.toml"
    args = ("calibrate", "tracks", *files, "--speed-knots", "15,30", "--s-knots", "0.2,0.4", "--max-iter", "2")
    rc, out, err = run(capsys, *args, "--out-table", str(table), "--out-config", str(conf), "--quiet")
    assert rc == 0, err
    assert "identified on 2 flights, 2 held out" in out and "held out all" in out and "cubic floor" in out
    assert f"--aero table --aero-table {table} --spin-decay" in out
    rc, out, err = run(capsys, *args, "--json", "--quiet")
    d = json.loads(out)
    assert d["model"] == "curves" and d["split"]["n_held_out"] == 2 and set(d["values"]) >= {"cd@15", "decay"}
    assert d["held_out"]["all"]["after"]["median_mm"] is not None
    rc, out, err = run(capsys, "--config", str(conf), "fly", "--speed-kmh", "90", "--elevation-deg", "8", "--json")
    assert rc == 0, err
    assert json.loads(out)["physics"]["aero"] == "table"


@pytest.mark.parametrize(
    "args,msg",
    [
        (("validate", "--serves", "{f}", "--split", "tour:itf"), "--split: no serve has tour"),
        (("validate", "--serves", "{f}", "--models", "magic"), "aero: unknown model"),
        (("validate", "--serves", "{f}", "--spin-axis", "wobble"), "--spin-axis: unknown axis"),
        (("serves", "--serves", "{f}", "--fit", "cd,cl"), "--fit: cl and a fitted spin axis"),
        (("serves", "--serves", "{f}", "--fit", "drag"), "--fit: unknown parameter"),
        (("serves", "--serves", "{bad}"), "missing column"),
        (("serves", "--serves", "{nan}"), "missing value"),
        (("serves", "--serves", "/nonexistent/s.csv"), "no such file"),
        (("sensitivity", "--serves", "{f}", "--cd", "a,b"), "--cd: expected comma-separated numbers"),
        (("tracks", "{bad}"), "missing column"),
        (("tracks", "{track}", "--split", "random"), "--split: unknown split"),
        (("tracks", "{track}", "--fit", "cd_v,wobble"), "--fit: unknown parameter"),
        (("tracks", "{track}", "--drag-sigma", "-1"), "--drag-sigma:"),
        (("tracks", "{track}", "--speed-knots", "30,20"), "cd: knots must be"),
        (("tracks", "{track}", "--out-config", "{dir}/c.toml"), "--out-config: needs --out-table"),
        (("tracks", "{points}"), "points: no hit-to-bounce flight"),
        (("validate", "--serves", "{same}"), "--serves: no serves left after the checks"),
    ],
)
def test_bad_input_exit_2_one_line(capsys, serves_file, tmp_path, args, msg):
    bad = tmp_path / "bad.csv"
    bad.write_text("match,point_ID\nx,y\n")
    nan = tmp_path / "nan.csv"
    lines = open(serves_file).read().splitlines()
    cols = lines[1].split(",")
    cols[3] = "NA"
    nan.write_text("\n".join([lines[0], ",".join(cols)]) + "\n")
    same = tmp_path / "same.csv"
    cols = lines[1].split(",")
    head = lines[0].split(",")
    i = head.index("x_serve_bounce")
    cols[i] = str(-float(cols[i]))
    same.write_text("\n".join([lines[0], ",".join(cols)]) + "\n")
    track = tmp_path / "track.csv"
    t = np.arange(0.0, 0.5, 0.02)
    track.write_text(track_to_csv(t, np.stack([-11 + 25 * t, 0 * t, 1 + 3 * t - 4.9 * t**2], axis=1)))
    points = tmp_path / "points.json"
    points.write_text(json.dumps({"samples": [{"time": 0.0, "event": "hit", "ball": [0, 0, 1]}]}))
    fmt = {"f": serves_file, "bad": bad, "nan": nan, "same": same, "track": track, "points": points, "dir": tmp_path}
    argv = [a.format(**fmt) for a in args]
    rc, out, err = run(capsys, "calibrate", *argv, "--quiet")
    assert rc == 2
    assert msg in err
    assert len(err.strip().splitlines()) == 1
    assert len(err.strip().splitlines()) == 1
