"""Browser end-to-end tests of ``tennislab app``: load each page, change inputs, read the result
from the page and compare it with the Python API.  Screenshots: out/screenshots/."""

from __future__ import annotations

import json

import numpy as np
import pytest

from tennislab.app import features
from tennislab.app import fields as F
from tennislab.app import services as S

pytestmark = pytest.mark.e2e
AVAIL = S.availability()


def open_page(pg, name: str):
    pg.goto(f"{pg.base}/#{name}")
    pg.wait_for_selector('body[data-ready="1"]', timeout=20000)
    assert pg.is_visible(f"#page-{name}")


def fill(pg, form: str, values: dict):
    for k, v in values.items():
        sel = f"#{form}-{k}"
        if pg.get_attribute(sel, "type") is None:  # a <select>
            pg.select_option(sel, str(v))
        else:
            pg.fill(sel, str(v))


def results(pg, box: str, timeout: float = 30000) -> dict:
    """data-key -> data-value of a result table (waits until it appears)."""
    pg.wait_for_selector(f"#{box} td[data-key]", timeout=timeout)
    return pg.eval_on_selector_all(
        f"#{box} td[data-key]", "els => Object.fromEntries(els.map(e => [e.dataset.key, e.dataset.value]))"
    )


def submit_and_wait(pg, button: str, status: str, path: str):
    with pg.expect_response(lambda r: r.url.endswith(path) and r.request.method == "POST", timeout=60000):
        pg.click(button)
    pg.wait_for_selector(f"#{status}:not(.busy)")


# ---------------------------------------------------------------- flight page
def test_flight_page(page):
    open_page(page, "flight")
    vals = {"speed_kmh": 150, "elevation_deg": -2.5, "heading_deg": 2, "spin_rpm": 1800, "spin_axis_deg": 20}
    fill(page, "flight", vals)
    submit_and_wait(page, "#submit-flight", "flight-status", "/api/flight")
    got = results(page, "flight-result")
    ref = S.flight(F.validate("flight", vals))
    assert float(got["landing_x"]) == pytest.approx(ref["landing"]["x"], abs=1e-9)
    assert float(got["landing_y"]) == pytest.approx(ref["landing"]["y"], abs=1e-9)
    assert got["net_result"] == ref["net"]["result"]
    assert page.locator("#flight-top path.traj").count() == 1
    page.snap("flight")


def _server_error(pg, path: str, body: dict) -> str:
    import urllib.error
    import urllib.request

    req = urllib.request.Request(
        pg.base + path, data=json.dumps(body).encode(), headers={"Content-Type": "application/json"}
    )
    try:
        urllib.request.urlopen(req, timeout=30)
    except urllib.error.HTTPError as exc:
        assert exc.code == 422
        return json.loads(exc.read())["error"]
    raise AssertionError("the server accepted a bad value")


def test_validation_in_the_page_sends_nothing(page):
    open_page(page, "flight")
    sent = []
    page.on("request", lambda r: sent.append(r.url) if r.method == "POST" else None)
    # the page shows the server's own message (same wording, same number format)
    for field, value in [
        ("speed_kmh", 9999),
        ("speed_kmh", 0.5),
        ("z", 1234567.0),
        ("spin_rpm", -0.001),
        ("air_density", 2),
        ("heading_deg", -61),
    ]:
        page.fill(f"#flight-{field}", str(value))
        assert page.inner_text(f"#err-flight-{field}") == _server_error(page, "/api/flight", {field: value})
        page.fill(f"#flight-{field}", str(F.FORMS["flight"].by_name()[field].default))
        assert page.inner_text(f"#err-flight-{field}") == ""
    page.fill("#flight-speed_kmh", "9999")
    page.fill("#flight-z", "abc")
    page.click("#submit-flight")
    page.wait_for_timeout(300)
    assert sent == []
    assert page.inner_text("#err-flight-z") == "z: expected a number, got 'abc'"
    assert "bad" in page.get_attribute("#flight-z", "class")
    page.fill("#flight-speed_kmh", "100")
    page.fill("#flight-z", "1.5")
    assert page.inner_text("#err-flight-speed_kmh") == "" and page.inner_text("#err-flight-z") == ""


