"""The one JSON cleaner, the result base classes, and ``to_frame()`` on every result that has rows."""

import dataclasses
import importlib
import json
import math
import pkgutil
from pathlib import Path

import numpy as np
import pytest

import tennislab
from tennislab.errors import InputError
from tennislab.results import UNIT_SUFFIXES, Result, Table, jsonable, trajectory_rows

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"


@dataclasses.dataclass(frozen=True)
class _Table(Table):
    x: np.ndarray
    name: str = "t"

    COLUMNS = ("x",)
    FRAME_COLUMNS = {"x": "x_m"}

    def rows(self):
        return [{"x": float(v)} for v in self.x]


def test_jsonable_cleans_numpy_and_non_finite():
    out = jsonable(
        {"a": np.float64(1.5), "b": float("nan"), "c": np.arange(3), "d": (np.bool_(True), math.inf), 1: np.int32(4)}
    )
    assert out == {"a": 1.5, "b": None, "c": [0, 1, 2], "d": [True, None], "1": 4}
    json.dumps(out, allow_nan=False)


def test_result_to_dict_and_frame():
    r = _Table(np.array([1.0, np.nan]))
    assert r.to_dict() == {"x": [1.0, None], "name": "t"}
    assert jsonable([r]) == [{"x": [1.0, None], "name": "t"}]
    pd = pytest.importorskip("pandas")
    f = r.to_frame()
    assert isinstance(f, pd.DataFrame) and list(f.columns) == ["x_m"] and list(f["x_m"][:1]) == [1.0]
    empty = _Table(np.array([])).to_frame()
    assert len(empty) == 0 and list(empty.columns) == ["x_m"]


def test_too_deep_is_an_input_error():
    deep: list = []
    cur = deep
    for _ in range(100):
        cur.append([])
        cur = cur[0]
    with pytest.raises(InputError, match="deeper"):
        jsonable(deep)


# ------------------------------------------------------------------ every result
def _all_results() -> list[type]:
    """Every Result class of the package (each module imported)."""
    for m in pkgutil.walk_packages(tennislab.__path__, "tennislab."):
        domain = ("trajectory", "serve", "linecall", "launcher", "calibrate", "batch", "core", "results")
        if m.name.split(".")[1] in domain and not m.name.endswith("__main__"):
            importlib.import_module(m.name)
    out, todo = [], [Result]
    while todo:
        for sub in todo.pop().__subclasses__():
            if sub.__module__.startswith("tennislab.") and sub is not Table:
                out.append(sub)
            todo.append(sub)
    return sorted(set(out), key=lambda c: c.__qualname__)


def _serves_csv() -> str:
    return str(EXAMPLES / "calibration" / "synthetic_serves.csv")


def _tracks():
    from tennislab.io.track import read_track

    return [read_track(str(EXAMPLES / "calibration" / f"track_{i}.csv")) for i in (1, 2, 3)]


def _track_call(name: str, **kw):
    from tennislab.io.track import read_track
    from tennislab.linecall import call_track

    tr = read_track(str(EXAMPLES / "tracks" / name))
    return call_track(tr.t, tr.xyz, tr.sigma, **kw)


def _flight():
    from tennislab.trajectory import fly

    return fly((-11.885, 0.0, 1.0), speed_kmh=120, elevation_deg=6, spin_rpm=2500, spin_axis="topspin", bounces=2)


def _serve():
    from tennislab.serve import simulate

    return simulate("pro", 46, 21, trajectory=True, advice=False)


def _window():
    from tennislab.serve import window

    return window("pro", step=10)


def _ball_window():
    from tennislab.serve import BallLaunch, ball_window

    return ball_window("pro", BallLaunch(50.0, 2500.0, -5.0), step=2.0)


def _windows():
    from tennislab.serve import windows

    return windows("all", step=15)


def _mc():
    from tennislab.serve import monte_carlo

    return monte_carlo("pro", 46, 21, n=200, samples=True)


def _impact():
    from tennislab.serve import impact

    return impact(40, 21, face_angle=35, history=True)


def _rally():
    from tennislab.linecall import call_rally

    return call_rally(EXAMPLES / "points" / "synthetic_points.json")


def _validation():
    from tennislab.calibrate import validate_serves

    return validate_serves(_serves_csv(), models=["choppin2018"])


def _calibration():
    from tennislab.calibrate import calibrate_serves

    return calibrate_serves(_serves_csv(), fit="cd", split="parity")


def _sensitivity():
    from tennislab.calibrate import sensitivity_serves

    return sensitivity_serves(_serves_csv(), cd=(0.6,), cl=(0.6,), spin_axes=("topspin",))


def _track_calibration():
    from tennislab.calibrate import calibrate_tracks

    return calibrate_tracks(_tracks(), fit="cd")


