"""`tennislab fly`: the JSON contract and bad input (issue 2)."""

import json
import os
import stat
import subprocess
import sys

import pytest

from tennislab.cli import main


def run(capsys, *args):
    try:
        rc = main(list(args))
    except SystemExit as exc:  # argparse's own errors (a bad --plot path is refused while parsing)
        rc = exc.code
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


# ------------------------------------------------------------------ one vocabulary (issue 17)
def fly_json(capsys, *args):
    rc, out, err = run(capsys, "fly", *args, "--json")
    assert rc == 0, err
    return json.loads(out)


def test_speed_elevation_heading_equal_the_velocity_vector(capsys):
    import math

    speed, el, hd = 30.0, 12.0, -4.0
    v = [
        speed * math.cos(math.radians(el)) * math.cos(math.radians(hd)),
        speed * math.cos(math.radians(el)) * math.sin(math.radians(hd)),
        speed * math.sin(math.radians(el)),
    ]
    a = fly_json(capsys, "--velocity", *map(str, v))
    b = fly_json(capsys, "--speed-ms", "30", "--elevation-deg", "12", "--heading-deg", "-4")
    c = fly_json(capsys, "--speed-kmh", "108", "--elevation-deg", "12", "--heading-deg", "-4")
    d = fly_json(capsys, "--speed-mph", str(30 / 0.44704), "--elevation-deg", "12", "--heading-deg", "-4")
    for other in (b, c, d):
        assert other["landing"]["x"] == pytest.approx(a["landing"]["x"], abs=1e-9)
        assert other["landing"]["y"] == pytest.approx(a["landing"]["y"], abs=1e-9)
    assert b["launch"]["speed_kmh"] == pytest.approx(108.0)
    assert b["launch"]["elevation_deg"] == pytest.approx(12.0) and b["launch"]["heading_deg"] == pytest.approx(-4.0)


@pytest.mark.parametrize(
    "name,vector",
    [
        ("topspin", (0, 1, 0)),
        ("backspin", (0, -1, 0)),
        ("slice", (0, -1, 0)),
        ("sidespin-left", (0, 0, 1)),
        ("sidespin", (0, 0, 1)),
        ("sidespin-right", (0, 0, -1)),
        ("0", (0, 1, 0)),
        ("180", (0, -1, 0)),
    ],
)
def test_named_spin_axes_equal_their_vectors(capsys, name, vector):
    """For a flat launch along +x the named axes are the conventions' vectors (docs/conventions.md)."""
    base = ["--speed-kmh", "100", "--elevation-deg", "0", "--position", "-11.885", "0", "1.2", "--spin-rpm", "2000"]
    base += ["--net", "through"]  # (some of these balls drop into the net: compare where they would land)
    a = fly_json(capsys, *base, "--spin-axis", name)
    b = fly_json(capsys, *base, "--spin-axis", *map(str, vector))
    assert a["launch"]["spin"] == pytest.approx(b["launch"]["spin"], abs=1e-9)
    assert a["landing"]["x"] == pytest.approx(b["landing"]["x"], abs=1e-9)
    assert a["launch"]["spin_rpm"] == pytest.approx(2000.0)


def test_json_keys_launch_landing_bounce_caveats(capsys):
    d = fly_json(capsys, "--speed-kmh", "120", "--elevation-deg", "6", "--spin-rpm", "2500", "--spin-axis", "topspin")
    assert d["bounce"] == d["landing"]  # the contract key stays beside the new name
    assert set(d["launch"]) >= {
        "position",
        "velocity",
        "spin",
        "speed_ms",
        "speed_kmh",
        "elevation_deg",
        "heading_deg",
        "spin_rpm",
        "spin_axis_deg",
    }
    assert d["launch"]["position"] == [-11.885, 0.0, 1.0]  # the default position
    assert d["launch"]["spin_axis_deg"] == pytest.approx(0.0, abs=1e-9)
    assert d["caveats"] == []


