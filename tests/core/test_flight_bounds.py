"""Guard rails of the flight (issues 16, 17): physical ranges, bounded integration, no NaN answered."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tennislab.core import flight
from tennislab.core.aero import get_aero_model
from tennislab.core.events import (
    COL,
    NCOLS,
    STATUS_BAD_START,
    STATUS_FAILED,
    STATUS_NAMES,
    STATUS_NO_LANDING,
    STATUS_OK,
    STATUS_OUT_OF_RANGE,
    event_array,
)
from tennislab.core.flight import MAX_STEPS, FlightParams, fly_batch, fly_dense
from tennislab.core.integrators import serial_kernel_fp
from tennislab.errors import InputError
from tennislab.io.aero_table import read_aero_table

POS = (-11.885, 0.0, 1.0)


@pytest.mark.parametrize(
    "kw,match",
    [
        (dict(velocity=(1e160, 0, 0)), r"^velocity: speed 1e\+160 m/s is outside the allowed range \[0, 100\] m/s$"),
        (dict(velocity=(1e9, 0, 7)), r"^velocity: speed 1e\+09 m/s .*\[0, 100\]"),
        (dict(velocity=(101.0, 0, 0)), r"^velocity: .*\[0, 100\]"),
        (dict(spin=(0, 1100.0, 0)), r"^spin: 10504.2 rpm is outside the allowed range \[0, 10000\] rpm$"),
        (dict(position=(-11.0, 0.0, 0.01)), r"^position: z = 0.01 m is outside the allowed range \[0.0335, 1000\] m"),
        (dict(position=(-11.0, 0.0, -1.0)), r"^position: z = -1 m"),
        (dict(position=(-2e3, 0.0, 1.0)), r"^position: x = -2000 m is outside the allowed range \[-1000, 1000\] m$"),
        (dict(velocity=(np.nan, 0, 0)), r"^velocity\[0\]: must be a finite number"),
    ],
)
def test_fly_refuses_absurd_launches(kw, match):
    args = dict(position=POS, velocity=(30.0, 0.0, 5.0), spin=(0.0, 0.0, 0.0)) | kw
    with pytest.raises(InputError, match=match):
        fly_dense(args["position"], args["velocity"], args["spin"])


@pytest.mark.parametrize(
    "build,match",
    [
        (
            lambda: FlightParams.from_options(mass=1e-12),
            r"^mass: 1e-12 kg is outside the allowed range \[0.01, 0.5\] kg$",
        ),
        (lambda: FlightParams.from_options(radius=0.5), r"^radius: .*\[0.01, 0.1\] m$"),
        (lambda: FlightParams.from_options(air_density=5), r"^air_density: .*\[0.0, 2.0\]"),
        (lambda: FlightParams.from_options(gravity=-1), r"^gravity: "),
        (
            lambda: FlightParams.from_options(spin_decay=50),
            r"^spin_decay: 50 1/s is outside the allowed range \[0.0, 10.0\]",
        ),
        (lambda: FlightParams.from_options(t_max=1e9), r"^t_max: "),
    ],
)
def test_physics_parameters_are_range_checked(build, match):
    with pytest.raises(InputError, match=match):
        build()


def test_batch_marks_bad_rows_and_answers_the_good_ones():
    S = np.array(
        [
            [-11.885, 0, 1.0, 1e160, 0, 0, 0, 0, 0],  # the hang of issue 16
            [-11.885, 0, 1.0, 1e9, 0, 7, 0, 0, 0],  # "lands at 800 m"
            [-11.885, 0, 1.0, 30, 0, 5, 0, 2000, 0],  # 19,099 rpm
            [-11.885, 0, 1.0, np.inf, 0, 5, 0, 0, 0],
            [-11.885, 0, -1.0, 30, 0, 5, 0, 0, 0],  # below the ground
            [-5e3, 0, 1.0, 30, 0, 5, 0, 0, 0],
            [-11.885, 0, 1.0, 30, 0, 5, 0, 100, 0],
        ]
    )
    tb = fly_batch(S)
    assert list(tb["status"]) == [4, 4, 4, 2, 2, 4, 0]
    assert list(tb.status_name) == ["out of range"] * 3 + ["bad start"] * 2 + ["out of range", "landed"]
    assert np.isnan(tb.data[:6, COL["land_t"] : COL["land_wz"] + 1]).all()
    assert (tb["n_steps"][:6] == 0).all() and tb["land_x"][6] > 0
    with pytest.raises(InputError, match="^states: "):
        fly_batch(np.zeros((3, 8)))
    with pytest.raises(InputError, match="^states: "):
        fly_batch([["a"] * 9])
    with pytest.raises(InputError, match="^rtol: "):
        fly_batch(S, rtol=0.0)


_any = st.floats(allow_nan=True, allow_infinity=True, width=64)
_big = st.one_of(_any, st.floats(-1e6, 1e6), st.floats(-120, 120))


@settings(max_examples=150, deadline=None)
@given(st.lists(_big, min_size=9, max_size=9), st.booleans())
def test_no_input_hangs_or_answers_nan(row, obstacle):
    """Whatever the row, the kernel returns within the step bound and a landed row is finite."""
    s = np.array(row, dtype=float)[None, :]
    tb = fly_batch(s, FlightParams(net_obstacle=obstacle))
    status = int(tb["status"][0])
    assert 0 <= status < len(STATUS_NAMES)
    assert 0 <= tb["n_steps"][0] <= MAX_STEPS
    if status == STATUS_OK:
        assert np.all(np.isfinite(tb.data[0, COL["land_t"] : COL["land_wz"] + 1]))
        assert np.hypot(tb["land_x"][0] - s[0, 0], tb["land_y"][0] - s[0, 1]) < 500.0


@settings(max_examples=40, deadline=None)
@given(
    speed=st.floats(0.0, 100.0),
    elev=st.floats(-90.0, 90.0),
    spin=st.floats(0.0, 10_000.0),
    z=st.floats(0.0335, 20.0),
    aero=st.sampled_from(["stepanek1988", "launcher2015", "constant"]),
)
def test_whole_allowed_range_lands_finite_in_both_paths(speed, elev, spin, z, aero):
    e = math.radians(elev)
    v = (speed * math.cos(e), 0.0, speed * math.sin(e))
    w = (0.0, spin * 2 * math.pi / 60, 0.0)
    p = FlightParams(aero=get_aero_model(aero))
    tr = fly_dense((-11.885, 0.0, z), v, w, p)
    tb = fly_batch(np.array([[-11.885, 0.0, z, *v, *w]]), p)
    assert tr.landing is not None and np.all(np.isfinite(tr.landing.position))
    assert tb["status"][0] == STATUS_OK and tb["n_steps"][0] < 2000
    assert tb["land_x"][0] == pytest.approx(tr.landing.x, abs=1e-4)


def test_kernel_step_bound_counts_rejected_steps():
    """With the range checks lifted, the overflowing launch of issue 16 stops at the step bound
    (rejections counted); a tiny bound stops a normal flight too."""
    p = FlightParams()
    ev = event_array(p.events())
    c = p.consts(2e-7, 2e-7)._replace(max_speed=math.inf, max_spin=math.inf, max_position=math.inf)
    S = np.array([[-11.885, 0, 1.0, 1e160, 0, 0, 0, 0, 0], [-11.885, 0, 1.0, 1e300, 1e300, 0, 0, 0, 0]])
    out = np.empty((2, NCOLS))
    serial_kernel_fp(S, p.aero.kernel, p.aero.params, c, ev, out)
    assert list(out[:, COL["status"]]) == [STATUS_FAILED, STATUS_FAILED]
    assert np.isnan(out[:, COL["land_x"]]).all()
    c3 = p.consts(2e-7, 2e-7)._replace(max_steps=3.0)
    out1 = np.empty((1, NCOLS))
    serial_kernel_fp(np.array([[-11.885, 0, 1.0, 20, 0, 15, 0, 0, 0]]), p.aero.kernel, p.aero.params, c3, ev, out1)
    assert out1[0, COL["status"]] == STATUS_FAILED and out1[0, COL["n_steps"]] <= 3


def test_scipy_path_has_an_evaluation_budget(monkeypatch):
    monkeypatch.setattr(flight, "MAX_RHS_EVALS", 40)
    with pytest.raises(InputError, match="^flight: no result within 40 evaluations"):
        fly_dense(POS, (30.0, 0.0, 5.0))


def test_no_landing_within_t_max_is_a_status_not_a_hang():
    p = FlightParams(t_max=0.2)
    assert fly_dense(POS, (20.0, 0.0, 10.0), params=p).landing is None
    assert fly_batch(np.array([[*POS, 20.0, 0.0, 10.0, 0, 0, 0]]), p)["status"][0] == STATUS_NO_LANDING


def test_bad_start_status_for_nan_rows():
    tb = fly_batch(np.array([[np.nan] * 9]))
    assert tb["status"][0] == STATUS_BAD_START and tb.net_result[0] == "none"
    assert STATUS_OUT_OF_RANGE == 4


# ----------------------------------------------------------------- aero tables
def _table(tmp_path, rows, name="t.csv", mode="w"):
    f = tmp_path / name
    if mode == "wb":
        f.write_bytes(rows)
    else:
        f.write_text("speed_ms,spin_rpm,cd,cl\n" + "\n".join(rows) + "\n")
    return str(f)


def test_aero_table_coefficients_are_range_checked(tmp_path):
    f = _table(tmp_path, ["10,0,0.5,0", "10,3000,0.5,1e6", "30,0,0.5,0", "30,3000,0.5,0.2"])
    with pytest.raises(InputError, match=r"^aero_table: cl = 1e\+06 at speed 10 m/s, spin 3000 rpm .*\[-2, 2\]$"):
        FlightParams.from_options(aero="table", aero_table=read_aero_table(f))
    with pytest.raises(InputError, match=r"^aero_table: cd = -0.1 "):
        get_aero_model("table", speed=[10.0], spin=[0.0], cd=[[-0.1]], cl=[[0.0]])
    with pytest.raises(InputError, match=r"^aero_table: speed 500 m/s is outside"):
        get_aero_model("table", speed=[10.0, 500.0], spin=[0.0], cd=[[0.5], [0.5]], cl=[[0.0], [0.0]])


@pytest.mark.parametrize(
    "content,match",
    [
        (b"speed_ms,spin_rpm,cd,cl\n10,0,0.5,0\n\xff\xfe,0,0.5,0\n", "not UTF-8 text"),
        (bytes(range(256)) * 8, "not UTF-8 text"),
        (b"speed_ms,spin_rpm,cd,cl\n10,0\x00,0.5,0\n", "binary data"),
        (b"", "missing column"),
        (b"speed_ms,spin_rpm,cd,cl\n", "no data rows"),
        (b"speed_ms,spin_rpm,cd,cl\n10,0,nan,0\n", "line 2: values must be finite"),
    ],
)
def test_malformed_aero_table_files_are_one_line(tmp_path, content, match):
    f = _table(tmp_path, content, mode="wb")
    with pytest.raises(InputError, match=f"^aero_table: {f}.*{match}") as e:
        read_aero_table(f)
    assert "\n" not in str(e.value)


def test_huge_aero_table_is_refused_without_reading_it(tmp_path):
    f = tmp_path / "huge.csv"
    with open(f, "wb") as fh:
        fh.truncate(64 * 1024 * 1024)  # sparse: no disk used
    with pytest.raises(InputError, match="larger than"):
        read_aero_table(str(f))
    with pytest.raises(InputError, match="(?i)no such file"):
        read_aero_table(str(tmp_path / "missing.csv"))
    with pytest.raises(InputError, match="directory"):
        read_aero_table(str(tmp_path))
    assert os.path.getsize(f) == 64 * 1024 * 1024


@pytest.mark.parametrize("elev", [1.0, 19.0, 45.0])
def test_the_limits_themselves_are_allowed_whatever_the_round_off(elev):
    """Hypothesis found it: 100 m/s at 19 deg comes back from its components as 100.00000000000001 m/s
    and was refused as 'outside [0, 100]'; the same for 10,000 rpm about a tilted axis."""
    e = math.radians(elev)
    v = (100.0 * math.cos(e), 0.0, 100.0 * math.sin(e))
    w = tuple(10_000 * 2 * math.pi / 60 * np.array([0.0, math.cos(e), math.sin(e)]))
    p = FlightParams(aero=get_aero_model("stepanek1988"))
    assert fly_dense((-11.885, 0.0, 1.0), v, w, p).landing is not None
    assert fly_batch(np.array([[-11.885, 0.0, 1.0, *v, *w]]), p)["status"][0] == STATUS_OK
    with pytest.raises(InputError, match="outside the allowed range"):
        fly_dense((-11.885, 0.0, 1.0), (100.001, 0.0, 0.0), (0.0, 0.0, 0.0), p)


@pytest.mark.parametrize("dz", [0.0, 7e-18, 1e-13, 1e-9])
def test_a_launch_on_the_ground_to_round_off_finds_its_real_landing(dz):
    """Hypothesis found it: a ball launched 7e-18 m above z = r and rising "landed" at t = 1e-14 s in
    the batch path (a root in the interpolant's round-off); both paths now agree on the real hop."""
    e = math.radians(1.0)
    v = (math.cos(e), 0.0, math.sin(e))
    p = FlightParams(aero=get_aero_model("stepanek1988"))
    z = p.ball.radius + dz
    tr = fly_dense((-11.885, 0.0, z), v, (0.0, 0.0, 0.0), p)
    tb = fly_batch(np.array([[-11.885, 0.0, z, *v, 0.0, 0.0, 0.0]]), p)
    assert tr.landing.t > 3e-3 and tb["land_t"][0] == pytest.approx(tr.landing.t, rel=1e-6)
