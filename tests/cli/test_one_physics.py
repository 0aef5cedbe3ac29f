"""One default physics for every command: fly, call, serve, serve-window and serve-mc fly the same
``standard`` physics unless told otherwise, and ``--preset seed000`` flies the serve paper's constants
(the serve commands' numbers before ``standard`` became their default)."""

import json
import math

import pytest

from tennislab.cli import main
from tennislab.core.flight import FlightParams
from tennislab.serve import seed_flight_params, simulate, window

SERVE = ("--player", "pro", "--impact-angle", "36", "--face-angle", "21")
COMMANDS = {
    "fly": ("fly", "--speed-kmh", "180", "--elevation-deg", "-5"),
    "call": ("call", "--position", "0", "0", "1", "--velocity", "20", "0", "0"),
    "serve": ("serve", *SERVE),
    "serve-window": ("serve-window", "--player", "junior", "--step", "15", "--no-progress"),
    "serve-mc": ("serve-mc", *SERVE, "--n", "200", "--no-progress"),
}


def _json(capsys, *argv) -> dict:
    capsys.readouterr()
    assert main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_every_command_reports_the_same_physics_by_default(capsys):
    """The same aero, ball, air, gravity, wind, spin decay, time limit and court; only the net rule is the
    command's own: fly and call stop a flight at the net, the serve judges the net crossing itself (the
    paper's 2-D test or the real net, ``serve.pipeline.judge``)."""
    physics = {name: _json(capsys, *argv)["physics"] for name, argv in COMMANDS.items()}
    want = json.loads(json.dumps(FlightParams.from_options(preset="standard").to_dict()))
    assert want["aero"] == "choppin2018" and want["air_density"] == 1.199 and want["mass"] == 0.0577
    nets = {name: got.pop("net_obstacle") for name, got in physics.items()}
    want.pop("net_obstacle")
    for name, got in physics.items():
        assert got == want, name
    assert nets == {"fly": True, "call": True, "serve": False, "serve-window": False, "serve-mc": False}


def test_the_python_serve_workflows_default_to_the_same_physics():
    res = simulate("pro", 36, 21, advice=False)
    assert res.inputs["aero"] == "choppin2018"
    std = simulate("pro", 36, 21, advice=False, flight=FlightParams.from_options())
    assert res.to_dict() == std.to_dict()


# `serve --player pro --impact-angle 36 --face-angle 21` as the serve commands flew it with the paper's
# constants as their default (docs/serve.md's example then): 46.40 m/s, 5370 rpm, net 0.827 m, X 14.461 m
OLD_SERVE = {
    "speed": 46.39864123120563,
    "spin_rpm": 5369.65944143625,
    "launch_angle": -5.536762299100148,
    "net_height": 0.8273311123043593,
    "landing_x": 14.461316853914804,
}


def test_preset_seed000_reproduces_the_old_serve_numbers(capsys):
    d = _json(capsys, "serve", *SERVE, "--preset", "seed000")
    assert d["physics_preset"] == "seed000" and d["physics"]["aero"] == "stepanek1988"
    for k, v in OLD_SERVE.items():
        assert d[k] == pytest.approx(v, rel=1e-9), k
    py = simulate("pro", 36, 21, advice=False, preset="seed000")
    assert py.to_dict() == simulate("pro", 36, 21, advice=False, flight=seed_flight_params()).to_dict()
    assert py.landing_x == pytest.approx(OLD_SERVE["landing_x"], rel=1e-9)
    # ... and the default flies another ball through other air: the serve lands elsewhere
    std = _json(capsys, "serve", *SERVE)
    assert std["physics_preset"] == "standard" and abs(std["landing_x"] - OLD_SERVE["landing_x"]) > 0.01


