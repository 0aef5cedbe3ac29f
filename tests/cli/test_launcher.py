"""`tennislab launcher` and `tennislab material`: JSON contracts, physics flags, exit codes (issue 5)."""

import csv
import json
import math

import pytest

from tennislab.cli import main
from tennislab.launcher.materials import SEED_TABLE1, SEED_TABLE3


def run(capsys, *args):
    try:
        rc = main([str(a) for a in args])
    except SystemExit as exc:  # argparse: usage errors (code 2), --help (0)
        rc = exc.code
    out = capsys.readouterr()
    return rc, out.out, out.err


def test_aim_json_contract(capsys, tmp_path):
    png = tmp_path / "aim.png"
    rc, out, _ = run(
        capsys,
        "launcher",
        "aim",
        "--target",
        8,
        2,
        "--speed-kmh",
        80,
        "--spin-rpm",
        1500,
        "--spin-axis-deg",
        0,
        "--height",
        1.2,
        "--json",
        "--plot",
        png,
    )
    assert d_exact_keys_present(out)
    assert rc == 0 and png.stat().st_size > 10_000
    d = json.loads(out)
    s = d["settings"]
    assert s["height_m"] == 1.2 and abs(s["speed_kmh"] - 80) <= 3
    assert d["tolerances"]["spin_axis_deg"] == 10  # the default: the axis may turn by 10 deg at 1500 +- 100 rpm
    assert abs(s["spin_rpm"] - 1500) <= 100 and abs(s["spin_axis_deg"]) <= 10
    assert d["asked"] == {"height_m": 1.2, "speed_kmh": 80, "spin_rpm": 1500, "spin_axis_deg": 0}
    assert isinstance(s["elevation_deg"], float) and isinstance(s["heading_deg"], float)
    assert d["rollers"]["rpm1"] < d["rollers"]["rpm2"]
    assert math.hypot(d["landing"]["x"] - 8, d["landing"]["y"] - 2) * 1e3 == pytest.approx(d["miss_mm"], abs=1e-6)
    assert d["net_clearance_m"] > 0 and d["solution"] == "low"
    assert d["other_solution"]["solution"] == "high" and d["other_solution"]["elevation_deg"] > 45


def d_exact_keys_present(out):
    d = json.loads(out)
    return {"tolerances", "preferences", "deviation", "asked", "trajectory", "other_solution"} <= set(d)


def test_aim_exact_tolerances_keep_the_asked_settings(capsys):
    rc, out, _ = run(
        capsys,
        "launcher",
        "aim",
        "--target",
        8,
        2,
        "--speed-kmh",
        80,
        "--spin-rpm",
        1500,
        "--speed-tolerance-kmh",
        0,
        "--spin-tolerance-rpm",
        0,
        "--spin-axis-tolerance-deg",
        0,
        "--json",
    )
    s = json.loads(out)["settings"]
    assert rc == 0 and (s["speed_kmh"], s["spin_rpm"], s["spin_axis_deg"]) == (80, 1500, 0)


def test_aim_speed_units_and_named_axis(capsys):
    outs = []
    for args in (
        ["--speed-kmh", 90, "--spin-axis-deg", 180],
        ["--speed-ms", 25, "--spin-axis", "slice"],
        ["--speed-mph", 90 / 1.609344, "--spin-axis", "backspin"],
    ):
        rc, out, err = run(capsys, "launcher", "aim", "--target", 9, -2, "--spin-rpm", 1000, *args, "--json")
        assert rc == 0, err
        outs.append(json.loads(out)["settings"])
    assert outs[0] == outs[1] == outs[2]


def test_aim_text_names_the_changes(capsys):
    rc, out, _ = run(capsys, "launcher", "aim", "--target", 9, 2, "--speed-kmh", 80, "--spin-rpm", 1500)
    assert rc == 0 and "from what was asked: speed" in out and "apex" in out


def test_help_names_the_paper(capsys):
    from tennislab.cli import build_parser

    text = build_parser()._subparsers._group_actions[0].choices["launcher"].format_help()
    assert "Wójcicki, Puciłowski & Kulesza 2010" in text and "seed 002" not in text


