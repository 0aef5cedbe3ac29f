"""Serves from the ball: a ball launch -> the racket (the impact model's inverse) -> the same ball."""

from __future__ import annotations

import json

import pytest

from tennislab.cli import main
from tennislab.errors import InputError
from tennislab.serve import BallLaunch, racket_for, simulate
from tennislab.serve.pipeline import make_setup

BALLS = [
    BallLaunch(50.0, 2500.0, -5.0),  # the coach's 180 km/h, 2500 rpm serve
    BallLaunch(40.0, 4000.0, 2.0),  # a kick
    BallLaunch(55.0, 0.0, -7.0),  # flat
    BallLaunch(30.0, 1000.0, 0.0, 0.0, 180.0),  # backspin
]


@pytest.mark.parametrize("ball", BALLS)
def test_ball_to_racket_to_the_same_ball(ball):
    setup = make_setup("professional")
    r = racket_for(setup, ball, height=2.9)
    player = setup.player.with_overrides(r.height, r.racket_speed)
    res = simulate(player, r.alpha_deg, r.beta_deg, advice=False)  # the forward workflow, not the solver's
    assert res.speed == pytest.approx(ball.speed_ms, rel=0.01)
    assert abs(res.spin_rpm) == pytest.approx(ball.spin_rpm, rel=0.01, abs=5.0)
    assert res.launch_angle == pytest.approx(ball.elevation_deg, abs=0.05)
    if ball.spin_rpm > 0:  # (a ball without spin comes back with |spin| ~ 1e-18 rpm of either sign)
        assert (res.spin_rpm < 0) == (ball.spin_axis_deg == 180.0)


def test_3d_ball_with_heading_and_sidespin_round_trip():
    setup = make_setup("professional", target="deuce", server_y=-0.5)
    ball = BallLaunch(45.0, 3000.0, -3.0, 3.0, -30.0)
    r = racket_for(setup, ball)
    res = simulate(
        setup.player.with_overrides(r.height, r.racket_speed),
        r.alpha_deg,
        r.beta_deg,
        target="deuce",
        server_y=-0.5,
        azimuth_deg=r.azimuth_deg,
        brush_deg=r.brush_deg,
        advice=False,
    )
    import math

    vx, vy, vz = res.velocity
    assert res.speed == pytest.approx(45.0, rel=0.01)
    assert abs(res.spin_rpm) == pytest.approx(3000.0, rel=0.01)
    assert math.degrees(math.atan2(vy, vx)) == pytest.approx(3.0, abs=0.05)
    assert r.gives.spin_axis_deg == pytest.approx(-30.0, abs=0.05)


def test_a_ball_the_impact_cannot_give_is_refused_with_the_nearest():
    with pytest.raises(InputError, match=r"ball launch: .* no racket .*nearest"):
        racket_for(make_setup("professional"), BallLaunch(50.0, 9000.0, -5.0))
    with pytest.raises(InputError, match="heading_deg"):
        racket_for(make_setup("professional"), BallLaunch(50.0, 2500.0, -5.0, heading_deg=3.0))