def test_preset_seed000_window_and_mc_reproduce_the_old_numbers(capsys):
    # serve-window --player junior --step 3 and serve-mc --player junior --impact-angle 45 --face-angle 10
    # --n 1000 with the paper's constants as the serve commands' old default: 37 in (14 topspin), peak spin
    # at alpha 42; P(in) 0.625, mean X 18.0507 m
    w = _json(capsys, "serve-window", "--player", "junior", "--step", "3", "--preset", "seed000", "--no-progress")
    assert (w["n_success"], w["summary"]["topspin"]["n"], w["peak_spin_alpha"]) == (37, 14, 42.0)
    assert int(window("junior", step=3, preset="seed000").success.sum()) == 37
    argv = ("serve-mc", "--player", "junior", "--impact-angle", "45", "--face-angle", "10", "--n", "1000")
    mc = _json(capsys, *argv, "--preset", "seed000", "--no-progress")
    assert mc["p_success"] == 0.625 and mc["landing_x"]["mean"] == pytest.approx(18.050659197065844, rel=1e-9)


def test_a_flight_and_a_preset_together_are_refused():
    from tennislab.errors import InputError

    with pytest.raises(InputError, match="preset"):
        simulate("pro", 36, 21, flight=seed_flight_params(), preset="seed000")
    with pytest.raises(InputError, match="preset"):
        simulate("pro", 36, 21, preset="paper")


# ------------------------------------------------------------------ impact: the serve's ball
RACKET = ("--racket-speed", "37.5", "--impact-angle", "30", "--face-angle", "15", "--toss-vz", "-1.5")


@pytest.mark.parametrize("preset", [None, "standard", "seed000"])
def test_impact_gives_the_serves_launch_for_the_same_racket_and_preset(capsys, preset):
    """`impact` hits the ball the serve commands hit (the preset's ball): the same racket (speed, alpha,
    beta, toss) gives the same ball speed, spin and launch angle, under the default and either preset."""
    flags = () if preset is None else ("--preset", preset)
    imp = _json(capsys, "impact", *RACKET, *flags)
    srv = _json(capsys, "serve", *RACKET, *flags)
    assert imp["physics_preset"] == srv["physics_preset"] == (preset or "standard")
    for k in ("speed", "spin_rpm", "launch_angle"):
        assert imp["ball"][k] == pytest.approx(srv[k], rel=1e-12), k
    assert imp["inputs"]["ball_mass"] == srv["physics"]["mass"]
    assert imp["inputs"]["ball_radius"] == srv["physics"]["radius"]


def test_impact_preset_seed000_is_the_old_impact_and_the_default_the_standard_ball(capsys):
    # `impact --racket-speed 40 --impact-angle 36 --face-angle 21` with the paper's ball (59 g, 33 mm), the
    # ball impact hit before standard became its default: the serve's OLD_SERVE launch (the pro's 40 m/s)
    argv = ("impact", "--racket-speed", "40", "--impact-angle", "36", "--face-angle", "21")
    old = _json(capsys, *argv, "--preset", "seed000")
    assert (old["inputs"]["ball_mass"], old["inputs"]["ball_radius"]) == (0.059, 0.033)
    for k in ("speed", "spin_rpm", "launch_angle"):
        assert old["ball"][k] == pytest.approx(OLD_SERVE[k], rel=1e-9), k
    new = _json(capsys, *argv)
    assert (new["inputs"]["ball_mass"], new["inputs"]["ball_radius"]) == (0.0577, 0.0335)
    assert new["physics_preset"] == "standard" and abs(new["ball"]["speed"] - old["ball"]["speed"]) > 0.1
    capsys.readouterr()
    assert main([*argv]) == 0
    text = capsys.readouterr().out
    assert "physics: ball 57.7 g, radius 33.5 mm (preset standard; no flight: no aero model or air)" in text


# ------------------------------------------------------------------ the launcher
AIM = ("launcher", "aim", "--target", "9", "2", "--speed-kmh", "80", "--spin-rpm", "1500", "--height", "1")
# `launcher aim --target 9 2 --speed-kmh 80 --spin-rpm 1500 --height 1` as the launcher flew it with the
# paper's aero (preset seed002) as its default: 77 km/h, 21 deg, 6 deg, 1416 rpm, miss 0.70 mm
OLD_AIM = {
    "settings": {
        "height_m": 1.0,
        "speed_kmh": 77.0,
        "elevation_deg": 21.0,
        "heading_deg": 6.0,
        "spin_rpm": 1416.0,
        "spin_axis_deg": -10.0,
    },
    "landing": {"x": 9.000626326589366, "y": 2.000317147859675},
    "miss_mm": 0.7020454126643517,
    "net_clearance_m": 2.064286046881645,
    "apex_z_m": 3.1278799057032933,
}


