"""Court, ball, atmosphere and aero models (issue 2)."""

import math

import numpy as np
import pytest

from tennislab.core.aero import aero_model_names, get_aero_model, register_aero
from tennislab.core.atmosphere import Atmosphere, air_density
from tennislab.core.ball import Ball
from tennislab.core.court import ITF_COURT, Court
from tennislab.errors import InputError
from tennislab.io.aero_table import read_aero_table


# ----------------------------------------------------------------- court
def test_net_profile():
    c = ITF_COURT
    assert c.net_height(0.0) == pytest.approx(0.914)
    assert c.y_post == pytest.approx(10.97 / 2 + 0.914)
    assert c.net_height(c.y_post) == pytest.approx(1.07)
    assert c.net_height(-c.y_post) == pytest.approx(1.07)
    assert c.net_height(c.y_post + 0.01) == 0.0
    ys = np.linspace(0, c.y_post, 50)
    assert np.all(np.diff(c.net_height(ys)) > 0)  # rises monotonically toward the posts


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
    assert b.inertia == pytest.approx(2 / 3 * b.mass * b.radius**2)
    assert b.area == pytest.approx(math.pi * b.radius**2)
    assert not Ball(mass=0.070).itf_compliant


@pytest.mark.parametrize(
    "kw", [dict(mass=-0.05), dict(mass=0.0), dict(radius=float("nan")), dict(radius=0.5), dict(inertia_factor=1.5)]
)
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
    assert cd == pytest.approx(0.55 + 1 / (22.5 + 4.2 * x**2.5) ** 0.4, rel=1e-14)
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
    v, w, cd_, cl_ = read_aero_table(str(f))
    m = get_aero_model("table", speed=v, spin=w, cd=cd_, cl=cl_)
    cd, cl = m.coefficients(20.0, 1500 * 2 * math.pi / 60, 0.033)
    assert cd == pytest.approx(0.7) and cl == pytest.approx(0.15)
    assert m.coefficients(50.0, 0.0, 0.033) == pytest.approx((0.8, 0.0))  # clamped
    f.write_text("speed_ms,spin_rpm,cd\n10,0,0.5\n")
    with pytest.raises(InputError, match="missing column"):
        read_aero_table(str(f))


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
    from tennislab.core.flight import FlightParams, fly_batch, fly_dense, initial_state

    p = FlightParams(aero=get_aero_model(lambda v, w: (0.6, 0.0)))
    s = initial_state((-11.0, 0, 1.0), (25.0, 0, 5.0))
    tb = fly_batch(s, p)
    tr = fly_dense(s[:3], s[3:6], s[6:], p)
    assert tb["land_x"][0] == pytest.approx(tr.landing.x, abs=1e-5)


# ----------------------------------------------------------------- inlined aero kernels
def _shots(n=60, seed=4):
    g = np.random.default_rng(seed)
    s = np.zeros((n, 9))
    s[:, 0], s[:, 1], s[:, 2] = -11.885, g.uniform(-3, 3, n), g.uniform(0.5, 2.8, n)
    sp, el = g.uniform(15, 60, n), np.radians(g.uniform(-6, 40, n))
    s[:, 3], s[:, 5] = sp * np.cos(el), sp * np.sin(el)
    s[:, 6:] = g.normal(size=(n, 3)) * 200.0
    return s


