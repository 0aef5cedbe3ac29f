"""A serve says why it failed and what would fix it; the default serve goes in; player profiles from dicts."""

import re

import pytest

from tennislab.errors import InputError
from tennislab.serve import (
    PlayerProfile,
    default_serve,
    get_player,
    monte_carlo,
    register_player,
    simulate,
)
from tennislab.serve.pipeline import REASONS
from tennislab.serve.verdict import pick, runs


def _proposals(advice: str) -> dict:
    """The settings the advice proposes: {"beta": b, "alpha": a, "azimuth": z} (those present)."""
    out = {}
    for key, pat in (
        ("beta", r"beta [-\d.]+ -> ([-\d.]+)"),
        ("alpha", r"hit at alpha ([-\d.]+) deg"),
        ("azimuth", r"azimuth [-\d.]+ -> ([-\d.]+) deg"),
    ):
        m = re.search(pat, advice)
        if m:
            out[key] = float(m.group(1))
    return out


@pytest.mark.parametrize(
    "alpha, beta, reason",
    [(36, 21, "net"), (40, 15, "long"), (10, 2, "long"), (3, 14, "short"), (3, 11, "net")],
)
def test_fault_reason_detail_and_advice_that_works(alpha, beta, reason):
    """Each fault names its reason with numbers; every change the advice proposes puts the serve in."""
    r = simulate("pro", alpha, beta)
    v = r.verdict
    assert not r.success and not v.success and v.reason == reason and reason in REASONS
    assert re.search(r"\d\.\d", v.detail) and v.line().startswith(f"FAULT ({reason}): ")
    props = _proposals(v.advice)
    assert props, v.advice
    if "beta" in props:
        assert simulate("pro", alpha, props["beta"], advice=False).success
    if "alpha" in props:
        assert simulate("pro", props["alpha"], beta, advice=False).success
    if reason in ("net", "short"):  # too low: the advice opens the face (smaller beta) or brushes more
        assert props.get("beta", beta) < beta or props.get("alpha", alpha) > alpha


def test_net_detail_has_the_clearance():
    r = simulate("pro", 36, 21)
    assert f"{r.net_clearance:+.3f}" in r.verdict.detail and r.net_clearance < 0
    assert r.net_height == pytest.approx(0.943 + r.net_clearance, abs=1e-12)
    d = r.to_dict()
    assert d["verdict"] == {"success": False, "reason": "net", "detail": r.verdict.detail, "advice": r.verdict.advice}


def test_short_and_wide():
    short = simulate("junior", 40, 30)
    assert short.verdict.reason == "short" and "before the net" in short.verdict.detail
    wide = simulate("pro", 4, 8, target="deuce", azimuth_deg=14.0)
    assert wide.verdict.reason == "wide" and "outside the deuce-box" in wide.verdict.detail
    az = _proposals(wide.verdict.advice)["azimuth"]
    assert az < 14 and simulate("pro", 4, 8, target="deuce", azimuth_deg=az, advice=False).success


def test_success_verdict_gives_the_margin():
    r = simulate("pro", 46, 21)
    assert r.success and r.verdict.reason is None and r.verdict.line().startswith("IN: ")
    assert r.verdict.advice.startswith("Margin: in for beta")


def test_no_advice_when_nothing_works():
    weak = PlayerProfile("weak", 0.5, 8.0)
    r = simulate(weak, 20, 5)
    assert not r.success and r.verdict.advice.startswith("no face angle")


def test_advice_helpers():
    import numpy as np

    v = np.arange(0.0, 10.0, 1.0)
    ok = np.array([0, 1, 1, 1, 0, 0, 1, 1, 1, 1], bool)
    assert runs(v, ok) == [(1.0, 3.0), (6.0, 9.0)]
    assert pick(5.0, runs(v, ok)) == (7.0, 6.0, 9.0)  # nearest interval, 1 deg inside
    assert pick(2.0, runs(v, ok)) == (2.0, 1.0, 3.0)  # already inside
    assert pick(0.0, [(1.0, 1.5)]) == (1.25, 1.0, 1.5)  # narrow interval: its middle
    assert pick(0.0, []) is None