def test_aim_high_machine_position_and_physics_flags(capsys):
    rc, out, _ = run(
        capsys,
        "launcher",
        "aim",
        "--target",
        9,
        0,
        "--speed-kmh",
        90,
        "--solution",
        "high",
        "--machine-position",
        -12,
        1,
        "--aero",
        "cross2014",
        "--mass",
        0.057,
        "--radius",
        0.033,
        "--air-density",
        1.1,
        "--gravity",
        9.81,
        "--wind",
        1,
        0,
        0,
        "--json",
    )
    assert rc == 0
    d = json.loads(out)
    assert d["solution"] == "high" and d["settings"]["elevation_deg"] > 45
    assert d["machine"]["position"] == [-12, 1]
    given = {
        "aero": "cross2014",
        "mass": 0.057,
        "radius": 0.033,
        "air_density": 1.1,
        "gravity": 9.81,
        "wind": [1, 0, 0],
    }
    assert {k: d["physics"][k] for k in given} == given  # (the keys of before; FlightParams.to_dict has every setting)
    assert d["physics"]["aero_options"] == {} and d["physics"]["t_max"] == 20.0


def test_aim_text_output(capsys):
    rc, out, _ = run(capsys, "launcher", "aim", "--target", 8, 0, "--speed-kmh", 80)
    assert rc == 0 and "low solution" in out and "rollers:" in out and "miss" in out


@pytest.mark.parametrize(
    "args,frag",
    [
        (["launcher", "aim", "--target", 11.5, 0, "--speed-kmh", 30], "beyond its reach"),
        (
            ["launcher", "aim", "--target", 8, 0, "--speed-kmh", 201],
            "--speed-kmh: 201 km/h is outside the allowed range [30, 200] km/h",
        ),
        (
            ["launcher", "aim", "--target", 8, 0, "--speed-kmh", 80, "--height", 3.5],
            "height_m: 3.5 m is outside the allowed range [0.1, 3] m",
        ),
        (["launcher", "aim", "--target", 8, 0, "--speed-kmh", 80, "--spin-axis-deg", 200], "--spin-axis-deg: 200 deg"),
        (["launcher", "aim", "--target", 3, 0, "--speed-kmh", 200], "into the net"),
        (
            ["launcher", "rollers", "--speed-kmh", 250],
            "--speed-kmh: 250 km/h is outside the allowed range [30, 200] km/h",
        ),
        (["launcher", "rollers", "--speed-kmh", 100, "--spin-rpm", 2500], "--spin-rpm: 2500 rpm"),
        (["launcher", "rollers", "--speed-kmh", 100, "--roller-axis-distance", 0.3], "--roller-axis-distance"),
        (["launcher", "power", "--speed-kmh", 100, "--roller-mass", -1], "--roller-mass"),
        (["launcher", "power", "--speed-kmh", 100, "--motor-power", 0], "--motor-power"),
        (["launcher", "aim", "--target", 8, 0, "--speed-kmh", 80, "--aero", "nope"], "aero"),
        (
            ["launcher", "aim", "--target", 8, 0, "--speed-kmh", 80, "--speed-tolerance-kmh", -1],
            "--speed-tolerance-kmh: -1",
        ),
        (
            ["launcher", "aim", "--target", 8, 0, "--speed-kmh", 80, "--spin-tolerance-rpm", -5],
            "--spin-tolerance-rpm: -5",
        ),
        (
            ["launcher", "aim", "--target", 9, 2, "--speed-kmh", 80, "--max-apex-m", 1.5],
            "--max-apex-m: the low flights",
        ),
        (["launcher", "aim", "--target", 9, 2, "--speed-kmh", 80, "--net-clearance-m", 3, 2], "--net-clearance-m: MIN"),
        (["launcher", "aim", "--target", 9, 2, "--speed-ms", 70], "--speed-ms: 70 m/s is outside"),
        (
            ["launcher", "aim", "--target", 9, 2, "--speed-kmh", 80, "--spin-axis", "wobble"],
            "--spin-axis: unknown axis",
        ),
        (
            ["launcher", "aim", "--target", 9, 2, "--speed-kmh", 80, "--solution", "high", "--trajectory", "low"],
            "--trajectory",
        ),
        (["launcher", "drill", "no_such_drill"], "--drill: 'no_such_drill' is not a file"),
        (["launcher", "rollers", "--speed-ms", 100], "--speed-ms: 100 m/s"),
        (
            ["launcher", "aim", "--target", 9, 2, "--speed-kmh", 80, "--plot", "x.xyz"],
            "--plot: x.xyz: unsupported file type",
        ),
        (["launcher", "drill", "lobs", "--csv", "/dev/null/x.csv"], "--csv: /dev/null/x.csv: /dev/null is a file"),
        (["launcher", "drill", "lobs", "--csv", "x" * 300 + ".csv"], "--csv: the file name is 304 characters"),
    ],
)
def test_bad_input_exit_2_one_line(capsys, args, frag):
    rc, out, err = run(capsys, *args)
    assert rc == 2 and frag in err and err.count("\n") == 1 and "Traceback" not in err