@pytest.mark.parametrize(
    "model",
    [
        get_aero_model("stepanek1988"),
        get_aero_model("constant", cd=0.6, cl=0.1),
        get_aero_model("launcher2015"),
        get_aero_model("cross2014"),
        get_aero_model(
            "table", speed=[5.0, 40.0], spin=[0.0, 600.0], cd=[[0.6, 0.7], [0.55, 0.65]], cl=[[0.0, 0.3], [0.0, 0.1]]
        ),
    ],
)
def test_inlined_kernels_agree_with_first_class_path(model):
    """The per-model kernels (formula inlined) compute what the shared pointer-calling kernel does."""
    from tennislab.core.aero import inline_tag
    from tennislab.core.events import COL, NCOLS, event_array
    from tennislab.core.flight import FlightParams, fly_batch
    from tennislab.core.integrators import batch_kernel_fp, serial_kernel_fp

    p = FlightParams(aero=model)
    assert inline_tag(model.kernel) is not None
    s = _shots()
    inl = fly_batch(s, p).data
    # serial and parallel kernels are separate compilations: equal up to the last bits
    assert np.nanmax(np.abs(inl - fly_batch(s, p, parallel=False).data)) < 1e-12
    for kern in (batch_kernel_fp, serial_kernel_fp):
        fp = np.empty((len(s), NCOLS))
        kern(s, model.kernel, model.params, p.consts(2e-7, 2e-7), event_array(p.events()), fp)
        assert np.array_equal(inl[:, COL["status"]], fp[:, COL["status"]])
        assert np.array_equal(inl[:, COL["n_steps"]], fp[:, COL["n_steps"]])
        # same arithmetic up to floating-point contraction: far below the integration tolerance
        assert np.nanmax(np.abs(inl - fp)) < 1e-9


def test_user_kernels_have_no_inline_tag():
    from tennislab.core.aero import inline_tag

    assert inline_tag(get_aero_model(lambda v, w: (0.6, 0.0)).kernel) is None
    assert inline_tag(None) is None


def test_inline_tag_survives_pickling_to_a_fresh_process():
    """A model shipped to a worker process keeps its tag (else workers would take another kernel)."""
    import pickle
    import subprocess
    import sys

    blob = pickle.dumps(get_aero_model("stepanek1988")).hex()
    code = (
        "import pickle,sys; from tennislab.core.aero import inline_tag; "
        f"m = pickle.loads(bytes.fromhex('{blob}')); print(type(inline_tag(m.kernel)).__name__)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.startswith("InlineStepanekKernel_")


def test_tag_classes_of_other_versions_unpickle():
    """A Numba cache index naming a tag class of another source version still loads."""
    import pickle

    from tennislab.core import aero

    with pytest.raises(AttributeError):
        aero.NoSuchThing  # noqa: B018
    ghost = aero.InlineStepanekKernel_0000000000
    assert ghost._fields == ("unused",)
    data = pickle.dumps(aero.inline_tag(aero.get_aero_model("stepanek1988").kernel))
    stale = data.replace(aero._DIGEST.encode(), b"0000000000")
    assert type(pickle.loads(stale)).__name__ == "InlineStepanekKernel_0000000000"


def test_aero_coefficients_from_python_matches_kernel():
    from tennislab.core.aero import aero_coefficients, inline_tag

    m = get_aero_model("stepanek1988")
    want = m.kernel(20.0, 300.0, 0.033, m.params)
    assert aero_coefficients(inline_tag(m.kernel), 20.0, 300.0, 0.033, m.params) == want
    assert aero_coefficients(m.kernel, 20.0, 300.0, 0.033, m.params) == want


def test_capped_lift_is_a_smooth_minimum_through_zero():
    """C_L of a capped linear-lift model: 0 without spin, within 0.01 of min(c_l S, cap) everywhere,
    within 0.00052 of c_l S up to S = 0.6, rising with spin, and the batch tolerance of a capped model."""
    from tennislab.core.aero import CAPPED_BATCH_TOL, get_aero_model

    m = get_aero_model("choppin2018")
    r, v = 0.0335, 30.0
    w = np.linspace(0.0, 2000.0, 4001)
    _, cl = m.coefficients(v, w, r)
    s = r * w / v
    assert cl[0] == 0.0
    assert np.all(np.diff(cl) > 0)
    assert np.max(np.abs(cl - np.minimum(0.6 * s, 0.5))) <= 0.0100001
    low = s <= 0.6
    assert np.max(np.abs(cl[low] - 0.6 * s[low])) < 5.2e-4
    # the blend's zone is held to a tighter error inside the kernels: no tighter tolerance than uncapped
    assert m.batch_tol == get_aero_model("cross2014").batch_tol == 2e-7
    assert get_aero_model("cross2014", cl_max=0.5).batch_tol == 2e-7
    assert get_aero_model("tennislab2026").batch_tol == CAPPED_BATCH_TOL  # kinks at its knots
