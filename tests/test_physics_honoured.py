"""Every physics setting reaches the flight of every workflow (issue 21: one converter, nothing dropped).

Each workflow flies with one setting away from its default -- wind, ``t_max``, the court's net,
the ball's moment of inertia, the net rule -- and the answer must move (or refuse) the way that
setting says, and its ``physics`` must report it (``FlightParams.to_dict()``).  The serve workflows
have their own such tests (tests/serve/test_pipeline.py).
"""

from __future__ import annotations

import dataclasses

import pytest

from tennislab.core import Court, FlightParams
from tennislab.errors import InputError
from tennislab.launcher import aim, launcher_params
from tennislab.linecall import call_state
from tennislab.trajectory import fly

BASE = FlightParams()
#: a groundstroke with topspin: 30 m/s, 8 deg up, from the centre of the near baseline
SHOT = dict(position=(-11.885, 0.0, 1.0), velocity=(29.7, 0.0, 4.2), spin=(0.0, 200.0, 0.0))


def _with(**kw) -> FlightParams:
    p = BASE
    ball = {k: kw.pop(k) for k in ("inertia_factor",) if k in kw}
    if ball:
        p = dataclasses.replace(p, ball=dataclasses.replace(p.ball, **ball))
    atm = {k: kw.pop(k) for k in ("wind",) if k in kw}
    if atm:
        p = dataclasses.replace(p, atmosphere=dataclasses.replace(p.atmosphere, **atm))
    return dataclasses.replace(p, **kw)


def _fly(params, **kw):
    return fly(SHOT["position"], SHOT["velocity"], SHOT["spin"], params=params, **kw)


def _call(params, **kw):
    return call_state(SHOT["position"], SHOT["velocity"], SHOT["spin"], params=params, **kw)


def test_wind_moves_the_landing_of_fly_and_call():
    calm_fly, calm_call = _fly(BASE).to_dict(), _call(BASE).to_dict()
    windy = _with(wind=(-5.0, 0.0, 0.0))  # a head wind
    f, c = _fly(windy).to_dict(), _call(windy).to_dict()
    assert f["landing"]["x"] < calm_fly["landing"]["x"] - 0.2
    assert c["bounce"]["x"] == pytest.approx(f["landing"]["x"], abs=1e-9)
    assert c["bounce"]["x"] < calm_call["bounce"]["x"] - 0.2
    assert f["physics"]["wind"] == c["physics"]["wind"] == [-5.0, 0.0, 0.0]


@pytest.mark.parametrize("workflow", [_fly, _call])
def test_t_max_ends_the_flight(workflow):
    assert workflow(_with(t_max=5.0)).to_dict()["physics"]["t_max"] == 5.0
    with pytest.raises(InputError, match="t_max = 0.3 s"):
        workflow(_with(t_max=0.3))


@pytest.mark.parametrize("workflow", [_fly, _call])
def test_the_court_s_net_is_the_one_flown_into(workflow):
    """A net 1.5 m high at the centre stops the groundstroke that clears the ITF net."""
    clear = workflow(BASE).to_dict()
    assert clear["net"]["result"] == "over" if workflow is _fly else clear["call"] in ("in", "out")
    high = _with(court=Court(net_center_height=1.5, net_post_height=1.6))
    d = workflow(high).to_dict()
    assert d["physics"]["court"]["net_center_height"] == 1.5
    if workflow is _fly:
        assert d["net_contact"] is not None and d["landing"] is None
    else:
        assert d["call"] == "net"


@pytest.mark.parametrize("workflow", [_fly, _call])
def test_the_net_rule_is_the_workflow_s_own(workflow):
    """``net=`` of the workflow is the rule (obstacle by default); the parameter set's flag follows it."""
    high = _with(court=Court(net_center_height=1.5, net_post_height=1.6), net_obstacle=False)
    assert workflow(high).to_dict()["physics"]["net_obstacle"] is True
    through = workflow(high, net="through").to_dict()
    assert through["physics"]["net_obstacle"] is False
    assert (through["landing"] if workflow is _fly else through["bounce"])["x"] > 0