def test_rollers_json(capsys):
    rc, out, _ = run(capsys, "launcher", "rollers", "--speed-kmh", 200, "--spin-rpm", 2000, "--json")
    d = json.loads(out)
    assert rc == 0 and d["rpm1"] == pytest.approx(4805, abs=1) and d["rpm2"] == pytest.approx(5805, abs=1)
    assert d["grab_angle_deg"] == pytest.approx(20.56, abs=0.01) and d["pulls_in"] is True
    rc, out, _ = run(capsys, "launcher", "rollers", "--speed-kmh", 100, "--friction", 0.3, "--json")
    assert json.loads(out)["pulls_in"] is False


def test_power_json(capsys):
    rc, out, _ = run(capsys, "launcher", "power", "--speed-kmh", 200, "--json")
    d = json.loads(out)
    assert rc == 0 and d["throw_power_w"] == pytest.approx(44.5, abs=0.1)
    assert d["startup_time_s"] == pytest.approx(35.3, abs=0.1) and d["energy_per_throw_j"] == pytest.approx(
        89.0, abs=0.1
    )
    rc, out, _ = run(
        capsys,
        "launcher",
        "power",
        "--speed-kmh",
        200,
        "--roller-mass",
        4,
        "--motor-power",
        90,
        "--throw-time",
        2,
        "--slip",
        "--json",
    )
    d2 = json.loads(out)
    assert d2["energy_per_throw_j"] == pytest.approx(2 * d["energy_per_throw_j"])
    assert d2["throw_power_w"] == pytest.approx(d["throw_power_w"])


def test_drill_cli(capsys, tmp_path):
    out_csv, png = tmp_path / "d.csv", tmp_path / "d.png"
    rc, out, _ = run(capsys, "launcher", "drill", "lobs", "--json", "--csv", out_csv, "--plot", png)
    assert rc == 0 and png.stat().st_size > 10_000
    d = json.loads(out)
    rows = list(csv.DictReader(out_csv.open()))
    assert d["ok"] and len(rows) == d["n_shots"] == 10
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: x\nshots: {a: {target: [8, 0], speed_kmh: 500}}\nprogram: [{shot: a}]\n")
    rc, out, err = run(capsys, "launcher", "drill", bad, "--csv", tmp_path / "never.csv")
    assert rc == 2 and "shots.a.speed_kmh: 500 km/h is outside the allowed range [30, 200] km/h" in err
    assert not (tmp_path / "never.csv").exists()


def test_drill_failed_check_exit_1(capsys, tmp_path):
    f = tmp_path / "tight.yaml"  # a 10 cm zone cannot be hit at the machine's 1-degree steps
    f.write_text(
        "name: tight\nshots: {a: {type: drive, target: [9.0, 0.3], zone: [8.995, 9.005, 0.295, 0.305],\n"
        "  speed_tolerance_kmh: 0, spin_tolerance_rpm: 0}}\nprogram: [{shot: a}]\n"
    )
    rc, out, _ = run(capsys, "launcher", "drill", f)
    assert rc == 1 and "FAILED" in out
    rc, out, _ = run(capsys, "launcher", "drill", f, "--no-check", "--json")
    assert rc == 0 and json.loads(out)["ok"] is False


