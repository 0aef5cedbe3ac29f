"""Court, ball, atmosphere and aero models (issue 2)."""
import math

import numpy as np
import pytest

from tennislab.core.aero import aero_model_names, get_aero_model, register_aero
from tennislab.core.atmosphere import Atmosphere, air_density
from tennislab.core.ball import Ball
from tennislab.core.court import ITF_COURT, Court
from tennislab.errors import InputError


# ----------------------------------------------------------------- court
def test_net_profile():
    c = ITF_COURT
    assert c.net_height(0.0) == pytest.approx(0.914)
    assert c.y_post == pytest.approx(10.97 / 2 + 0.914)
    assert c.net_height(c.y_post) == pytest.approx(1.07)
    assert c.net_height(-c.y_post) == pytest.approx(1.07)
    assert c.net_height(c.y_post + 0.01) == 0.0
    ys = np.linspace(0, c.y_post, 50)
    assert np.all(np.diff(c.net_height(ys)) > 0)      # rises monotonically toward the posts


def test_court_dimensions_and_areas():
    c = ITF_COURT
    assert c.area_bounds("singles") == (0.0, 11.885, -4.115, 4.115)
    assert c.area_bounds("doubles")[3] == pytest.approx(5.485)
    # deuce box of the far half is on the receiver's right: y > 0
    assert c.contains("deuce-box", 3.0, 2.0) and not c.contains("deuce-box", 3.0, -2.0)
    assert c.contains("ad-box", 3.0, -2.0)
    assert c.contains("near-deuce-box", -3.0, -2.0)
    # lines belong to the area they bound: the outer edge of the service line is in
    assert c.contains("deuce-box", 6.40, 1.0) and not c.contains("deuce-box", 6.4001, 1.0)
    # the centre service line belongs to both boxes
    assert c.contains("deuce-box", 3.0, -0.02) and c.contains("ad-box", 3.0, 0.02)
    assert c.contains("singles", 11.885, 4.115) and not c.contains("singles", 11.886, 0.0)
    assert set(c.areas_at(3.0, 1.0)) >= {"singles", "doubles", "deuce-box", "full-singles"}
    # a margin (half a ball mark) widens the area
    assert c.contains("singles", 11.90, 0.0, margin=0.02)
    with pytest.raises(InputError, match="unknown name"):
        c.area_bounds("tramlines")


def test_lines_are_inside_the_areas_they_bound():
    c = ITF_COURT
    lines = c.lines()
    x0, x1, y0, y1 = lines["baseline"]
    assert x1 == pytest.approx(11.885) and x1 - x0 == pytest.approx(c.baseline_width)
    x0, x1, y0, y1 = lines["service"]
    assert x1 == pytest.approx(6.40)
    x0, x1, y0, y1 = lines["center"]
    assert y1 - y0 == pytest.approx(0.05) and y0 == -y1
    assert lines["near-baseline"][0] == pytest.approx(-11.885)


def test_court_validation():
    with pytest.raises(InputError):
        Court(singles_width=12.0)
    with pytest.raises(InputError):
        Court(line_width=-0.01)


# ----------------------------------------------------------------- ball
def test_ball_defaults_and_inertia():
    b = Ball()
    assert b.itf_compliant
    assert b.inertia == pytest.approx(2 / 3 * b.mass * b.radius ** 2)
    assert b.area == pytest.approx(math.pi * b.radius ** 2)
    assert not Ball(mass=0.070).itf_compliant


@pytest.mark.parametrize("kw", [dict(mass=-0.05), dict(mass=0.0), dict(radius=float("nan")),
                                dict(radius=0.5), dict(inertia_factor=1.5)])
def test_ball_validation(kw):
    with pytest.raises(InputError):
        Ball(**kw)