def _surface():
    from tennislab.calibrate import calibrate_surface
    from tennislab.core.bounce import bounce
    from tennislab.core.surfaces import get_surface

    rng = np.random.default_rng(1)
    vin = np.column_stack([rng.uniform(15, 30, 20), rng.uniform(-2, 2, 20), rng.uniform(-9, -4, 20)])
    win = np.column_stack([np.zeros(20), rng.uniform(-200, 200, 20), np.zeros(20)])
    ball = tennislab.core.ball.Ball()
    vout = np.array([bounce(v, w, get_surface("clay"), ball).velocity_out for v, w in zip(vin, win)])
    return calibrate_surface(vin, win, vout + rng.normal(0, 0.1, vout.shape), base="hard")


def _drill():
    from tennislab.launcher import compile_drill
    from tennislab.launcher.drill_schema import load_drill

    return compile_drill(load_drill("baseline_rally"))


def _play():
    from tennislab.launcher.hitsdb_results import PlayResult

    keys = ("index", "time_s", "height_m", "speed_kmh", "elevation_deg", "heading_deg", "spin_rpm", "spin_axis_deg")
    keys += ("rpm1", "rpm2", "interval_s", "landing_x", "landing_y", "miss_mm", "in_zone")  # play --jsonl's
    seq = [{"shot": r["name"], **{k: r[k] for k in keys}, "hit_id": 1} for r in _drill().rows()]
    return PlayResult("baseline_rally", "baseline_rally", "shipped", "x.sqlite", "0" * 12, {}, [], seq)


def _drill_list(tmp_path):
    from tennislab.launcher import HitsDB

    return HitsDB(str(tmp_path / "d.sqlite")).list_drills()


def _drills_imported(tmp_path):
    from tennislab.launcher import HitsDB

    return HitsDB(str(tmp_path / "d.sqlite")).import_drills(["baseline_rally"])


def _young():
    from tennislab.launcher.materials import young_modulus

    return young_modulus([49.0, 98.0], [0.004, 0.008], 0.067)


def _friction():
    from tennislab.launcher.materials import friction_coefficient

    return friction_coefficient([39.0, 30.0], [0.01, 0.012])


slow = pytest.mark.slow
#: how to get each table (cheap inputs); the slow ones run in ``make test`` only
FACTORIES = {
    "FlightResult": pytest.param(_flight),
    "ServeResult": pytest.param(_serve),
    "ServeWindow": pytest.param(_window),
    "ServeWindows": pytest.param(_windows, marks=slow),
    "BallWindow": pytest.param(_ball_window),
    "MonteCarloResult": pytest.param(_mc),
    "ImpactSummary": pytest.param(_impact),
    "TrackCall": pytest.param(lambda: _track_call("serve_t_line.csv", target="deuce-box")),
    "RallyCall": pytest.param(_rally, marks=slow),
    "ValidationResult": pytest.param(_validation, marks=slow),
    "CalibrationResult": pytest.param(_calibration, marks=slow),
    "SensitivityResult": pytest.param(_sensitivity, marks=slow),
    "TrackCalibrationResult": pytest.param(_track_calibration, marks=slow),
    "SurfaceCalibrationResult": pytest.param(_surface),
    "CompiledDrill": pytest.param(_drill),
    "PlayResult": pytest.param(_play),
    "DrillList": pytest.param(_drill_list),
    "DrillsImported": pytest.param(_drills_imported),
    "YoungResult": pytest.param(_young),
    "FrictionResult": pytest.param(_friction),
}
#: frame columns that are labels or dimensionless (counts, ratios, probabilities, flags, identifiers)
UNITLESS = {
    *("player", "success", "category", "landed", "reason", "segment", "outlier", "model", "match"),
    *("point_ID", "serve_num", "serve_type", "part", "cd", "cl", "cd_s", "spin_axis", "speed_scale", "n"),
    *("track", "bounce", "point", "shot", "shot_no", "team", "stroke", "serve", "target", "call"),
    *("provisional_call", "reason", "p_in", "fit_outliers", "fit_n_points", "fit_drag_scale", "net_contact"),
    *("n_bounces", "tracker_call", "call_agrees", "index", "name", "type", "zone", "in_zone", "ok", "key"),
    *("source", "revision", "n_shots", "n_distinct", "hit_id", "friction_coefficient", "stored", "shipped"),
    *("title", "description", "file", "path", "sha256", "shots", "distinct", "imported", "shadowed"),
    *("filename", "format_version", "imported_utc"),
}


def test_every_result_with_rows_is_a_table_and_the_others_have_no_frame():
    classes = _all_results()
    tables = {c.__name__ for c in classes if issubclass(c, Table)}
    assert tables == set(FACTORIES), "a Table without a to_frame test, or a test of a class that is gone"
    for c in classes:
        if not issubclass(c, Table):  # no rows: no to_frame that could only fail
            assert not hasattr(c, "to_frame") and not hasattr(c, "rows"), c