def test_cli_serve_from_the_ball_says_the_racket(capsys):
    assert main(["serve", "--speed-kmh", "180", "--spin-rpm", "2500", "--elevation-deg", "-5", "--height", "2.9"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("racket for this ball: 37.7 m/s, alpha 18.3 deg, beta 11.7 deg")
    assert "2500 rpm topspin" in out
    assert main(["serve", "--speed-ms", "50", "--spin-rpm", "2500", "--elevation-deg", "-5", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    r = d["racket_for_ball"]
    assert d["speed"] == pytest.approx(50.0, rel=0.01) and d["spin_rpm"] == pytest.approx(2500.0, rel=0.01)
    assert (d["alpha"], d["beta"]) == (r["alpha_deg"], r["beta_deg"])
    assert d["player_profile"]["racket_speed"] == pytest.approx(r["racket_speed_ms"])


@pytest.mark.parametrize(
    "argv, flag",
    [
        (["serve", "--speed-kmh", "180", "--impact-angle", "3"], "--impact-angle"),
        (["serve", "--speed-kmh", "180", "--spin-rpm", "2500"], "--elevation-deg"),
        (["serve", "--spin-rpm", "2500", "--elevation-deg", "-5"], "--spin-rpm"),
        (["serve", "--player", "pro"], "--impact-angle"),
        (["serve-mc", "--speed-kmh", "180", "--elevation-deg", "-5", "--heading-deg", "2"], "--heading-deg"),
    ],
)
def test_cli_mixed_or_missing_launch_is_one_line_exit_2(capsys, argv, flag):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and flag in err


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["serve", "--speed-kmh", "400", "--elevation-deg", "5"],
            "--speed-kmh: 400 km/h is outside the allowed range [3.6, 360] km/h",
        ),
        (
            ["serve", "--speed-mph", "300", "--elevation-deg", "5"],
            "--speed-mph: 300 mph is outside the allowed range [2.2, 223.7] mph",
        ),
        (
            ["serve-mc", "--speed-ms", "0.5", "--elevation-deg", "5"],
            "--speed-ms: 0.5 m/s is outside the allowed range [1, 100] m/s",
        ),
        (
            ["serve-window", "--speed-kmh", "150", "--heading-range", "5", "-5", "--target", "deuce"],
            "--heading-range: give the lower bound first (got 5 -5 deg)",
        ),
        (
            ["serve-window", "--speed-kmh", "150", "--elevation-range", "5", "-5"],
            "--elevation-range: give the lower bound first (got 5 -5 deg)",
        ),
        (
            ["serve-window", "--speed-kmh", "150", "--heading-deg", "3", "--target", "deuce"],
            "--heading-deg: not with serve-window (its headings are swept: --heading-range LO HI)",
        ),
    ],
)
def test_a_ball_launch_out_of_range_names_its_flag_and_unit(capsys, argv, message):
    assert main(argv) == 2
    assert capsys.readouterr().err.strip() == f"tennislab {argv[0]}: error: {message}"


def test_a_ball_launch_in_any_speed_unit_is_the_same_ball():
    assert BallLaunch.of(speed_kmh=180.0, elevation_deg=-5.0).speed_ms == pytest.approx(50.0, rel=1e-12)
    assert BallLaunch.of(speed_mph=100.0, elevation_deg=0.0).speed_ms == pytest.approx(44.704, rel=1e-12)
    with pytest.raises(InputError, match=r"^speed_ms: give one speed"):
        BallLaunch.of(speed_kmh=180.0, speed_ms=50.0, elevation_deg=0.0)
    with pytest.raises(InputError, match=r"^speed_ms: a ball launch needs its speed"):
        BallLaunch.of(elevation_deg=0.0)


@pytest.mark.parametrize("cmd", ["serve", "serve-mc", "serve-window", "impact"])
def test_every_help_that_takes_alpha_and_beta_says_what_they_are(capsys, cmd):
    with pytest.raises(SystemExit):
        main([cmd, "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert "face normal" in out and "alpha" in out
    assert "beta" in out and "below the horizontal" in out


# ---------------------------------------------------------------- serve-window: the empty window, the spin classes
def test_an_empty_window_says_why_and_the_azimuth_that_lets_serves_in(capsys):
    argv = ["serve-window", "--target", "deuce", "--server-y", "-0.5", "--step", "6"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    hint = next(line for line in out.splitlines() if line.startswith("hint: "))
    assert "no serve of the window goes in (" in hint and "wide" in hint
    psi = float(hint.split("--azimuth ")[1].split(")")[0])
    n = int(hint.split("), ")[1].split(" serves go in")[0])
    assert n > 0
    # the hint is checked: the window at that azimuth has serves that go in
    assert main([*argv, "--azimuth", str(psi), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["n_success"] > 0 and "hint" not in d


def test_the_window_summary_has_every_spin_class_and_its_bands(capsys):
    assert main(["serve-window", "--step", "6", "--spin-bands", "1000", "4000", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert set(d["summary"]) == {"flat", "other", "topspin"}
    assert d["spin_bands_rpm"] == {"flat": [0.0, 1000.0], "other": [1000.0, 4000.0], "topspin": [4000.0, None]}
    assert d["summary"]["other"]["n"] > 0
    lo, hi = d["summary"]["other"]["spin_rpm"]
    assert 1000 <= lo <= hi <= 4000
    assert sum(c["n"] for c in d["summary"].values()) == d["n_success"]
    assert main(["serve-window", "--step", "6"]) == 0
    out = capsys.readouterr().out
    assert any(line.startswith("other ") for line in out.splitlines())
    assert "spin classes: flat < 1200 rpm, other 1200-3200 rpm, topspin > 3200 rpm" in out


# ---------------------------------------------------------------- the physics, stated in every output
@pytest.mark.parametrize(
    "argv, preset",
    [
        (["fly", "--speed-kmh", "180", "--elevation-deg", "-5"], "standard"),
        (["serve", "--player", "pro", "--impact-angle", "36", "--face-angle", "21"], "standard"),
        (
            ["serve", "--player", "pro", "--impact-angle", "36", "--face-angle", "21", "--preset", "seed000"],
            "seed000",
        ),
        pytest.param(
            ["serve-mc", "--impact-angle", "36", "--face-angle", "21", "--n", "500"], "standard", marks=pytest.mark.slow
        ),
        (["serve-window", "--step", "10"], "standard"),
        (["serve-window", "--step", "10", "--preset", "seed000"], "seed000"),
    ],
)
def test_every_output_states_its_physics_and_preset(capsys, argv, preset):
    from tennislab.core.flight import FlightParams

    want = FlightParams.from_options(preset=preset).to_dict()
    assert main(argv) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("physics: "))
    assert line.startswith(f"physics: {want['aero']} aero, air {want['air_density']:g} kg/m^3")
    assert f"ball {round(want['mass'] * 1e3, 2):g} g" in line and line.endswith(f"(preset {preset})")
    if argv[0] != "fly":  # fly's JSON is FlightResult.to_dict(), whose `physics` is the same dict
        assert main([*argv, "--json"]) == 0
        d = json.loads(capsys.readouterr().out)
        assert d["physics"] == want and d["physics_preset"] == preset


# ---------------------------------------------------------------- serve-window of a ball: its launch directions
@pytest.mark.slow
def test_ball_window_agrees_with_single_serves_of_that_ball(capsys):
    from tennislab.serve import ball_window

    w = ball_window("professional", BallLaunch(50.0, 2500.0, 0.0), height=2.9, step=1.0)
    assert w.success.any() and not w.success.all()
    for row in w.rows()[::4]:  # each launch direction, served as a ball by `simulate` through its racket
        r = racket_for(make_setup("professional"), BallLaunch(50.0, 2500.0, row["elevation_deg"]), height=2.9)
        res = simulate(
            make_setup("professional").player.with_overrides(2.9, r.racket_speed), r.alpha_deg, r.beta_deg, advice=False
        )
        assert res.success == row["success"], row
    assert main(["serve-window", "--speed-kmh", "180", "--spin-rpm", "2500", "--height", "2.9", "--step", "1"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("ball: 180.0 km/h, 2500 rpm topspin from 2.90 m; racket 37.7 m/s, alpha 18.3 deg")
    assert out[1].startswith(f"in: {int(w.success.sum())} of {w.success.size} launch directions: elevation ")
    assert main(["serve-window", "--speed-kmh", "180", "--spin-rpm", "2500", "--elevation-range", "5", "10"]) == 0
    assert "in: none of the 11 launch directions (hint:" in capsys.readouterr().out
