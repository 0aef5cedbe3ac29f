"""Calibration on serves: checks, splits, the aim, and recovery of known coefficients (issue 13 section 3).

Synthetic serves are flown by ``cross2014``'s compiled linear-lift kernel; the calibration fits its
own family through a speed x spin table: a different code path, so recovering the generating
coefficients proves the fitting code (not the physics: that is tests/calibrate/test_realdata.py).
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tennislab.calibrate import (
    FAMILIES,
    SpinAxis,
    aero_table_csv,
    calibrate_serves,
    check_serves,
    family_coefficients,
    family_table,
    predict_bounces,
    sensitivity_serves,
    serves_csv,
    serves_from_columns,
    split_serves,
    synthetic_serves,
    validate_serves,
)
from tennislab.calibrate.aim import aim_through_net, spin_vectors
from tennislab.calibrate.serves import load_serves
from tennislab.calibrate.stats import by_group, summarize
from tennislab.core.aero import get_aero_model
from tennislab.core.flight import FlightParams, fly_dense
from tennislab.errors import InputError
from tennislab.io.aero_table import read_aero_table

TRUTH = FlightParams.from_options(aero="cross2014", cd=0.66, cl=0.45)
AXIS = SpinAxis.by_family(
    {"flat": (0.5, 0.8), "slice": (0.2, 0.95), "kick": (0.8, 0.5), "pronated": (0.6, 0.6), "other": (0.4, 0.6)},
    name="truth",
)


@pytest.fixture(scope="module")
def serves():
    return synthetic_serves(240, TRUTH, AXIS, seed=3)


def test_aim_passes_the_net_point_and_matches_scipy(serves):
    s = serves.subset(np.arange(6))
    ft, fs = AXIS.fractions(s.family)
    aim = aim_through_net(s.impact, s.speed, s.spin, s.net, TRUTH, f_top=ft, f_side=fs)
    assert aim.converged.all() and aim.net_miss.max() < 1e-4
    for i in range(len(s)):
        tr = fly_dense(aim.states[i, :3], aim.states[i, 3:6], aim.states[i, 6:9], TRUTH)
        assert tr.net.y == pytest.approx(s.net[i, 0], abs=1e-4)
        assert tr.net.z == pytest.approx(s.net[i, 1], abs=1e-4)
        assert tr.landing.x == pytest.approx(s.bounce[i, 0], abs=1e-3)
        assert tr.landing.y == pytest.approx(s.bounce[i, 1], abs=1e-3)


def test_prediction_with_the_generating_model_is_exact(serves):
    p = predict_bounces(serves, TRUTH, AXIS)
    assert p.converged.all()
    assert np.max(p.miss) < 1e-4


def test_prediction_signs(serves):
    # more drag lands short (length < 0); spin curving left lands left (width > 0)
    s = serves.subset(serves.family == "slice")
    more_drag = FlightParams.from_options(aero="cross2014", cd=0.8, cl=0.45)
    assert np.median(predict_bounces(s, more_drag, AXIS).length) < -0.1
    no_side = SpinAxis.by_family({f: (AXIS.top[i], 0.0) for i, f in enumerate(FAMILIES)})
    assert np.median(predict_bounces(s, TRUTH, no_side).width) < -0.05


def test_calibration_recovers_cd_and_the_spin_axes(serves):
    r = calibrate_serves(serves, fit="cd", cl=0.45, spin_axis="fitted", split="parity")
    assert r.values["cd"] == pytest.approx(0.66, abs=2e-3)
    for i, fam in enumerate(FAMILIES):
        assert r.spin_axis.top[i] == pytest.approx(AXIS.top[i], abs=0.02), fam
        assert r.spin_axis.side[i] == pytest.approx(AXIS.side[i], abs=0.02), fam
    assert r.after["held_out"]["miss_median_m"] < 0.005
    assert abs(r.after["held_out"]["length_median_m"]) < 0.002
    d = r.to_dict()
    for k in ("values", "sd", "before", "after", "held_out_groups", "table", "spin_axis", "split", "n_fit"):
        assert k in d
    assert d["n_fit"] + d["n_held_out"] == len(serves)
    assert len(r.rows()) == len(serves)


def test_calibration_recovers_cd_and_cl_with_a_known_axis(serves):
    r = calibrate_serves(serves, fit=("cd", "cl"), spin_axis=AXIS, split="none")
    assert r.values["cd"] == pytest.approx(0.66, abs=2e-3)
    assert r.values["cl"] == pytest.approx(0.45, abs=5e-3)
    assert r.sd["cd"] > 0 and "cd:cl" in r.correlation
    assert r.after["held_out"]["n"] == 0


def test_lift_and_a_fitted_axis_are_refused(serves):
    with pytest.raises(InputError, match="^fit: cl and a fitted spin axis"):
        calibrate_serves(serves, fit="cd,cl", spin_axis="fitted")
    with pytest.raises(InputError, match="^fit: unknown parameter"):
        calibrate_serves(serves, fit="cd,drag")


def test_table_is_the_model_fitted_and_readable(tmp_path):
    v, w, cd, cl = family_table(0.6, 0.6, 0.1, radius=0.0335)
    p = tmp_path / "t.csv"
    p.write_text(aero_table_csv(v, w, cd, cl))
    v2, w2, cd2, cl2 = read_aero_table(str(p))
    model = get_aero_model("table", speed=v2, spin=w2, cd=cd2, cl=cl2)
    for speed, spin in ((20.0, 150.0), (45.3, 210.0), (61.0, 90.0), (30.0, 0.0)):
        want = family_coefficients(speed, spin, cd=0.6, cl=0.6, cd_s=0.1, radius=0.0335)
        got = model.coefficients(speed, spin, 0.0335)
        assert got[0] == pytest.approx(float(want[0]), rel=2e-3)
        assert got[1] == pytest.approx(float(want[1]), rel=2e-3, abs=1e-6)


def test_validation_ranks_the_generating_model_first(serves):
    r = validate_serves(serves, models=["stepanek1988", "cross2014"], spin_axis=AXIS)
    by = {m.model: m for m in r.models}
    assert by["stepanek1988"].overall["miss_median_m"] > 0.02
    d = r.to_dict()
    assert d["n_used"] == len(serves) and d["models"][0]["groups"]["serve_type"]
    truth_row = calibrate_serves(serves, fit=(), cd=0.66, cl=0.45, spin_axis=AXIS, split="none")
    assert truth_row.after["fit"]["miss_median_m"] < 0.001


def test_sensitivity_grid(serves):
    r = sensitivity_serves(serves, cd=(0.56, 0.66, 0.76), cl=(0.45,), spin_axes=(AXIS,))
    med = [g["held_out"]["length_median_m"] for g in r.grid]
    assert med[0] > 0.05 and abs(med[1]) < 0.002 and med[2] < -0.05  # less drag lands long
    assert len(r.rows()) == 6


def test_serves_csv_roundtrip(serves, tmp_path):
    p = tmp_path / "s.csv"
    p.write_text(serves_csv(serves))
    back = load_serves(p)
    assert len(back) == len(serves)
    assert np.allclose(back.impact, serves.impact, atol=1e-5)
    assert (back.family == serves.family).all()


def _one(**over):
    base = {
        "match": "atp_roland_garros_2019SM043",
        "point_ID": "1_1_1_1",
        "serve_num": 1.0,
        "spd": 180.0,
        "serve_type": "Flat",
        "spin_rpm": 1500.0,
        "x_ball_serve_impact": -11.5,
        "y_ball_serve_impact": 0.5,
        "z_ball_serve_impact": 2.8,
        "x_net_serve": 0.0,
        "y_net_serve": -0.2,
        "z_net_serve": 1.2,
        "x_serve_bounce": 5.5,
        "y_serve_bounce": -0.6,
        "z_serve_bounce": 0.034,
    }
    base.update(over)
    return base


def _serves(rows):
    cols = {k: np.array([r[k] for r in rows], dtype=object if isinstance(rows[0][k], str) else float) for k in rows[0]}
    return serves_from_columns(cols)


@pytest.mark.parametrize(
    "over,reason",
    [
        ({}, ""),
        ({"spd": 30.0}, "speed"),
        ({"z_ball_serve_impact": 0.04}, "impact"),
        ({"x_ball_serve_impact": 15.7}, "impact"),
        ({"x_serve_bounce": -5.5}, "same_side"),
        ({"z_net_serve": 0.93}, "net_contact"),
        ({"y_net_serve": 2.0}, "off_path"),
        ({"z_net_serve": 1.0, "z_ball_serve_impact": 3.4}, "below_chord"),
    ],
)
def test_checks(over, reason):
    s = _serves([_one(**over)])
    assert check_serves(s).tolist() == [reason]


def test_duplicates_flag_both_copies():
    s = _serves([_one(), _one(point_ID="1_1_2_1", spd=170.0), _one(point_ID="1_1_3_1", x_serve_bounce=5.0)])
    assert check_serves(s).tolist() == ["duplicate", "duplicate", ""]


def test_match_names_and_groups():
    s = _serves(
        [_one(), _one(match="wta_australian_open_2021WS701", serve_type=""), _one(match="odd", serve_type="Kick")]
    )
    assert s.tour.tolist() == ["atp", "wta", ""]
    assert s.group("event").tolist() == ["roland_garros_2019", "australian_open_2021", "(unknown)"]
    assert s.family.tolist() == ["flat", "other", "kick"]
    assert s.group("serve_type").tolist() == ["Flat", "(none)", "Kick"]
    with pytest.raises(InputError, match="^group:"):
        s.group("colour")


def test_splits(serves):
    fit, held, _ = split_serves(serves, "parity")
    assert fit.any() and held.any() and not (fit & held).any()
    assert not (set(serves.match[fit]) & set(serves.match[held]))
    fit, held, _ = split_serves(serves, "tournament:roland_garros")
    assert set(serves.tournament[fit]) == {"roland_garros"}
    fit, held, _ = split_serves(serves, "none")
    assert fit.all() and not held.any()
    with pytest.raises(InputError, match="^split: no serve has"):
        split_serves(serves, "tour:itf")
    with pytest.raises(InputError, match="^split: unknown split"):
        split_serves(serves, "random")


def test_spin_axis_parsing():
    assert SpinAxis.parse("topspin").top == (1.0,) * len(FAMILIES)
    side = SpinAxis.parse("90")
    assert side.side[0] == pytest.approx(1.0) and side.top[0] == pytest.approx(0.0, abs=1e-12)
    assert SpinAxis.parse("none").rate_scale == 0.0
    d = SpinAxis.angle(30.0).to_dict()
    assert d["angle_deg"]["flat"] == pytest.approx(30.0)
    with pytest.raises(InputError, match="^spin_axis"):
        SpinAxis.parse("wobble")
    with pytest.raises(InputError, match="^spin_axis"):
        SpinAxis.by_family({"flat": (0.9, 0.9)})
    with pytest.raises(InputError, match="^spin_axis"):
        SpinAxis.by_family({"lob": (1.0, 0.0)})


@settings(max_examples=60, deadline=None)
@given(
    st.floats(-1, 1),
    st.floats(-1, 1),
    st.floats(-0.3, 0.3),
    st.floats(-math.pi, math.pi),
)
def test_spin_vectors_keep_the_rate(ft, fs, elev, head):
    w = spin_vectors(np.array([200.0]), elev, head, ft, fs)
    assert np.linalg.norm(w) == pytest.approx(200.0, rel=1e-9)


def test_summaries_and_bootstrap():
    rng = np.random.default_rng(0)
    L = rng.normal(0.1, 0.2, 2000)
    W = rng.normal(-0.05, 0.1, 2000)
    clusters = np.repeat(np.arange(40), 50).astype(str)
    s = summarize(L, W, clusters)
    assert s["n"] == 2000
    assert s["length_median_m"] == pytest.approx(0.1, abs=0.02)
    lo, hi = s["length_median_ci95_m"]
    assert lo < s["length_median_m"] < hi and hi - lo < 0.05
    assert s["miss_p90_m"] > s["miss_median_m"]
    assert summarize([np.nan], [np.nan])["miss_median_m"] is None
    g = by_group(L, W, np.where(L > 0.1, "a", "b"))
    assert set(g) == {"a", "b"}