@pytest.mark.parametrize("make", list(FACTORIES.values()), ids=list(FACTORIES))
def test_to_frame_on_every_table(make, tmp_path, monkeypatch):
    pd = pytest.importorskip("pandas")
    monkeypatch.chdir(tmp_path)
    res = make(tmp_path) if make.__code__.co_argcount else make()
    rows = res.rows()
    frame = res.to_frame()
    assert isinstance(frame, pd.DataFrame) and len(frame) == len(rows) > 0
    keys = list(dict.fromkeys(k for r in rows for k in r))
    assert list(frame.columns) == [res.FRAME_COLUMNS.get(k, k) for k in keys]
    assert set(res.FRAME_COLUMNS) <= set(keys), "FRAME_COLUMNS renames a key the rows do not have"
    assert set(rows[0]) <= set(res.COLUMNS) or not res.COLUMNS, "COLUMNS lists the row keys"
    unnamed = [c for c in frame.columns if not c.endswith(UNIT_SUFFIXES) and c not in UNITLESS]
    assert not unnamed, f"{type(res).__name__}: columns without a unit: {unnamed}"


def test_a_flights_frame_samples_every_segment():
    res = _flight()
    f = res.to_frame()
    assert list(f["segment"].unique()) == [0, 1, 2]
    first = f.iloc[0]
    assert first["t_s"] == 0.0 and first["x_m"] == -11.885 and first["z_m"] == 1.0
    assert first["speed_ms"] == pytest.approx(120 / 3.6) and first["spin_rpm"] == pytest.approx(2500)
    seg0 = f[f["segment"] == 0]
    assert np.allclose(np.diff(seg0["t_s"])[:-1], 0.01) and seg0["z_m"].iloc[-1] == pytest.approx(0.0335, abs=1e-9)
    assert seg0["t_s"].iloc[-1] == pytest.approx(res.to_dict()["landing"]["t"], abs=1e-12)
    v = np.linalg.norm(f[["vx_ms", "vy_ms", "vz_ms"]].to_numpy(), axis=1)
    assert np.allclose(v, f["speed_ms"])
    fine = res.to_frame(step_s=0.001)
    assert len(fine) > 9 * len(f)
    with pytest.raises(InputError, match="step_s"):
        res.rows(step_s=0.0)


def test_a_tracks_frame_has_the_fits_residuals():
    res = _track_call("serve_t_line.csv", target="deuce-box")
    f = res.to_frame()
    d = res.to_dict()
    assert int(f["outlier"].sum()) == d["fit"]["outliers"]
    assert sorted(f.index[f["outlier"]]) == d["fit"]["outlier_rows"]
    assert set(f["segment"]) <= {"before", "after", "unused"} and (f["segment"] == "before").sum() == d["fit"]["n_pre"]
    used = f[f["segment"] != "unused"]
    rms = math.sqrt(float(np.mean(used["residual_mm"] ** 2)))
    assert rms == pytest.approx(d["fit"]["rms_mm"], rel=1e-9)
    assert f["t_s"].iloc[0] == pytest.approx(res.track[0][0] + res.time_offset)


def test_a_serves_frame_is_its_flight_to_the_bounce():
    res = _serve()
    f = res.to_frame()
    assert f["z_m"].iloc[0] == pytest.approx(res.player.impact_height)
    assert f["speed_ms"].iloc[0] == pytest.approx(res.speed) and f["t_s"].iloc[-1] == pytest.approx(res.landing["t"])
    from tennislab.serve import simulate

    with pytest.raises(InputError, match="trajectory=True"):
        simulate("pro", 46, 21, advice=False).to_frame()


def test_trajectory_rows_end_on_the_segment_end():
    class Seg:
        t = np.array([1.0, 1.025])

        @staticmethod
        def sol(ts):
            return np.vstack([ts, 0 * ts, 0 * ts, 1 + 0 * ts, 0 * ts, 0 * ts, 0 * ts, 0 * ts, 0 * ts])

    rows = trajectory_rows([Seg()], 0.01)
    assert [r["t_s"] for r in rows] == pytest.approx([1.0, 1.01, 1.02, 1.025])
    assert rows[-1]["x_m"] == pytest.approx(1.025) and rows[0]["speed_ms"] == 1.0


def test_call_rally_takes_a_path_as_well_as_read_points():
    from tennislab.io.hawkeye import read_points
    from tennislab.linecall import call_rally

    path = EXAMPLES / "points" / "synthetic_points.json"
    first = read_points(str(path))[:1]
    assert call_rally(first).to_dict()["summary"]["n_shots"] == 3
    with pytest.raises(InputError, match=r"nope\.json: [Nn]o such file"):
        call_rally("nope.json")
    with pytest.raises(InputError, match="^points: expected a point file, a folder of them or read points"):
        call_rally([{"samples": []}])


def test_as_dict_is_the_old_name_of_to_dict():
    """One name per concept: ``to_dict()`` everywhere; ``as_dict()`` still works, with a warning."""
    from tennislab.launcher import Settings

    s = Settings(speed_kmh=80.0, spin_rpm=1000.0, spin_axis_deg=0.0, elevation_deg=10.0, heading_deg=0.0, height_m=1.0)
    with pytest.warns(DeprecationWarning, match=r"Settings.as_dict\(\) is now to_dict\(\)"):
        assert s.as_dict() == s.to_dict()
