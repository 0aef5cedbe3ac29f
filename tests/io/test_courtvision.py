"""CourtVision readers: serves, ball trajectory, point by point (issue 13 section 1), fuzzed."""

import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tennislab.errors import InputError
from tennislab.io.courtvision import (
    MAX_BYTES,
    POSITIONS,
    SERVE_NUMERIC,
    parse_ball_trajectory,
    parse_pbp,
    parse_serves,
    read_ball_trajectory,
    read_pbp,
    read_serves,
)


def _realdata() -> Path:
    """The real data (``$TENNISLAB_REALDATA``, set by tests/conftest.py)."""
    return Path(os.environ["TENNISLAB_REALDATA"])


REALDATA = _realdata()

HEADER = (
    "match,point_ID,serve_num,spd,serve_type,spin_rpm,x_ball_serve_impact,y_ball_serve_impact,z_ball_serve_impact,"
    "x_net_serve,y_net_serve,z_net_serve,x_serve_bounce,y_serve_bounce,z_serve_bounce,point_end_type,error_type"
)
ROW = (
    "atp_australian_open_2020MS157,1_1_3_2,2,148.0,Slice,1855.5,-11.531,-0.462,3.068,0.0,0.742,1.355,"
    "5.474,1.681,0.034,Forced Error,"
)
GOOD = HEADER + "\n" + ROW + "\n" + ROW.replace("1_1_3_2", "1_1_4_1").replace("Slice", "") + "\n"


def test_serves_good():
    d = parse_serves(GOOD)
    assert d["spd"].tolist() == [148.0, 148.0]
    assert d["serve_type"].tolist() == ["Slice", ""]
    assert d["line"].tolist() == [2, 3]
    for c in SERVE_NUMERIC:
        assert d[c].dtype == float


def test_serves_optional_columns_absent():
    header = ",".join(h for h in HEADER.split(",") if h not in ("serve_type", "point_end_type", "error_type"))
    row = ",".join(
        v for h, v in zip(HEADER.split(","), ROW.split(",")) if h not in ("serve_type", "point_end_type", "error_type")
    )
    d = parse_serves(header + "\n" + row + "\n")
    assert d["serve_type"].tolist() == [""]


@pytest.mark.parametrize(
    "text,msg",
    [
        ("", "empty"),
        (HEADER + "\n", "no data rows"),
        (HEADER.replace("spd,", "") + "\n" + ROW, "missing column"),
        (HEADER + ",spd\n" + ROW + ",1", "duplicate column"),
        (HEADER + "\n" + ROW.replace("148.0", "fast"), "line 2, column 'spd': not a number"),
        (HEADER + "\n" + ROW.replace("148.0", "NA"), "line 2, column 'spd': missing value"),
        (HEADER + "\n" + ROW.replace("148.0", "nan"), "missing value"),
        (HEADER + "\n" + ROW.replace("148.0", "inf"), "finite"),
        (HEADER + "\n" + ROW.replace("148.0", "1e300"), "finite"),
        (HEADER + "\n" + ROW.replace("atp_australian_open_2020MS157", ""), "column 'match': missing value"),
        (HEADER + "\n" + ROW + ",extra", "field"),
        (b"\xff\xfe" + GOOD.encode(), "UTF-8"),
        (GOOD + "\x00", "NUL"),
        (HEADER + '\n"unterminated' + ROW, "CSV|field"),
    ],
)
def test_serves_errors(text, msg):
    with pytest.raises(InputError, match=msg):
        parse_serves(text, name="s.csv")


def test_errors_are_one_line():
    with pytest.raises(InputError) as e:
        parse_serves(HEADER + "\n" + ROW.replace("148.0", "x\ny"))
    assert "\n" not in str(e.value)


def test_size_limit(tmp_path):
    p = tmp_path / "big.csv"
    with open(p, "wb") as fh:
        fh.write(GOOD.encode())
        fh.seek(MAX_BYTES + 10)
        fh.write(b"\n")
    with pytest.raises(InputError, match="larger than"):
        read_serves(p)


TRAJ = (
    "point_ID,set_num,game_num,point_num,serve_num,strike_index,position,x,y,z\n"
    "1_1_1_1,1,1,1,1,1,hit,-11.459,-0.771,2.868\n"
    "1_1_1_1,1,1,1,1,,bounce,7.651,4.32,0.033\n"
)


def test_trajectory_good_and_errors():
    d = parse_ball_trajectory(TRAJ)
    assert d["position"].tolist() == ["hit", "bounce"]
    assert d["strike_index"][0] == 1 and np.isnan(d["strike_index"][1])
    with pytest.raises(InputError, match="position"):
        parse_ball_trajectory(TRAJ.replace("bounce", "volley"))
    with pytest.raises(InputError, match="column 'x'"):
        parse_ball_trajectory(TRAJ.replace("7.651", ""))
    assert set(POSITIONS) == {"hit", "peak", "net", "bounce", "last"}


PBP = (
    "point_ID,serve_num,serve_speed_kph,fault_distance_missed_m,serve_type,spin_rpm,trapped_by_net\n"
    "1_1_1_1,1,52.32 KPH,1.27 Metre,Slice,NA,False\n"
    "1_1_1_2,2,175 KPH,NA,,1188.99,True\n"
)


def test_pbp_units_and_missing():
    d = parse_pbp(PBP)
    assert d["serve_speed_kph"].tolist() == [52.32, 175.0]
    assert d["fault_distance_missed_m"][0] == 1.27 and np.isnan(d["fault_distance_missed_m"][1])
    assert np.isnan(d["spin_rpm"][0])
    assert d["trapped_by_net"].tolist() == ["False", "True"]
    with pytest.raises(InputError, match="serve_speed_kph"):
        parse_pbp(PBP.replace("175 KPH", "fast KPH"))
    with pytest.raises(InputError, match="missing column"):
        parse_pbp(PBP.replace("serve_speed_kph", "speed"))


_fuzz = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@_fuzz
@given(st.one_of(st.text(max_size=400), st.binary(max_size=400)))
def test_fuzz_any_input_is_parsed_or_refused(data):
    for parse in (parse_serves, parse_ball_trajectory, parse_pbp):
        try:
            parse(data)
        except InputError as exc:
            assert "\n" not in str(exc)


_cell = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.sampled_from(["", "NA", "nan", "1 KPH", "x", '"', ",", "1e999"]),
    st.text(max_size=6),
)


@_fuzz
@given(st.lists(st.lists(_cell, min_size=17, max_size=17), min_size=1, max_size=5))
def test_fuzz_serves_rows(rows):
    text = HEADER + "\n" + "\n".join(",".join(r) for r in rows) + "\n"
    try:
        d = parse_serves(text)
    except InputError as exc:
        assert "\n" not in str(exc)
    else:
        for c in SERVE_NUMERIC:
            assert np.all(np.isfinite(d[c]))


@pytest.mark.skipif(not REALDATA.is_dir(), reason="../shared/realdata is absent")
def test_real_files():
    s = read_serves(REALDATA / "courtvision_serves.csv")
    assert s["spd"].size == 13140
    for m in ("atp_australian_open_2020MS701", "wta_australian_open_2021WS701"):
        t = read_ball_trajectory(REALDATA / "courtvision" / f"{m}_ball_trajectory.csv")
        p = read_pbp(REALDATA / "courtvision" / f"{m}_pbp.csv")
        assert t["x"].size > 1000 and p["serve_speed_kph"].size > 100
        assert np.nanmax(p["serve_speed_kph"]) < 260