def test_the_ball_s_inertia_changes_the_bounce():
    """I = 0.55 m r^2 (Cross 2020's real ball) instead of the thin shell's 2/3 changes the spin off the court."""
    shell = _call(BASE).to_dict()["bounce"]
    real = _call(_with(inertia_factor=0.55)).to_dict()
    assert real["physics"]["inertia_factor"] == 0.55
    assert abs(real["bounce"]["spin_out"][1] - shell["spin_out"][1]) > 1.0
    bounced = fly(**SHOT, params=_with(inertia_factor=0.55), bounces=1).to_dict()["bounces"][0]
    assert bounced["spin_out"][1] == pytest.approx(real["bounce"]["spin_out"][1], rel=1e-6)


def test_launcher_aim_flies_its_wind_and_court():
    base = launcher_params()
    calm = aim((8.0, 0.0), speed_kmh=80, params=base).to_dict()
    windy = aim((8.0, 0.0), speed_kmh=80, params=launcher_params(wind=(-5.0, 0.0, 0.0))).to_dict()
    assert windy["physics"]["wind"] == [-5.0, 0.0, 0.0]
    assert windy["exact"]["elevation_deg"] > calm["exact"]["elevation_deg"] + 0.1  # (before the machine's steps)
    high = aim((8.0, 0.0), speed_kmh=80, params=dataclasses.replace(base, court=Court(net_center_height=1.2)))
    assert high.to_dict()["physics"]["court"]["net_center_height"] == 1.2
    assert high.solution.net_clearance_m < calm["net_clearance_m"] - 0.2


def test_the_command_line_s_net_rule_is_the_library_s():
    """``fly`` and ``call --position`` default to the one net rule (``core.events.DEFAULT_NET``)."""
    from tennislab.cli import build_parser
    from tennislab.core import DEFAULT_NET

    parser = build_parser()
    fly_args = parser.parse_args(["fly", "--speed-kmh", "120", "--elevation-deg", "6"])
    call_args = parser.parse_args(["call", "--position", "-11.885", "0", "1", "--velocity", "30", "0", "1"])
    assert fly_args.net == call_args.net == DEFAULT_NET == "obstacle"


def test_a_track_fit_flies_its_wind():
    """call_track fits with the flight's wind: a track flown in a cross wind is followed to the micrometre
    with that wind, not without it (the fit's free drag, lift and spin cannot make up a wind)."""
    from tennislab.linecall import call_track

    windy = _with(wind=(0.0, 4.0, 0.0))
    frame = fly(**SHOT, params=windy).to_frame()
    frame = frame[frame.segment == 0]
    t, xyz = frame.t_s.to_numpy(), frame[["x_m", "y_m", "z_m"]].to_numpy()
    fit_windy, fit_calm = (call_track(t, xyz, params=p).to_dict() for p in (windy, BASE))
    assert fit_windy["physics"]["wind"] == [0.0, 4.0, 0.0]
    assert fit_windy["fit"]["rms_mm"] < 0.01 < 0.1 < fit_calm["fit"]["rms_mm"]


def test_the_inverse_map_and_a_drill_fly_their_wind():
    """The launcher's inverse map (refined on the real kernel) and a compiled drill aim with the wind."""
    from tennislab.launcher import compile_drill, inverse_aim, load_drill

    calm = inverse_aim((8.0, 0.0), 80, params=launcher_params()).to_dict()
    head = inverse_aim((8.0, 0.0), 80, params=launcher_params(wind=(-5.0, 0.0, 0.0))).to_dict()
    assert head["physics"]["wind"] == [-5.0, 0.0, 0.0]
    assert head["settings"]["elevation_deg"] > calm["settings"]["elevation_deg"] + 1.0
    assert head["miss_mm"] < 20.0
    drill = load_drill("baseline_rally")
    still, tail = compile_drill(drill), compile_drill(drill, params=launcher_params(wind=(3.0, 0.0, 0.0)))
    assert tail.to_dict()["physics"]["wind"] == [3.0, 0.0, 0.0] and still.to_dict()["physics"]["wind"] == [0.0] * 3
    moved = [a != b for a, b in zip(still.rows(), tail.rows())]
    assert any(moved) and all(r["miss_mm"] < 50.0 for r in tail.rows())
