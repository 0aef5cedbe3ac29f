"""One default physics for every command: fly, call, serve, serve-window and serve-mc fly the same
``standard`` physics unless told otherwise, and ``--preset seed000`` flies the serve paper's constants
(the serve commands' numbers before ``standard`` became their default)."""

import json

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