def test_a_ball_into_the_net_says_so(capsys):
    rc, out, _ = run(capsys, "fly", "--speed-ms", "20", "--elevation-deg", "6")
    assert rc == 0 and "net: STOPPED BY THE NET (mesh)" in out and "note: The ball hits the net" in out
    assert "landing:" not in out
    d = fly_json(capsys, "--speed-ms", "20", "--elevation-deg", "6")
    assert d["net"]["result"] == "net" and "hits the net" in d["caveats"][0]
    assert d["landing"] is None and d["bounce"] is None and d["net_contact"]["part"] == "mesh"
    rc, out, _ = run(capsys, "fly", "--speed-ms", "20", "--elevation-deg", "6", "--net", "through")
    assert rc == 0 and "net: HITS THE NET" in out and "landing:" in out


# ------------------------------------------------------------------ guard rails (issues 16, 17)
@pytest.mark.parametrize(
    "args,expect",
    [
        (["--velocity", "1e9", "0", "7"], "--velocity: |v| = 1e+09 m/s is outside the allowed range [0, 100] m/s"),
        (["--velocity", "1e160", "0", "0"], "--velocity: |v| = 1e+160 m/s is outside the allowed range"),
        (["--speed-kmh", "400", "--elevation-deg", "5"], "--speed-kmh: 400 km/h is outside the allowed range [0, 360]"),
        (
            ["--speed-mph", "250", "--elevation-deg", "5"],
            "--speed-mph: 250 mph is outside the allowed range [0, 223.7]",
        ),
        (["--speed-ms", "-3", "--elevation-deg", "5"], "--speed-ms: -3 m/s is outside the allowed range [0, 100]"),
        (["--speed-ms", "30", "--elevation-deg", "95"], "--elevation-deg: 95 deg is outside the allowed range"),
        (
            ["--velocity", "30", "0", "5", "--spin-rpm", "20000", "--spin-axis", "topspin"],
            "--spin-rpm: 20000 rpm is outside the allowed range [0, 10000] rpm",
        ),
        (["--velocity", "30", "0", "5", "--spin", "0", "2000", "0"], "--spin: |omega| = 2000 rad/s (19099 rpm)"),
        (
            ["--position", "0", "0", "-1", "--velocity", "30", "0", "5"],
            ("--position z: -1 m is below the ball radius", "--position: z = -1 m is outside the allowed range"),
        ),
        (["--position", "1e6", "0", "1", "--velocity", "30", "0", "5"], "--position[0]: 1e+06 m is outside"),
        (["--speed-kmh", "100"], "--elevation-deg: give the launch elevation [deg] with --speed-kmh"),
        (["--elevation-deg", "5"], "--elevation-deg: give a velocity vector, or a speed with an elevation"),
        ([], "--velocity: give a velocity vector, or a speed with an elevation [deg]"),
        (["--velocity", "30", "0", "5", "--speed-kmh", "100"], "--speed-kmh: give either a velocity vector"),
        (["--velocity", "30", "0", "5", "--heading-deg", "3"], "--heading-deg: give either a velocity vector"),
        (["--velocity", "30", "0", "5", "--spin-axis", "topspin"], "--spin-rpm: give --spin-rpm and --spin-axis"),
        (["--velocity", "30", "0", "5", "--spin-rpm", "1", "--spin-axis", "1", "2"], "--spin-axis: expected a name"),
        (["--velocity", "30", "0", "5", "--spin-rpm", "1", "--spin-axis", "0", "0", "0"], "zero vector"),
        (
            ["--velocity", "30", "0", "5", "--spin", "0", "1", "0", "--spin-rpm", "3", "--spin-axis", "topspin"],
            "--spin: give either a spin vector or --spin-rpm with --spin-axis",
        ),
        (["--velocity", "30", "0", "5", "--surface", "clay"], "--surface: the surface is used only for bounces"),
    ],
)
def test_absurd_or_ignored_inputs_are_refused_with_the_range(capsys, args, expect):
    rc, out, err = run(capsys, "fly", *args)
    assert rc == 2 and out == ""
    assert err.count("\n") == 1 and "Traceback" not in err
    alternatives = expect if isinstance(expect, tuple) else (expect,)  # core's wording or the workflow's
    assert err.startswith("tennislab fly: error: ") and any(e in err for e in alternatives), err


# ------------------------------------------------------------------ output files (issue 16)
FAST = ["fly", "--velocity", "30", "0", "5"]


