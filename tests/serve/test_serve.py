"""Serve analysis (seed 000): profiles, the window, Table 1 reproduction, optimum rules, 3-D serves.

Tolerances against the published Table 1 are justified in docs/serve.md ("Tolerances"):
with the converged integrator and the dissipative friction rule, the flat serves and the
geometry of the window (beta, X, Y, gamma) reproduce; spin and speed reproduce only with the
seed's own numerical scheme (Euler 1e-4 s + its clamp friction rule), tested separately.
"""

import dataclasses

import numpy as np
import pytest

from tennislab.errors import InputError
from tennislab.serve import SeedCriteria, get_player, seed_flight_params, seed_impact_params
from tennislab.serve.published import OPTIMUM, PEAK_SPIN_ALPHA, TABLE1
from tennislab.serve.single import simulate_serve
from tennislab.serve.window import angle_grid, serve_window

PLAYERS = ("professional", "recreational", "junior")


@pytest.fixture(scope="module")
def windows():
    return {p: serve_window(p) for p in PLAYERS}


@pytest.fixture(scope="module")
def seed_scheme_windows():
    imp = dataclasses.replace(seed_impact_params(), friction_model="seed-clamp")
    return {p: serve_window(p, impact=imp, dt=1e-4, method="euler") for p in PLAYERS}


def test_profiles_and_constants():
    assert (get_player("pro").impact_height, get_player("pro").racket_speed) == (3.0, 40.0)
    assert (get_player("rec").impact_height, get_player("rec").racket_speed) == (2.8, 30.0)
    assert (get_player("junior").impact_height, get_player("junior").racket_speed) == (2.2, 25.0)
    f = seed_flight_params()
    assert (f.ball.mass, f.ball.radius, f.atmosphere.density, f.atmosphere.gravity) == (0.059, 0.033, 1.22, 9.82)
    assert f.aero.name == "stepanek1988"
    i = seed_impact_params()
    assert (i.racket_mass, i.string_stiffness, i.friction) == (0.2, 50e3, 0.35)
    c = SeedCriteria()
    assert (c.net_top, c.service_line, c.flat_max_rpm, c.topspin_min_rpm) == (0.943, 18.318, 1200, 3200)
    # physics flags override
    assert seed_flight_params(gravity=9.81).atmosphere.gravity == 9.81
    with pytest.raises(InputError, match="player"):
        get_player("nobody")


def test_angle_grid():
    assert angle_grid(1.0).size == 91 and angle_grid(1.0)[-1] == 90.0
    assert angle_grid(2.5).size == 37
    with pytest.raises(InputError, match="step"):
        angle_grid(0.0)


def test_window_consistent_with_single_serve(windows):
    w = windows["professional"]
    for ib, ia in [(8, 3), (19, 40), (30, 10)]:
        s = simulate_serve("pro", float(w.alpha_deg[ia]), float(w.beta_deg[ib]))
        g = w.serve(ib, ia)
        assert s["success"] == g["success"]
        for k in ("speed", "spin_rpm", "launch_angle", "net_height", "landing_x"):
            assert s[k] == pytest.approx(g[k], rel=1e-9, abs=1e-9, nan_ok=True)


def _within(ours, pub, tol):
    return ours is not None and abs(ours[0] - pub[0]) <= tol and abs(ours[1] - pub[1]) <= tol


@pytest.mark.parametrize("player", PLAYERS)
def test_table1_flat_and_geometry(windows, player):
    """Flat serves and the window's geometry (docs/serve.md, Tolerances)."""
    s, pub = windows[player].summary(), TABLE1[player]
    f, pf = s["flat"], pub["flat"]
    assert _within(f["beta"], pf["beta"], 1.0)
    assert f["speed"][0] >= 0.95 * pf["speed"][0] and f["speed"][1] <= pf["speed"][1]
    assert _within(f["launch_angle"], pf["launch_angle"], 1.0)
    assert _within(f["landing_x"], pf["landing_x"], 0.5)
    assert _within(f["net_height"], pf["net_height"], 0.1)
    t, pt = s["topspin"], pub["topspin"]
    assert _within(t["beta"], pt["beta"], 2.0)
    assert _within(t["landing_x"], pt["landing_x"], 0.3)
    assert _within(t["net_height"], pt["net_height"], 0.25)
    assert _within(t["launch_angle"], pt["launch_angle"], 2.0)
    assert 0.6 * pt["n"] <= t["n"] <= 1.1 * pt["n"]
    assert 0.75 * pt["spin_rpm"][1] <= t["spin_rpm"][1] < pt["spin_rpm"][1]