def test_the_launcher_flies_every_commands_default_physics(capsys):
    """aim, drill and table fly the standard preset as fly does, and say so (text and JSON); rollers and
    power, which fly nothing, take its ball and say so."""
    want = json.loads(json.dumps(FlightParams.from_options(preset="standard").to_dict()))
    fly = _json(capsys, *COMMANDS["fly"])["physics"]
    aim = _json(capsys, *AIM)
    drill = _json(capsys, "launcher", "drill", "baseline_rally")
    for name, d in (("aim", aim), ("drill", drill)):
        assert d["physics_preset"] == "standard", name
        got = dict(d["physics"])
        assert got.pop("net_obstacle") is False  # the launcher judges the net crossing itself, as the serve
        assert (
            got
            == {k: v for k, v in want.items() if k != "net_obstacle"}
            == {k: v for k, v in fly.items() if k != "net_obstacle"}
        ), name
    for cmd in ("rollers", "power"):
        d = _json(capsys, "launcher", cmd, "--speed-kmh", "100", "--spin-rpm", "1000")
        assert (d["ball_mass"], d["ball_radius"], d["physics_preset"]) == (0.0577, 0.0335, "standard"), cmd
    for argv, line in (
        (AIM, "  physics: choppin2018 aero, air 1.199 kg/m^3, g 9.80665 m/s^2, ball 57.7 g, radius 33.5 mm "),
        (("launcher", "rollers", "--speed-kmh", "100"), "physics: ball 57.7 g, radius 33.5 mm (preset standard; "),
    ):
        capsys.readouterr()
        assert main(list(argv)) == 0
        assert line in capsys.readouterr().out, argv


def test_launcher_preset_seed002_reproduces_the_old_aim_and_drill(capsys):
    old = _json(capsys, *AIM, "--preset", "seed002")
    assert old["physics_preset"] == "seed002" and old["physics"]["aero"] == "launcher2015"
    assert old["settings"] == OLD_AIM["settings"]
    for k in ("miss_mm", "net_clearance_m", "apex_z_m"):
        assert old[k] == pytest.approx(OLD_AIM[k], rel=1e-9), k
    assert old["landing"] == pytest.approx(OLD_AIM["landing"], rel=1e-9)
    new = _json(capsys, *AIM)
    assert new["settings"] != old["settings"]  # another drag and lift: other settings for the same target
    # the Python workflows: the default is the standard preset, launcher_params(preset="seed002") the paper's
    from tennislab.launcher import aim, launcher_params

    assert launcher_params() == FlightParams.from_options()
    assert launcher_params(preset="seed002") == FlightParams.from_options(preset="seed002")
    py = aim((9.0, 2.0), 80, 1500, 0.0, 1.0, params=launcher_params(preset="seed002"))
    assert py.settings.to_dict() == OLD_AIM["settings"]
    # the shipped drill's distinct shots with the paper's aero, as `launcher drill baseline_rally` compiled
    # them before (height, speed, elevation, heading, spin, axis)
    keys = ("height_m", "speed_kmh", "elevation_deg", "heading_deg", "spin_rpm", "spin_axis_deg")
    d = _json(capsys, "launcher", "drill", "baseline_rally", "--preset", "seed002")
    assert {r["name"]: tuple(r[k] for k in keys) for r in d["shots"]} == {
        "deep-left": (1.0, 80.0, 20.0, 6.0, 1402.0, 8.0),
        "deep-right": (1.0, 80.0, 20.0, -6.0, 1402.0, -8.0),
        "drive-middle": (1.0, 82.0, 15.0, 0.0, 392.0, 0.0),
        "slice-left": (1.0, 73.0, 16.0, 5.0, 1013.0, 173.0),
    }