@pytest.mark.parametrize(
    "make,expect",
    [
        (lambda d: d / "x.xyz", "unsupported file type ('.xyz')"),
        (lambda d: d / "file" / "x.png", "is a file, not a directory"),
        (lambda d: d / "nodir" / "x.png", "does not exist"),
        (lambda d: d / ("n" * 300 + ".png"), "characters long (limit"),
        (lambda d: d, "is a directory"),
    ],
)
def test_bad_plot_paths_fail_before_the_work_and_write_nothing(tmp_path, capsys, make, expect):
    (tmp_path / "file").write_text("mine")
    rc, out, err = run(capsys, *FAST, "--plot", str(make(tmp_path)))
    assert rc == 2 and out == "" and err.count("\n") == 1 and ": error: --plot: " in err and expect in err, err
    assert sorted(os.listdir(tmp_path)) == ["file"] and (tmp_path / "file").read_text() == "mine"


@pytest.mark.parametrize("ext", [".png", ".pdf", ".svg"])
def test_plots_are_written_with_the_users_umask(tmp_path, capsys, ext):
    old = os.umask(0o022)
    try:
        out = tmp_path / f"f{ext}"
        rc, _, err = run(capsys, *FAST, "--plot", str(out))
        assert rc == 0, err
        assert stat.S_IMODE(out.stat().st_mode) == 0o644
        assert os.listdir(tmp_path) == [out.name]  # no temporary file left
    finally:
        os.umask(old)


def test_the_help_examples_run(capsys, tmp_path, monkeypatch):
    import shlex

    from tennislab.cli.fly import EXAMPLES

    monkeypatch.chdir(tmp_path)
    lines = " ".join(EXAMPLES.replace("\\\n", " ").splitlines()[1:])
    for cmd in [c for c in lines.split("tennislab ") if c.strip()]:
        rc, _, err = run(capsys, *shlex.split(cmd))
        assert rc == 0, (cmd, err)
    assert (tmp_path / "fly.png").stat().st_size > 10_000


def test_every_accepted_figure_type_is_written(tmp_path):
    """--plot accepts exactly the formats Matplotlib writes without LaTeX or optional codecs."""
    import matplotlib.pyplot as plt
    from matplotlib.backend_bases import FigureCanvasBase

    from tennislab.plot.save import FIGURE_SUFFIXES, save_figure

    supported = FigureCanvasBase.get_supported_filetypes()
    fig, ax = plt.subplots(figsize=(2, 2))
    ax.plot([0, 1], [0, 1])
    try:
        for ext in FIGURE_SUFFIXES:
            assert ext[1:] in supported, ext
            save_figure(fig, str(tmp_path / f"f{ext}"))
            assert (tmp_path / f"f{ext}").stat().st_size > 100
    finally:
        plt.close(fig)


def test_library_parameter_names_become_the_commands_flags():
    from tennislab.cli import flag_message

    opts = {"--spin-rpm", "--spin-axis", "--speed-kmh", "--velocity"}
    assert flag_message("spin_axis: give spin_rpm and spin_axis together", opts) == (
        "--spin-axis: give --spin-rpm and --spin-axis together"
    )
    assert flag_message("speed_kmh: 400 km/h is outside", opts) == "--speed-kmh: 400 km/h is outside"
    assert flag_message("velocity[0]: must be finite", opts) == "--velocity[0]: must be finite"
    # the library's advice to set a parameter is said with the command's flag; Python users read the keyword
    assert flag_message('cl: computes C_L from spin; use aero="constant" to set it', opts | {"--aero", "--cl"}) == (
        "--cl: computes C_L from spin; use --aero constant to set it"
    )
    assert flag_message('wind: still air; use method="numeric"', opts) == 'wind: still air; use method="numeric"'
    # names the command has no flag for, paths and dotted keys stay as they are
    assert flag_message("mass: see my_file.csv and physics.spin_rpm", opts) == (
        "mass: see my_file.csv and physics.spin_rpm"
    )


def test_an_os_error_is_one_line(capsys, monkeypatch):
    from tennislab.cli import fly as fly_cli

    def full(*a, **k):
        raise OSError(28, "No space left on device", "/tmp/x.png")

    monkeypatch.setattr(fly_cli, "save_figure", full)
    rc, out, err = run(capsys, "fly", "--velocity", "30", "0", "5", "--plot", "x.png")
    assert rc == 2 and err == "tennislab fly: error: /tmp/x.png: No space left on device\n"