def test_material_cli(capsys, tmp_path):
    y = tmp_path / "y.csv"
    y.write_text("load_kg,deformation_m\n" + "".join(f"{kg},{dl}\n" for kg, dl, _ in SEED_TABLE1))
    rc, out, _ = run(capsys, "material", "young", "--csv", y, "--json")
    d = json.loads(out)
    assert rc == 0 and len(d["rows"]) == 10 and d["mean_mpa"] == pytest.approx(3.59, abs=0.01)
    assert d["rows"][0]["young_modulus_mpa"] == pytest.approx(3.39, abs=0.01)
    f = tmp_path / "f.csv"
    f.write_text("contact_length_m,friction_angle_deg\n" + "".join(f"{c},{a}\n" for c, a, _ in SEED_TABLE3["roller"]))
    rc, out, _ = run(capsys, "material", "friction", "--csv", f, "--json")
    d = json.loads(out)
    assert rc == 0 and d["max"] == pytest.approx(2.05, abs=0.001) and d["rows"][0]["contact_length_m"] == 0.005
    rc, out, _ = run(capsys, "material", "friction", "--csv", f)
    assert rc == 0 and "mean mu" in out
    f.write_text("angle\n30\n")
    rc, out, err = run(capsys, "material", "friction", "--csv", f)
    assert rc == 2 and "missing column friction_angle_deg" in err
    rc, out, err = run(capsys, "material", "young", "--csv", tmp_path / "nope.csv")
    assert rc == 2
    rc, out, err = run(capsys, "material", "young", "--csv", y, "--diameter", "nan")
    assert rc == 2 and "--diameter" in err and err.count("\n") == 1
    y.write_bytes(b"load_kg,deformation_m\n\xff\xfe,1\n")
    rc, out, err = run(capsys, "material", "young", "--csv", y)
    assert rc == 2 and "UTF-8" in err and err.count("\n") == 1


@pytest.mark.parametrize("flag", [["--wind", "1", "0", "0"], ["--aero", "cross2014"], ["--mass", "0.058"]])
def test_material_rejects_flags_it_ignores(tmp_path, flag):
    import subprocess
    import sys

    f = tmp_path / "f.csv"
    f.write_text("friction_angle_deg\n30\n")
    p = subprocess.run(
        [sys.executable, "-m", "tennislab", "material", "friction", "--csv", str(f), *flag],
        capture_output=True,
        text=True,
    )
    assert p.returncode == 2 and "unrecognized arguments" in p.stderr and p.stderr.count("\n") == 1


def test_inverse_text_json_and_refusals(capsys):
    """`launcher inverse`: the continuous angles of `launcher.inverse_aim` (text and JSON: its `to_dict()` and
    the physics preset); a target outside the reach, a height or spin outside the machine's range: one line,
    exit 2."""
    from tennislab.launcher import inverse_aim

    rc, out, _ = run(capsys, "launcher", "inverse", "--target", 9, 2, "--speed-kmh", 100, "--spin-rpm", 1000)
    assert rc == 0 and out.startswith("low solution for target (9, 2) m (continuous angles):")
    assert " flights, " in out and " ms (the reach map: " in out and "preset standard" in out
    rc, out, _ = run(
        capsys, "launcher", "inverse", "--target", 9, 2, "--speed-kmh", 100, "--spin-rpm", 1000,
        "--spin-axis", "backspin", "--height", 0.5, "--trajectory", "high", "--json",
    )  # fmt: skip
    d = json.loads(out)
    ref = inverse_aim((9.0, 2.0), 100, 1000, 180.0, 0.5, trajectory="high").to_dict()
    assert rc == 0 and set(d) == set(ref) | {"physics_preset"} and d["solution"] == "high"
    assert d["settings"]["elevation_deg"] == pytest.approx(ref["settings"]["elevation_deg"], abs=1e-9)
    assert d["miss_mm"] < 1.0 and d["flights"] == 4 and d["physics_preset"] == "standard"
    for args, start in (
        (("--target", 30, 2), "tennislab launcher: error: --target: (30, 2) m, 42.43 m from the machine, is outside"),
        (("--target", 9, 2, "--height", 5), "tennislab launcher: error: height_m: 5 m is outside the allowed range"),
        (("--target", 9, 2, "--spin-rpm", 3000), "tennislab launcher: error: --spin-rpm: 3000 rpm is outside"),
    ):
        rc, out, err = run(capsys, "launcher", "inverse", "--speed-kmh", 100, *args)
        assert rc == 2 and out == "" and err.startswith(start) and err.count("\n") == 1, err