SMALL = ("--height", "1", "--speed-kmh", "100", "100", "--spin-rpm", "0", "0", "--spin-axis-deg", "0", "0")
SMALL += ("--elevation-deg", "5", "15", "--heading-deg", "-6", "6", "--no-progress")


def test_a_database_built_with_seed002_still_answers_with_its_own_physics(capsys, tmp_path):
    """A file built with the launcher's old default (the paper's aero) is read, described and looked up
    with the physics it stores, with no physics from the caller; extending it asks for that preset."""
    from tennislab.launcher import fly_settings, launcher_params
    from tennislab.launcher.machine import DEFAULT_SPEC, Settings

    path = str(tmp_path / "seed002.sqlite")
    built = _json(capsys, "launcher", "table", "--db", path, *SMALL, "--preset", "seed002")
    assert built["physics_preset"] == "seed002" and built["hits_total"] > 20
    info = _json(capsys, "launcher", "info", "--db", path)
    assert info["physics"]["aero"]["name"] == "launcher2015" and info["physics_preset"] == "seed002"
    paper, standard = launcher_params(preset="seed002"), launcher_params()
    for extra in (("--no-fallback",), ()):  # a stored hit; the machine's aim when nothing is stored within 2 cm
        d = _json(capsys, "launcher", "lookup", "--db", path, "--target", "8", "1", *extra)
        assert d["physics"]["aero"] == "launcher2015" and d["physics_preset"] == "seed002"
        st = Settings(**d["settings"])
        lands = fly_settings(st, DEFAULT_SPEC, paper).landing
        assert math.hypot(lands.x - d["landing"]["x"], lands.y - d["landing"]["y"]) < 1e-3, extra
        other = fly_settings(st, DEFAULT_SPEC, standard).landing  # the default flies them elsewhere
        assert math.hypot(other.x - d["landing"]["x"], other.y - d["landing"]["y"]) > 0.05, extra
    assert d["source"] == "refined" and d["miss_mm"] < 20
    capsys.readouterr()
    assert main(["launcher", "lookup", "--db", path, "--target", "8", "1", "--no-fallback"]) == 0
    assert "(the file's; preset seed002)" in capsys.readouterr().out
    # a preset the user names is compared with the file's, as a physics flag is (the default one is not)
    assert main(["launcher", "lookup", "--db", path, "--target", "8", "1", "--no-fallback", "--preset", "seed002"]) == 0
    capsys.readouterr()
    assert main(["launcher", "lookup", "--db", path, "--target", "8", "1", "--preset", "standard"]) == 2
    err = capsys.readouterr().err
    assert "built for another machine/physics than the flags given: physics.aero.name" in err, err
    # extending it with today's default is refused, saying which preset the file holds; with it, it resumes
    assert main(["launcher", "table", "--db", path, *SMALL]) == 2
    assert "the file's physics is preset seed002's" in capsys.readouterr().err
    again = _json(capsys, "launcher", "table", "--db", path, *SMALL, "--preset", "seed002")
    assert again["chunks_done_before"] == again["n_chunks"] and again["hits_total"] == built["hits_total"]


def test_the_python_impact_workflow_hits_the_same_ball():
    from tennislab.errors import InputError
    from tennislab.serve import impact, seed_impact_params

    std, paper = impact(40, 36, face_angle=21), impact(40, 36, face_angle=21, preset="seed000")
    assert (std.params.ball.mass, std.params.ball.radius) == (0.0577, 0.0335)
    assert std.to_dict()["ball"]["speed"] == pytest.approx(simulate("pro", 36, 21, advice=False).speed, rel=1e-12)
    assert paper.to_dict()["ball"]["speed"] == pytest.approx(OLD_SERVE["speed"], rel=1e-9)
    with pytest.raises(InputError, match="preset"):
        impact(40, 36, params=seed_impact_params(), preset="seed000")