@pytest.mark.parametrize("player", ["professional", "recreational", "junior"])
def test_default_serve_goes_in_with_margin(player):
    d = default_serve(player)
    r = simulate(player, d["impact_angle"], d["face_angle"], advice=False)
    assert r.success and r.category == d["category"] == "topspin" and d["margin_deg"] >= 1
    # every serve within the margin goes in
    m = d["margin_deg"]
    for da in (-m, m):
        for db in (-m, m):
            assert simulate(player, d["impact_angle"] + da, d["face_angle"] + db, advice=False).success


def test_default_serve_is_robust():
    """The default serve keeps > 90 % in with 1 deg / 1 m/s of scatter, more than the paper's optimum."""
    d = default_serve("professional")
    p = monte_carlo("professional", d["impact_angle"], d["face_angle"], n=2000, seed=1).p_success
    assert p > 0.9


def test_caveats_next_to_the_numbers():
    r = simulate("pro", 46, 21).to_dict()
    assert any("placeholder" in c for c in r["caveats"]) and any("2-D" in c for c in r["caveats"])
    lit = simulate("pro", 36, 21, **_literal()).to_dict()["caveats"]
    assert any("seed-clamp" in c for c in lit) and any("Euler" in c for c in lit) and any("gap" in c for c in lit)
    assert not any("2-D" in c for c in simulate("pro", 4, 8, target="deuce").to_dict()["caveats"])


def _literal() -> dict:
    from tennislab.serve import scheme_integration, seed_impact_params

    method, dt = scheme_integration("seed-literal")
    return {"impact_params": seed_impact_params(impact_scheme="seed-literal"), "method": method, "dt": dt}


def test_serve_dict_keeps_contract_keys():
    d = simulate("rec", 44, 18).to_dict()
    old = ("player", "alpha", "beta", "speed", "spin_rpm", "launch_angle", "net_height", "landing_x", "success")
    for k in (*old, "category", "landing", "impact", "velocity", "spin", "criteria"):
        assert k in d
    assert set(d["impact"]) >= {"contact_time_ms", "regime", "v_n", "v_t", "omega"}
    assert d["player"] == "recreational" and d["player_profile"]["impact_height"] == 2.8
    assert d["speed_kmh"] == pytest.approx(d["speed"] * 3.6)


# ------------------------------------------------------------------------------ profiles
def test_profile_from_dict_and_registration():
    d = {"name": "Club Ace", "impact_height": 2.9, "racket_speed": 35, "aliases": ["ace"], "description": "me"}
    p = PlayerProfile.from_dict(d)
    assert (p.impact_height, p.racket_speed, p.aliases) == (2.9, 35.0, ("ace",))
    assert PlayerProfile.from_dict(p.to_dict()) == p
    register_player(d)
    assert get_player("ace") == get_player("club ace") == p
    r = simulate("ace", 44, 18, advice=False)
    assert r.player.name == "Club Ace" and r.to_dict()["player_profile"]["racket_speed"] == 35.0


@pytest.mark.parametrize(
    "d, field",
    [
        ({"name": "x", "impact_height": 2.5}, "racket_speed"),
        ({"name": "x", "impact_height": 2.5, "racket_speed": 30, "speed": 1}, "speed"),
        ({"name": "x", "impact_height": "high", "racket_speed": 30}, "impact_height"),
        ({"name": "x", "impact_height": 9.0, "racket_speed": 30}, "impact_height"),
        ({"name": "x", "impact_height": 2.5, "racket_speed": 0}, "racket_speed"),
        ({"name": "", "impact_height": 2.5, "racket_speed": 30}, "name"),
        ({"name": "x", "impact_height": 2.5, "racket_speed": 30, "aliases": "y"}, "aliases"),
        ("not a table", "player"),
    ],
)
def test_profile_bad_dicts(d, field):
    with pytest.raises(InputError) as e:
        PlayerProfile.from_dict(d)
    assert str(e.value).startswith(f"{field}:")


def test_profile_overrides():
    p = get_player("pro").with_overrides(racket_speed=45.0)
    assert (p.name, p.impact_height, p.racket_speed) == ("professional*", 3.0, 45.0)
    assert get_player("pro").with_overrides() is get_player("pro")