@pytest.mark.parametrize("player", PLAYERS)
def test_table1_spin_and_speed_with_seed_scheme(seed_scheme_windows, player):
    """With the seed's Euler step (1e-4 s) and its clamp friction rule, speeds and spins come
    within a few percent of Table 1 and fig 5 (docs/serve.md explains what remains)."""
    w = seed_scheme_windows[player]
    s, pub = w.summary(), TABLE1[player]
    assert s["flat"]["speed"][0] == pytest.approx(pub["flat"]["speed"][0], rel=0.025)
    assert s["topspin"]["spin_rpm"][1] == pytest.approx(pub["topspin"]["spin_rpm"][1], rel=0.05)
    assert s["topspin"]["speed"][1] == pytest.approx(pub["topspin"]["speed"][1], rel=0.05)
    assert s["topspin"]["n"] == pytest.approx(pub["topspin"]["n"], rel=0.10)
    assert abs(w.peak_spin_alpha - PEAK_SPIN_ALPHA[player]) <= 5


@pytest.mark.parametrize("player", PLAYERS)
def test_optimum_rules(windows, player):
    """Flat: the largest X (ties: speed); topspin: the largest spin (ties: X); both successful."""
    w = windows[player]
    of, ot = w.optimum("flat"), w.optimum("topspin")
    flat = w.mask("flat")
    assert of["success"] and of["category"] == "flat"
    assert of["landing_x"] == pytest.approx(w.landing_x[flat].max())
    assert ot["spin_rpm"] == pytest.approx(w.grid("spin_rpm")[w.mask("topspin")].max())
    # like the seed's figs 7-9: the optimum flat serve lands within 0.2 m of the service line
    assert ot["landing_x"] <= 18.318 and of["landing_x"] > 18.318 - 0.2
    assert OPTIMUM[player]["flat"]["landing_x"] > 18.318 - 0.2


def test_categories_and_criteria(windows):
    w = windows["junior"]
    spin = w.grid("spin_rpm")
    assert np.all(spin[w.mask("flat")] < 1200) and np.all(spin[w.mask("topspin")] > 3200)
    assert np.all(w.net_height[w.success] > 0.943) and np.all(w.landing_x[w.success] <= 18.318)
    # alpha = 0 gives no spin at any beta
    assert np.all(w.spin_rpm[0] == 0)


def test_3d_serve_to_the_boxes():
    """3-D: a serve down the middle of the seed's plane from y = 0 lands on the centre line (in
    both boxes); turned left it lands in the deuce box, turned right in the ad box; the real net is used."""
    flat = simulate_serve("pro", 4, 8, target="deuce")
    assert flat["success"] and abs(flat["landing"]["y"]) < 1e-9
    assert simulate_serve("pro", 4, 8, target="ad")["success"]
    # the seed's 2-D line (service line + r = 18.318 m) is more generous than the real one
    seed_only = simulate_serve("pro", 7, 8)
    assert seed_only["success"] and not simulate_serve("pro", 7, 8, target="deuce")["success"]
    left = simulate_serve("pro", 4, 8, target="deuce", azimuth_deg=4.0, server_y=-0.3)
    right = simulate_serve("pro", 4, 8, target="ad", azimuth_deg=-4.0, server_y=0.3)
    assert left["success"] and left["landing"]["y"] > 0
    assert right["success"] and right["landing"]["y"] < 0
    assert not simulate_serve("pro", 4, 8, target="ad", azimuth_deg=4.0, server_y=-0.3)["success"]
    wide = simulate_serve("pro", 4, 8, target="deuce", azimuth_deg=25.0)
    assert not wide["success"]
    slice_ = simulate_serve("pro", 30, 15, target="deuce", brush_deg=-90, azimuth_deg=0)
    assert slice_["spin"][2] > 0 and slice_["landing"]["y"] < 0  # moves right off the strings


def test_toss_velocity_changes_spin():
    """A falling ball (toss) raises the relative tangential speed and the spin (worksheet sec. 1.1)."""
    a = simulate_serve("pro", 20, 12)
    b = simulate_serve("pro", 20, 12, toss_vz=-3.0)
    assert b["spin_rpm"] > a["spin_rpm"]


def test_serve_bad_input():
    with pytest.raises(InputError, match="impact angle"):
        simulate_serve("pro", 95, 3)
    with pytest.raises(InputError, match="target"):
        simulate_serve("pro", 5, 3, azimuth_deg=3.0)
    with pytest.raises(InputError, match="target"):
        simulate_serve("pro", 5, 3, target="middle")


def test_3d_window_down_the_t_is_within_the_seed_window(windows):
    """From y = 0 straight down the centre line, the real net (0.914 m) and box (line at 6.40 m)
    are stricter than the seed's 0.943 - r... criteria (net 0.91 + r, line + r): a subset."""
    w2 = windows["recreational"]
    w3 = serve_window("rec", target="deuce")
    assert w3.mode == "deuce-box" and w2.mode == "seed-2d"
    assert np.all(w2.success[w3.success])
    assert 0.8 * w2.success.sum() < w3.success.sum() < w2.success.sum()
    # turned toward the ad box it no longer lands in the deuce box
    w_ad = serve_window("rec", step=3, target="deuce", azimuth_deg=-6.0)
    assert w_ad.success.sum() == 0
    with pytest.raises(InputError, match="target"):
        serve_window("rec", step=10, azimuth_deg=3.0)
