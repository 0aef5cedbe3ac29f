"""`tennislab fly`: the JSON contract and bad input (issue 2)."""

import json
import subprocess
import sys

import pytest

from tennislab.cli import main


def run(capsys, *args):
    rc = main(list(args))
    out = capsys.readouterr()
    return rc, out.out, out.err


def test_fly_json_contract(capsys):
    rc, out, _ = run(
        capsys,
        "fly",
        "--position",
        "-11.885",
        "0",
        "2.8",
        "--velocity",
        "50",
        "0",
        "-3",
        "--spin-rpm",
        "2000",
        "--spin-axis",
        "0",
        "1",
        "0",
        "--json",
    )
    assert rc == 0
    d = json.loads(out)
    for k in ("x", "y", "t"):
        assert isinstance(d["bounce"][k], float)
    assert len(d["bounce"]["velocity"]) == 3
    assert d["net"]["result"] in ("over", "net", "none")
    assert d["net"]["clearance"] == pytest.approx(d["net"]["z"] - 0.914 - 0.0335, abs=1e-9)
    assert d["apex"]["z"] == pytest.approx(2.8)


def test_fly_physics_flags_and_plot(capsys, tmp_path):
    png = tmp_path / "f.png"
    rc, out, _ = run(
        capsys,
        "fly",
        "--position",
        "-11.885",
        "0",
        "1",
        "--velocity",
        "25",
        "0",
        "6",
        "--aero",
        "constant",
        "--cd",
        "0.6",
        "--mass",
        "0.059",
        "--radius",
        "0.033",
        "--air-density",
        "1.22",
        "--gravity",
        "9.82",
        "--wind",
        "1",
        "0",
        "0",
        "--plot",
        str(png),
        "--json",
    )
    assert rc == 0 and png.stat().st_size > 10_000
    d = json.loads(out)
    assert d["physics"]["mass"] == 0.059 and d["physics"]["gravity"] == 9.82


def test_fly_human_summary(capsys):
    rc, out, _ = run(capsys, "fly", "--position", "-11.885", "0", "1", "--velocity", "25", "0", "6")
    assert rc == 0 and "landing" in out and "net" in out


@pytest.mark.parametrize(
    "args,needle",
    [
        (["--mass", "-1"], "mass"),
        (["--aero", "nosuchmodel"], "unknown model"),
        (["--radius", "nan"], "radius"),
        (["--spin-rpm", "100"], "--spin-axis"),
        (["--air-density", "5"], "--air-density"),
    ],
)
def test_fly_bad_input_one_line_exit_2(capsys, args, needle):
    rc, out, err = run(capsys, "fly", "--position", "-11.885", "0", "1", "--velocity", "25", "0", "6", *args)
    assert rc == 2
    assert needle in err and err.count("\n") == 1 and "Traceback" not in err


def test_fly_nan_velocity_subprocess():
    p = subprocess.run(
        [sys.executable, "-m", "tennislab", "fly", "--position", "-11", "0", "1", "--velocity", "nan", "0", "1"],
        capture_output=True,
        text=True,
    )
    assert p.returncode == 2
    assert "velocity[0]" in p.stderr and "Traceback" not in p.stderr
    assert p.stderr.count("\n") == 1


def test_fly_below_ground_is_an_error(capsys):
    rc, _, err = run(capsys, "fly", "--position", "0", "0", "0.01", "--velocity", "1", "0", "0")
    assert rc == 2 and "radius" in err