# ---------------------------------------------------------------- serve explorer
@pytest.mark.skipif(not AVAIL["serve"]["available"], reason="serve module not installed")
def test_serve_explorer(page):
    open_page(page, "serve")
    page.select_option("#serve-player", "junior")
    assert float(page.input_value("#serve-height")) == 2.2
    assert float(page.input_value("#serve-racket_speed")) == 25
    vals = {
        "player": "junior",
        "impact_angle": 30,
        "face_angle": 10,
        "target": "deuce",
        "azimuth_deg": 1.5,
        "brush_deg": 15,
    }
    fill(page, "serve", vals)
    submit_and_wait(page, "#submit-serve", "serve-status", "/api/serve")
    got = results(page, "serve-result")
    ref = features.serve(F.validate("serve", vals))
    assert float(got["speed"]) == pytest.approx(ref["speed"], rel=1e-12)
    assert float(got["spin_rpm"]) == pytest.approx(ref["spin_rpm"], rel=1e-12)
    assert float(got["landing_x"]) == pytest.approx(ref["landing_x"], abs=1e-9)
    assert got["success"] == ("yes" if ref["success"] else "no") and got["category"] == ref["category"]

    # the 3-D view rotates when dragged
    page.locator("#serve-3d").scroll_into_view_if_needed()
    before = page.locator("#serve-3d").screenshot()
    box = page.locator("#serve-3d").bounding_box()
    page.mouse.move(box["x"] + 300, box["y"] + 200)
    page.mouse.down()
    page.mouse.move(box["x"] + 420, box["y"] + 240, steps=5)
    page.mouse.up()
    assert page.locator("#serve-3d").screenshot() != before

    # the window heat map: counts as the Python API, a click picks a serve
    page.select_option("#serve-target", "seed-2d")
    fill(page, "serve", {"azimuth_deg": 0, "brush_deg": 0})
    page.fill("#window-step", "3")
    submit_and_wait(page, "#run-window", "window-status", "/api/serve/window")
    page.wait_for_selector("#window-legend .legend-item")
    legend = page.eval_on_selector_all(
        "#window-legend .legend-item", "els => els.map(e => [e.dataset.code, +e.dataset.n])"
    )
    win = features.serve_window(F.validate("window", {"player": "junior", "step": 3}))
    assert dict(legend) == {str(it["code"]): it["n"] for it in win["legend"]}
    code = np.array(win["code"])
    cells = np.argwhere(code == 2) if (code == 2).any() else np.argwhere(code > 0)  # prefer a topspin success
    assert len(cells), "the junior's window has no successful serve"
    ib, ia = cells[len(cells) // 2]
    want = ("flat", "topspin", "other")[code[ib, ia] - 1]
    page.locator("#serve-heatmap").scroll_into_view_if_needed()
    hb = page.locator("#serve-heatmap").bounding_box()
    cw = page.eval_on_selector("#serve-heatmap", "c => [c.width, c.height]")
    na, nb = len(win["alpha"]), len(win["beta"])
    l, t, w, h = 40, 10, cw[0] - 50, cw[1] - 44  # HeatMap.geom()
    px = l + (ia + 0.5) * w / na
    py = t + h - (ib + 0.5) * h / nb
    with page.expect_response(lambda r: r.url.endswith("/api/serve"), timeout=60000):
        page.mouse.click(hb["x"] + px * hb["width"] / cw[0], hb["y"] + py * hb["height"] / cw[1])
    page.wait_for_selector("#serve-status.ok")
    assert float(page.input_value("#serve-impact_angle")) == win["alpha"][ia]
    assert float(page.input_value("#serve-face_angle")) == win["beta"][ib]
    page.wait_for_timeout(200)
    got = results(page, "serve-result")
    assert got["success"] == "yes" and got["category"] == want
    page.snap("serve")


@pytest.mark.skipif(not AVAIL["serve"]["available"], reason="serve module not installed")
def test_serve_bad_input_message(page):
    open_page(page, "serve")
    page.fill("#serve-impact_angle", "120")
    page.click("#submit-serve")
    msg = page.inner_text("#err-serve-impact_angle")
    assert msg == "impact_angle: 120 deg is outside the allowed range [0.0, 90.0] deg"
    assert msg == _server_error(page, "/api/serve", {"impact_angle": 120})
    page.select_option("#serve-player", "custom")
    page.fill("#serve-racket_speed", "-3")
    assert page.inner_text("#err-serve-racket_speed") == _server_error(page, "/api/serve", {"racket_speed": -3})


# ---------------------------------------------------------------- launcher planner
def _court_click(pg, x: float, y: float):
    """Click the launcher court at court coordinates (x, y) [m]."""
    pt = pg.evaluate(
        """([x, y]) => {
        const svg = document.querySelector('#launcher-court');
        const court = svg.querySelector('rect.court');
        const r = court.getBoundingClientRect();           // court rect spans [-L, L] x [-d, d]
        const L = 11.885, d = 10.97 / 2;
        return [r.left + (x + L) / (2 * L) * r.width, r.top + (d - y) / (2 * d) * r.height];
    }""",
        [x, y],
    )
    with pg.expect_response(lambda r: r.url.endswith("/api/launcher/aim"), timeout=60000):
        pg.mouse.click(pt[0], pt[1])
    pg.wait_for_selector("#aim-status.ok")


@pytest.mark.skipif(not AVAIL["launcher"]["available"], reason="launcher module not installed")
def test_launcher_planner_and_drill_download(page, tmp_path, capsys):
    from tennislab.cli import main
    from tennislab.launcher.aim import aim, aim_result_dict

    open_page(page, "launcher")
    fill(page, "aim", {"speed_kmh": 95, "spin_rpm": 1200, "shot": "topspin"})
    shots = []
    for x, y in [(9.0, 2.5), (8.0, -3.0), (5.0, 0.5)]:
        _court_click(page, x, y)
        tx, ty = float(page.input_value("#aim-target_x")), float(page.input_value("#aim-target_y"))
        assert (tx, ty) == pytest.approx((x, y), abs=0.1)
        got = results(page, "aim-result")
        ref = aim_result_dict(aim((tx, ty), 95, 1200, 0.0, 1.0))
        for k, v in ref["settings"].items():
            assert float(got[f"settings.{k}"]) == v, k
        assert float(got["rollers.rpm1"]) == pytest.approx(ref["rollers"]["rpm1"], rel=1e-12)
        assert float(got["miss_mm"]) == pytest.approx(ref["miss_mm"], abs=1e-6)
        page.click("#add-shot")
        shots.append(ref["settings"])
    assert page.inner_text("#drill-count") == "3"
    assert page.locator("#drill-table tbody tr").count() == 3
    page.snap("launcher")
    try:
        import tennislab.io.drill  # noqa: F401
    except ImportError:
        pytest.skip("drill files not available")
    page.fill("#drill-name", "e2e drill")
    with page.expect_download(timeout=60000) as dl:
        page.click("#download-drill")
    path = tmp_path / dl.value.suggested_filename
    dl.value.save_as(str(path))
    assert path.name == "e2e-drill.json"
    capsys.readouterr()
    assert main(["launcher", "drill", str(path), "--json"]) == 0
    compiled = json.loads(capsys.readouterr().out)
    assert [{k: r[k] for k in shots[0]} for r in compiled["shots"]] == shots


# ---------------------------------------------------------------- line-call replay
def test_linecall_page(page, tmp_path):
    open_page(page, "linecall")
    if not AVAIL["linecall"]["available"]:
        assert "not available" in page.inner_text("#linecall-unavailable")
        page.snap("linecall")
        return
    from tennislab.app import linecall_adapter

    text = features.sample_track()
    page.select_option("#linecall-target", "deuce-box")
    f = tmp_path / "track.csv"
    f.write_text(text)
    page.set_input_files("#track-file", str(f))
    submit_and_wait(page, "#submit-linecall", "call-status", "/api/linecall")
    got = results(page, "call-result")
    ref = linecall_adapter.reference_call(text, target="deuce-box")
    assert got["call"] == ref["call"] and got["against"] == "deuce-box"
    assert float(got["p_in"]) == pytest.approx(ref["p_in"], abs=1e-12)
    assert float(got["distance_mm"]) == pytest.approx(ref["distance_mm"], abs=1e-3)
    assert float(got["bounce.x"]) == pytest.approx(ref["bounce"]["x"], abs=1e-6)
    assert page.locator("#call-mark").count() == 1
    page.snap("linecall")
    # a broken file gives a clear message in the page
    bad = tmp_path / "bad.csv"
    bad.write_text("time,where\n1,2\n")
    page.set_input_files("#track-file", str(bad))
    submit_and_wait(page, "#submit-linecall", "call-status", "/api/linecall")
    assert "error" in page.get_attribute("#call-status", "class")
    assert page.inner_text("#call-status").strip() != ""


# ---------------------------------------------------------------- degraded installation
def test_pages_degrade_when_modules_are_missing(degraded_page):
    pg = degraded_page
    for name, feature in (("serve", "serve"), ("launcher", "launcher"), ("linecall", "linecall")):
        pg.goto(f"{pg.base}/#{name}")
        pg.wait_for_selector('body[data-ready="1"]', timeout=20000)
        text = pg.inner_text(f"#{name}-unavailable")
        assert text.startswith(f"{feature}: not available in this installation"), text
    pg.snap("degraded")
    # the rest keeps working
    open_page(pg, "flight")
    submit_and_wait(pg, "#submit-flight", "flight-status", "/api/flight")
    assert results(pg, "flight-result")["net_result"] in ("over", "net")
