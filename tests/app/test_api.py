"""API tests of ``tennislab app`` (FastAPI TestClient): every endpoint, good and bad input."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

pytest.importorskip("fastapi")
pytest.importorskip("httpx")

from tennislab.app import fields as F
from tennislab.app.server import STATIC
from tennislab.core.court import ITF_COURT
from tennislab.core.flight import FlightParams
from tennislab.core.flight import fly_dense as core_fly
from tennislab.results import jsonable
from tennislab.serve import default_serve
from tennislab.trajectory import fly
from tennislab.units import DEG, KMH, RPM


def err(r, status=422) -> str:
    assert r.status_code == status, (r.status_code, r.text)
    body = r.json()
    assert set(body) == {"error"}
    assert "\n" not in body["error"] and "Traceback" not in body["error"]
    return body["error"]


# ----------------------------------------------------------------- meta and static files
def test_meta_lists_forms_court_and_modules(client):
    m = client.get("/api/meta").json()
    assert set(m["forms"]) >= {"flight", "serve", "window", "aim", "linecall"}
    assert m["pool"]["workers"] >= 1 and m["limits"]["json_depth"] == F.MAX_JSON_DEPTH
    assert m["court"]["lines"] == {k: list(v) for k, v in ITF_COURT.lines().items()}
    for name, spec in m["forms"].items():
        for f in spec:
            assert f["kind"] in ("float", "int", "choice", "bool")
            if f["kind"] == "choice":
                assert f["default"] in f["choices"], (name, f["name"])
            else:  # every default passes its own validation
                assert F.FORMS[name].by_name()[f["name"]].parse(f["default"]) == f["default"]
    assert m["players"]["professional"] == {"height": 3.0, "racket_speed": 40.0}


def test_page_and_assets_served_offline(client):
    r = client.get("/")
    assert r.status_code == 200 and "text/html" in r.headers["content-type"]
    csp = r.headers["content-security-policy"]
    assert "default-src 'self'" in csp and "script-src 'self'" in csp
    for src in re.findall(r'(?:src|href)="([^"]+)"', r.text):
        assert src.startswith(("/static/", "#", "data:")), src
        if src.startswith("/static/"):
            assert client.get(src).status_code == 200, src
    # nothing in the shipped assets loads from the network (the SVG namespace URI is not fetched)
    for p in STATIC.rglob("*"):
        if p.is_file():
            text = p.read_text()
            urls = set(re.findall(r"https?://[^\s\"'`)]+", text)) - {"http://www.w3.org/2000/svg"}
            assert not urls, (p.name, urls)
            assert "@import" not in text and "cdn" not in text.lower()


def test_unknown_host_header_refused(client):
    r = client.get("/api/meta", headers={"host": "evil.example"})
    assert r.status_code == 400


def test_get_on_post_endpoint_is_405(client):
    assert client.get("/api/flight").status_code == 405


# ----------------------------------------------------------------- flight
def test_flight_matches_python_api(client):
    """The Flight page answers exactly what the flight workflow (``tennislab fly``) computes."""
    body = {
        "x": -11.885,
        "y": 0.5,
        "z": 2.8,
        "speed_kmh": 180,
        "elevation_deg": -4,
        "heading_deg": -1.5,
        "spin_rpm": 2000,
        "spin_axis_deg": 30,
        "aero": "stepanek1988",
        "bounces": 1,
        "surface": "clay",
    }
    r = client.post("/api/flight", json=body)
    assert r.status_code == 200, r.text
    out = r.json()
    ref = fly(
        (-11.885, 0.5, 2.8),
        speed_ms=180 * KMH,
        elevation_deg=-4,
        heading_deg=-1.5,
        spin_rpm=2000,
        spin_axis=30,
        params=FlightParams.from_options(aero="stepanek1988", air_density=1.199, wind=(0, 0, 0)),
        bounces=1,
        surface="clay",
    )
    points = out.pop("points")
    assert out == jsonable(ref.to_dict())
    assert points == ref.points(len(points))
    # an independent statement of the launch convention (elevation, heading, axis angle 0 = topspin)
    e, h = -4 * DEG, -1.5 * DEG
    d = np.array([math.cos(e) * math.cos(h), math.cos(e) * math.sin(h), math.sin(e)])
    t = np.cross([0, 0, 1.0], [d[0], d[1], 0])
    t /= np.linalg.norm(t)
    u = np.cross(d, t)
    w = (math.cos(30 * DEG) * t + math.sin(30 * DEG) * u) * 2000 * RPM
    tr = core_fly((-11.885, 0.5, 2.8), d * 180 * KMH, w, FlightParams.from_options(aero="stepanek1988"))
    assert out["landing"]["x"] == pytest.approx(tr.landing.x, abs=1e-9)
    assert out["landing"]["y"] == pytest.approx(tr.landing.y, abs=1e-9)
    assert out["net"]["clearance"] == pytest.approx(tr.net.clearance, abs=1e-9)
    assert points[0] == pytest.approx([-11.885, 0.5, 2.8], abs=1e-4)
    assert len(out["bounces"]) == 1 and out["surface"] == "clay"


def test_spin_axis_convention_matches_launcher(client):
    from tennislab.core.launch import launch_spin

    for a, h, g in [(10, 5, 0), (-5, -20, 90), (30, 12, 180), (0, 0, -90), (45, 40, 33)]:
        body = {"elevation_deg": a, "heading_deg": h, "spin_rpm": 1500, "spin_axis_deg": g, "speed_kmh": 60, "z": 1}
        ours = client.post("/api/flight", json=body).json()["launch"]["spin"]
        theirs = launch_spin(1500 * RPM, a * DEG, h * DEG, g * DEG)
        assert ours == pytest.approx(np.asarray(theirs).ravel(), abs=1e-9)


@pytest.mark.parametrize(
    "body, field",
    [
        ({"z": -1}, "height"),
        ({"z": 0.01}, "height"),
        ({"speed_kmh": 1e9}, "speed"),
        ({"speed_kmh": "fast"}, "speed"),
        ({"speed_kmh": True}, "speed"),
        ({"speed_kmh": [1, 2]}, "speed"),
        ({"speed_kmh": None}, "speed"),
        ({"spin_rpm": -5}, "spin"),
        ({"aero": "os.system"}, "aero model"),
        ({"aero": 3}, "aero model"),
        ({"bounces": 1.5}, "bounces"),
        ({"surface": "ice"}, "court surface"),
        ({"bogus": 1}, "bogus"),
        ({"__class__": 1}, "__class__"),
    ],
)
def test_flight_bad_fields(client, body, field):
    msg = err(client.post("/api/flight", json=body))
    assert msg.startswith(f"{field}:"), msg


def test_nan_and_infinity_refused(client):
    for lit in ("NaN", "Infinity", "-Infinity"):
        msg = err(client.post("/api/flight", content=f'{{"x": {lit}}}', headers={"content-type": "application/json"}))
        assert msg.startswith("position x:") and "finite" in msg


@pytest.mark.parametrize("content", ["", "not json", "[1, 2]", "42", '"text"', '{"x": 1', "\xff\xfe"])
def test_malformed_bodies(client, content):
    msg = err(
        client.post("/api/flight", content=content.encode("latin-1"), headers={"content-type": "application/json"})
    )
    assert msg.startswith("request:")


def test_body_size_limit(client):
    big = json.dumps({"x": 1, "pad": "a" * (F.MAX_BODY_BYTES + 10)})
    msg = err(client.post("/api/flight", content=big, headers={"content-type": "application/json"}), 413)
    assert "limit" in msg


def test_flight_that_never_lands_is_a_clean_error(client):
    # straight up at 260 km/h into 20 m/s of head wind still lands; a launch below the ground does not start
    msg = err(client.post("/api/flight", json={"z": 0.03}))
    assert msg.startswith("height:")


# ----------------------------------------------------------------- serve explorer
def test_serve_matches_impact_model_and_window(client):
    from tennislab.core.impact import impact_single
    from tennislab.serve import seed_impact_params
    from tennislab.serve.pipeline import default_flight

    win = client.post("/api/serve/window", json={"player": "professional", "step": 3}).json()
    code = np.array(win["code"])
    alpha, beta = np.array(win["alpha"]), np.array(win["beta"])
    assert code.shape == (beta.size, alpha.size)
    succ = np.argwhere(code > 0)
    fail = np.argwhere(code == 0)
    assert len(succ) > 0 and len(fail) > 0
    rng = np.random.default_rng(0)
    picks = [tuple(succ[i]) for i in rng.choice(len(succ), 4, replace=False)] + [
        tuple(fail[i]) for i in rng.choice(len(fail), 2, replace=False)
    ]
    fp = default_flight()  # the serve workflows' physics (the app states it: `physics`)
    assert win["physics"] == fp.to_dict() and win["physics_preset"] == "standard"
    for ib, ia in picks:
        body = {"player": "professional", "impact_angle": float(alpha[ia]), "face_angle": float(beta[ib])}
        r = client.post("/api/serve", json=body)
        assert r.status_code == 200, r.text
        s = r.json()
        assert s["success"] == bool(code[ib, ia] > 0), (alpha[ia], beta[ib])
        if code[ib, ia] > 0:
            assert s["category"] == ("flat", "topspin", "other")[code[ib, ia] - 1]
        ref = impact_single(40.0, min(alpha[ia], 89.999) * DEG, seed_impact_params(ball=fp.ball))
        assert s["speed"] == pytest.approx(ref.speed, rel=1e-9)
        assert s["spin_rpm"] == pytest.approx(ref.omega / RPM, rel=1e-9)
        assert s["flight"]["points"][0] == pytest.approx([-11.885, 0.0, 3.0], abs=1e-4)
        assert s["physics"] == win["physics"] and s["physics_preset"] == "standard"


def test_serve_custom_player_and_3d(client):
    from tennislab.serve import PlayerProfile, simulate

    base = {"player": "custom", "height": 2.5, "racket_speed": 33.0, "impact_angle": 30, "face_angle": 12}
    a = client.post("/api/serve", json=base).json()
    assert a["player"] == "custom"
    assert {k: a["player_profile"][k] for k in ("name", "impact_height", "racket_speed")} == {
        "name": "custom",
        "impact_height": 2.5,
        "racket_speed": 33.0,
    }
    three_d = {"target": "deuce", "azimuth_deg": 3.0, "brush_deg": 20.0, "server_y": 0.5, "toss_vz": -2.0}
    b = client.post("/api/serve", json={**base, **three_d}).json()
    ref = simulate(
        PlayerProfile("custom", 2.5, 33.0),
        30,
        12,
        target="deuce",
        azimuth_deg=3.0,
        brush_deg=20.0,
        server_y=0.5,
        toss_vz=-2.0,
        trajectory=True,
    ).to_dict()
    for k in ("speed", "spin_rpm", "launch_angle", "net_height", "landing_x", "success", "category"):
        assert b[k] == ref[k], k
    assert b["flight"]["landing"]["x"] == pytest.approx(ref["landing"]["x"], abs=1e-6)
    assert b["flight"]["points"][0] == pytest.approx([-11.885, 0.5, 2.5], abs=1e-4)
    assert b["landing_y"] > a["landing_y"] + 0.3  # the face turned toward +y
    # a named player ignores the custom height and speed
    c = client.post("/api/serve", json={**base, "player": "junior"}).json()
    assert (c["player_profile"]["impact_height"], c["player_profile"]["racket_speed"]) == (2.2, 25.0)
    # 3-D options need a real service box: a clear message, nothing computed
    msg = err(client.post("/api/serve", json={**base, "azimuth_deg": 2.0}))
    assert "azimuth" in msg and "deuce" in msg


def test_window_legend_counts_match_python(client):
    from tennislab.serve import window

    r = client.post("/api/serve/window", json={"player": "junior", "step": 2}).json()
    win = window("junior", step=2.0)
    w = win.summary()
    n = {it["code"]: it["n"] for it in r["legend"]}
    assert n[1] == w["flat"]["n"] and n[2] == w["topspin"]["n"]
    assert r["summary"]["flat"]["n"] == w["flat"]["n"]
    # the answer is the workflow's to_dict() (the JSON of `tennislab serve-window`), extended for the heat map
    ref = win.to_dict()
    assert {k: r[k] for k in ref} == json.loads(json.dumps(ref))
    assert [it["label"] for it in r["legend"]][1:3] == ["flat (< 1200 rpm)", "topspin (> 3200 rpm)"]
    # the heat map's span holds every success
    code = np.array(r["code"])
    ib, ia = np.nonzero(code > 0)
    sp = r["span"]
    assert sp["beta_lo"] <= min(np.array(r["beta"])[ib]) and max(np.array(r["beta"])[ib]) <= sp["beta_hi"]
    assert sp["alpha_lo"] <= min(np.array(r["alpha"])[ia]) and max(np.array(r["alpha"])[ia]) <= sp["alpha_hi"]
    assert sp["beta_hi"] < 60  # every success of a junior lies far below beta 90


@pytest.mark.parametrize(
    "path, body, field",
    [
        ("/api/serve", {"player": "god"}, "player"),
        ("/api/serve", {"impact_angle": 91}, "impact angle α"),
        ("/api/serve", {"aim_deg": 1}, "aim_deg"),
        ("/api/serve", {"face_angle": "x"}, "face angle β"),
        ("/api/serve", {"racket_speed": 0}, "racket speed"),
        ("/api/serve", {"target": "anywhere"}, "success criteria"),
        ("/api/serve", {"toss_vz": 50}, "ball vertical speed at impact"),
        ("/api/serve/window", {"step": 0.1}, "angle step"),
        ("/api/serve/window", {"step": 45, "extra": 1}, "extra"),
        ("/api/serve/window", {"height": 10}, "impact height"),
    ],
)
def test_serve_bad_fields(client, path, body, field):
    assert err(client.post(path, json=body)).startswith(f"{field}:")


def test_default_serve_succeeds(client):
    """The explorer opens on a serve that succeeds (asked through the app, whatever the serve model)."""
    meta = client.get("/api/meta").json()
    defaults = {f["name"]: f["default"] for f in meta["forms"]["serve"]}
    assert {k: defaults[k] for k in F.DEFAULT_SERVE} == F.DEFAULT_SERVE
    best = default_serve(F.DEFAULT_SERVE["player"])
    assert (best["impact_angle"], best["face_angle"]) == (
        F.DEFAULT_SERVE["impact_angle"],
        F.DEFAULT_SERVE["face_angle"],
    )
    for body in ({}, defaults):
        out = client.post("/api/serve", json=body).json()
        assert out["success"] is True, out
        assert out["verdict"]["success"] is True and out["verdict"]["reason"] is None


def test_failing_serve_gives_its_verdict_when_the_model_does(client):
    """The old default (alpha 36, beta 21) fails with this serve model; the verdict, when the serve
    workflow gives one, says why and what would fix it."""
    out = client.post("/api/serve", json={"impact_angle": 36, "face_angle": 21}).json()
    assert out["success"] is False
    v = out["verdict"]
    assert v["success"] is False and v["reason"] and v["advice"]


# ----------------------------------------------------------------- launcher planner
def test_aim_matches_python_api(client):
    from tennislab.launcher.aim import aim

    body = {"target_x": 9.0, "target_y": -2.5, "speed_kmh": 95, "spin_rpm": 1200, "shot": "backspin"}
    r = client.post("/api/launcher/aim", json=body)
    assert r.status_code == 200, r.text
    out = r.json()
    ref = aim((9.0, -2.5), 95, 1200, 180.0, 1.0).to_dict()
    assert out["settings"] == ref["settings"]
    assert out["rollers"] == pytest.approx(ref["rollers"])
    assert out["miss_mm"] == pytest.approx(ref["miss_mm"], abs=1e-6)
    land = out["flight"]["landing"]
    assert (land["x"], land["y"]) == pytest.approx((ref["landing"]["x"], ref["landing"]["y"]), abs=1e-4)


def test_aim_flat_shot_has_no_spin_and_unreachable_target_explained(client):
    out = client.post("/api/launcher/aim", json={"target_x": 8, "target_y": 1, "shot": "flat"}).json()
    assert out["settings"]["spin_rpm"] == 0
    msg = err(client.post("/api/launcher/aim", json={"target_x": 11.5, "target_y": 0, "speed_kmh": 30}))
    assert msg.startswith("target:") and "reach" in msg


@pytest.mark.parametrize(
    "body, field",
    [
        ({"target_x": 30}, "target x"),
        ({"speed_kmh": 250}, "ball speed"),
        ({"spin_rpm": 3000}, "spin"),
        ({"shot": "tweener"}, "shot type"),
        ({"solution": "middle"}, "solution"),
        ({"height": 0}, "launch height"),
    ],
)
def test_aim_bad_fields(client, body, field):
    assert err(client.post("/api/launcher/aim", json=body)).startswith(f"{field}:")


def test_drill_download_is_accepted_by_the_cli(client, tmp_path, capsys):
    from tennislab.cli import main

    shots = [
        {"target_x": 8, "target_y": 0},
        {"target_x": 9, "target_y": 3, "shot": "backspin", "speed_kmh": 90},
        {"target_x": 5, "target_y": -2, "shot": "flat"},
    ]
    r = client.post("/api/launcher/drill", json={"name": "Tuesday / kids", "shots": shots})
    assert r.status_code == 200, r.text
    out = r.json()
    assert out["check"]["ok"] and out["n_shots"] == 3
    assert re.fullmatch(r"[a-z0-9_-]+\.json", out["filename"])
    p = tmp_path / out["filename"]
    p.write_text(out["text"])
    capsys.readouterr()
    assert main(["launcher", "drill", str(p), "--json"]) == 0
    compiled = json.loads(capsys.readouterr().out)
    aims = [client.post("/api/launcher/aim", json=s).json()["settings"] for s in shots]
    got = [{k: row[k] for k in aims[0]} for row in compiled["shots"]]
    assert got == aims


@pytest.mark.parametrize(
    "body, prefix",
    [
        ({"shots": []}, "drill:"),
        ({"shots": "all"}, "drill:"),
        ({}, "drill:"),
        ({"shots": [{"target_x": "a"}]}, "shot 1: target x:"),
        ({"shots": [{"target_x": 8}, {"target_x": 8, "machine_x": -13}]}, "shot 2:"),
        ({"shots": [{}] * 51}, "drill:"),
        ({"shots": [{}], "name": "x" * 100}, "drill name:"),
        ({"shots": [{}], "evil": 1}, "evil:"),
    ],
)
def test_drill_bad_input(client, body, prefix):
    assert err(client.post("/api/launcher/drill", json=body)).startswith(prefix)


# ----------------------------------------------------------------- line-call replay
def test_linecall_requires_a_csv_text(client):
    for body in ({}, {"csv": 5}, {"csv": None}):
        assert err(client.post("/api/linecall", json=body)).startswith("track file:")


def test_linecall_track_size_limit(client):
    text = "t,x,y,z\n" + "0.0,1.0,1.0,1.0\n" * 70_000  # about 1.1 MB
    r = client.post("/api/linecall", json={"csv": text})
    assert r.status_code in (413, 422)
    assert r.json()["error"].startswith(("track file:", "request:"))


def test_linecall_bad_choice(client):
    assert err(client.post("/api/linecall", json={"csv": "t,x,y,z\n", "line": "net"})).startswith("line:")


def test_sample_track_is_a_csv(client):
    r = client.get("/api/linecall/sample")
    assert r.status_code == 200 and r.text.startswith("t,x,y,z,sigma\n")
    rows = np.loadtxt(r.text.splitlines()[1:], delimiter=",")
    assert rows.shape[1] == 5 and np.all(np.diff(rows[:, 0]) > 0)


def cli_call(text: str, tmp_path, *args) -> dict:
    """The reference: ``tennislab call --track FILE --json`` run in process."""
    import contextlib
    import io

    from tennislab.cli import main

    f = tmp_path / "track.csv"
    f.write_text(text)
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["call", "--track", str(f), "--json", *args]) == 0
    return json.loads(buf.getvalue())


@pytest.mark.parametrize(
    "form, args",
    [
        ({"target": "deuce-box"}, ["--target", "deuce-box"]),
        ({"line": "service"}, ["--line", "service"]),
        ({}, []),
        ({"surface": "clay"}, ["--surface", "clay"]),
    ],
)
def test_linecall_matches_the_cli(client, tmp_path, form, args):
    text = client.get("/api/linecall/sample").text
    r = client.post("/api/linecall", json={"csv": text, **form})
    assert r.status_code == 200, r.text
    out = r.json()
    ref = cli_call(text, tmp_path, *args)
    assert out["call"] == ref["call"]
    for k in ("x", "y", "t", "sigma_mm"):
        assert out["bounce"][k] == pytest.approx(ref["bounce"][k], abs=1e-9), k
    assert out["distance_mm"] == pytest.approx(ref["distance_mm"], abs=1e-6)
    assert out["p_in"] == pytest.approx(ref["p_in"], abs=1e-12)
    assert out["mark"]["length"] == pytest.approx(ref["mark"]["length"], abs=1e-12)
    assert out["fit"]["rms_mm"] == pytest.approx(ref["fit"]["rms_mm"], abs=1e-9)
    assert out["fit"]["outliers"] == ref["fit"]["outliers"]
    assert len(out["track"]) > 20 and len(out["fitted"]) > 20 and len(out["mark"]["discs"]) > 3


def test_sample_track_is_a_close_call(client):
    """The example serve lands a few mm beyond the service line: the call must be uncertain."""
    text = client.get("/api/linecall/sample").text
    out = client.post("/api/linecall", json={"csv": text, "target": "deuce-box"}).json()
    assert abs(out["distance_mm"]) < 10 and 0.01 < out["p_in"] < 0.99
    assert out["line"] == "service" and out["line_rect"] == list(ITF_COURT.lines()["service"])


@pytest.mark.parametrize(
    "text", ["", "a,b\n1,2\n", "t,x,y,z\n0,1,2\n", "t,x,y,z\n0,1,2,nan\n1,1,2,3\n", "t,x,y,z\n1,0,0,1\n0,0,0,1\n"]
)
def test_linecall_bad_tracks(client, text):
    assert err(client.post("/api/linecall", json={"csv": text}))


def test_concurrent_requests_give_the_same_answers(client):
    from concurrent.futures import ThreadPoolExecutor

    body = {"player": "recreational", "step": 3}
    ref = client.post("/api/serve/window", json=body).json()
    aim_ref = client.post("/api/launcher/aim", json={}).json()

    def one(i):
        if i % 2:
            return "w", client.post("/api/serve/window", json=body).json()
        return "a", client.post("/api/launcher/aim", json={}).json()

    with ThreadPoolExecutor(4) as ex:
        outs = list(ex.map(one, range(8)))
    for kind, out in outs:
        _same(out, ref if kind == "w" else aim_ref)


def _same(a, b, path=""):
    """Equal answers: the same keys and values, floats to 1e-9 relative (worker processes may run
    separately compiled kernels, which can differ in the last bits: docs/flight.md)."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and a.keys() == b.keys(), path
        for k in a:
            if k != "reach_map":  # whether this call built the reach map or found it: not the answer
                _same(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            _same(x, y, f"{path}[{i}]")
    elif isinstance(a, float) and isinstance(b, float):
        assert a == pytest.approx(b, rel=1e-9, abs=1e-12), path
    else:
        assert a == b, path


@pytest.mark.parametrize(
    "path",
    [
        "/static/../server.py",
        "/static/%2e%2e/server.py",
        "/static/..%2fserver.py",
        "/static/../../errors.py",
        "/server.py",
        "/api/../app/server.py",
    ],
)
def test_no_file_outside_static_is_served(client, path):
    r = client.get(path)
    assert r.status_code in (404, 400, 405) and "def create_app" not in r.text