# ----------------------------------------------------------------- atmosphere
def test_air_density_values():
    # dry air at 15 degC, 101325 Pa: ISA sea-level density 1.2250 kg/m^3
    assert air_density(15.0, 101325.0, relative_humidity=0.0) == pytest.approx(1.2250, abs=1e-3)
    # humid air is lighter; hot air is lighter; altitude lowers density (~ -11 % at 1000 m)
    assert air_density(20, relative_humidity=1.0) < air_density(20, relative_humidity=0.0)
    assert air_density(35) < air_density(5)
    # ISA at 1000 m: 8.5 degC, 89876 Pa, 1.1117 kg/m^3
    assert air_density(8.5, altitude_m=1000, relative_humidity=0) == pytest.approx(1.1117, abs=1e-3)
    with pytest.raises(InputError, match="temperature_c"):
        air_density(90)


def test_seed_values_reproducible():
    a = Atmosphere(density=1.22, gravity=9.82)
    assert (a.density, a.gravity) == (1.22, 9.82)
    assert Atmosphere.from_weather(15, 101325, relative_humidity=0).density == pytest.approx(1.225, abs=1e-3)


# ----------------------------------------------------------------- aero
def test_stepanek_matches_seed_equations():
    m = get_aero_model("stepanek1988")
    r, v, w = 0.033, 40.0, 300.0
    x = v / (r * w)
    cd, cl = m.coefficients(v, w, r)
    assert cd == pytest.approx(0.55 + 1 / (22.5 + 4.2 * x ** 2.5) ** 0.4, rel=1e-14)
    assert cl == pytest.approx(1 / (2 + x), rel=1e-14)
    assert m.coefficients(40.0, 0.0, r) == (0.55, 0.0)
    # C_D rises with spin (seed 000 section 2.1)
    cds, _ = m.coefficients(40.0, np.array([50.0, 200.0, 600.0]), r)
    assert np.all(np.diff(cds) > 0)


def test_launcher2015_is_linear_in_spin():
    m = get_aero_model("launcher2015", cd=0.5, cl=0.8)
    cd, cl = m.coefficients(20.0, 100.0, 0.0335)
    assert cd == 0.5 and cl == pytest.approx(0.8 * 0.0335 * 100 / 20)
    assert get_aero_model("wojcicki2010").name == "launcher2015"


def test_table_model_interpolates(tmp_path):
    f = tmp_path / "aero.csv"
    rows = ["speed_ms,spin_rpm,cd,cl"]
    for v in (10, 30):
        for w in (0, 3000):
            rows.append(f"{v},{w},{0.5 + v / 100},{w / 10000}")
    f.write_text("\n".join(rows) + "\n")
    m = get_aero_model("table", path=str(f))
    cd, cl = m.coefficients(20.0, 1500 * 2 * math.pi / 60, 0.033)
    assert cd == pytest.approx(0.7) and cl == pytest.approx(0.15)
    assert m.coefficients(50.0, 0.0, 0.033) == pytest.approx((0.8, 0.0))   # clamped
    f.write_text("speed_ms,spin_rpm,cd\n10,0,0.5\n")
    with pytest.raises(InputError, match="missing column"):
        get_aero_model("table", path=str(f))


def test_callable_and_registry():
    m = get_aero_model(lambda v, w: (0.5, 0.1))
    assert m.coefficients(10.0, 5.0, 0.03) == (0.5, 0.1)
    with pytest.raises(InputError, match="unknown model"):
        get_aero_model("nope")
    assert {"constant", "stepanek1988", "launcher2015", "table"} <= set(aero_model_names())

    @register_aero("test-only-model")
    def _f(cd=0.4):
        return get_aero_model("constant", cd=cd)
    assert get_aero_model("test-only-model").coefficients(1.0, 0.0, 0.03)[0] == 0.4


def test_callable_model_used_by_batch_path():
    from tennislab.core.flight import FlightParams, fly, fly_batch, initial_state
    p = FlightParams(aero=get_aero_model(lambda v, w: (0.6, 0.0)))
    s = initial_state((-11.0, 0, 1.0), (25.0, 0, 5.0))
    tb = fly_batch(s, p)
    tr = fly(s[:3], s[3:6], s[6:], p)
    assert tb["land_x"][0] == pytest.approx(tr.landing.x, abs=1e-5)
