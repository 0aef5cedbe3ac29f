"""Browser end-to-end tests of ``tennislab app`` in Chromium, at 1400 px and at 390 px: load each page,
change inputs, read the results from the page and compare them with the workflows the server calls.
Screenshots: out/screenshots/."""

from __future__ import annotations

import csv
import io
import json
import re
import struct
import urllib.error
import urllib.request

import numpy as np
import pytest

from tennislab.app import features
from tennislab.app import fields as F
from tennislab.app import services as S

pytestmark = pytest.mark.e2e
INTERNAL_NAMES = [f.name for form in F.FORMS.values() for f in form.fields if "_" in f.name]


# ---------------------------------------------------------------- helpers
def idle(pg, timeout: float = 60000):
    """Wait until the page has no computation scheduled or running."""
    pg.wait_for_function("() => window.tennislab && window.tennislab.idle && window.tennislab.idle()", timeout=timeout)


def open_page(pg, name: str, query: str = ""):
    pg.goto(f"{pg.base}/#{name}{query}")
    pg.wait_for_selector('body[data-ready="1"]', timeout=30000)
    # A hash change within the loaded app is handled by a task queued after goto returns: wait until the
    # page is shown (its run is counted as pending in the same task), then until it is idle.
    pg.wait_for_function(
        "n => { const el = document.getElementById('page-' + n); return el && !el.hidden; }", arg=name, timeout=30000
    )
    idle(pg)
    assert pg.is_visible(f"#page-{name}")


def fill(pg, form: str, values: dict):
    for k, v in values.items():
        sel = f"#{form}-{k}"
        if pg.get_attribute(sel, "type") is None:  # a <select>
            pg.select_option(sel, str(v))
        else:
            pg.fill(sel, str(v))
    idle(pg)


def results(pg, box: str) -> dict:
    """data-key -> data-value of a result table ({} when the page shows none)."""
    return pg.eval_on_selector_all(
        f"#{box} td[data-key]", "els => Object.fromEntries(els.map(e => [e.dataset.key, e.dataset.value]))"
    )


def server_error(pg, path: str, body: dict) -> str:
    req = urllib.request.Request(
        pg.base + path, data=json.dumps(body).encode(), headers={"Content-Type": "application/json"}
    )
    try:
        urllib.request.urlopen(req, timeout=60)
    except urllib.error.HTTPError as exc:
        assert exc.code == 422
        return json.loads(exc.read())["error"]
    raise AssertionError("the server accepted a bad value")


def count_posts(pg) -> list:
    sent: list = []
    pg.on("request", lambda r: sent.append(r.url) if r.method == "POST" else None)
    return sent


def drawn_inside(pg, svg: str) -> bool:
    """Every point of every trajectory drawn in an SVG view lies inside its axes (nothing clipped)."""
    return pg.evaluate(
        """(sel) => {
        const svg = document.querySelector(sel), ax = svg.tlAxes;
        const paths = [...svg.querySelectorAll('path.traj')];
        if (!paths.length) return false;
        const x0 = ax.px(ax.u0), x1 = ax.px(ax.u1), y0 = ax.py(ax.v1), y1 = ax.py(ax.v0);
        return paths.every(p => p.getAttribute('d').slice(1).split('L').every(s => {
            const [x, y] = s.split(',').map(Number);
            return x >= x0 - 0.5 && x <= x1 + 0.5 && y >= y0 - 0.5 && y <= y1 + 0.5;
        }));
    }""",
        f"#{svg}",
    )


def view3d_inside(pg, canvas: str) -> bool:
    """Every point of every track of a 3-D view (and its shadow) projects inside the canvas."""
    return pg.evaluate(
        """(sel) => {
        const c = document.querySelector(sel), v = c.tlView;
        if (!v.tracks.length) return false;
        return v.tracks.every(t => t.points.every(p => [p, [p[0], p[1], 0]].every(q => {
            const [x, y] = v.project(q);
            return x >= 0 && x <= c.width && y >= 0 && y <= c.height;
        })));
    }""",
        f"#{canvas}",
    )


# ---------------------------------------------------------------- flight page
def test_flight_page_matches_the_workflow(wide_page):
    page = wide_page
    open_page(page, "flight")
    vals = {"speed_kmh": 150, "elevation_deg": -2.5, "heading_deg": 2, "spin_rpm": 1800, "spin_axis_deg": 20}
    vals |= {"bounces": 1, "surface": "clay"}
    fill(page, "flight", vals)
    got = results(page, "flight-result")
    ref = S.flight(F.validate("flight", vals))
    assert float(got["landing_x"]) == ref["landing"]["x"]
    assert float(got["landing_y"]) == ref["landing"]["y"]
    assert float(got["bounces.0.x"]) == ref["bounces"][0]["x"]
    assert got["net_result"] == ref["net"]["result"]
    assert page.locator("#flight-top path.traj").count() == 1
    page.snap("flight")


def test_validation_in_the_page_matches_the_server(wide_page):
    page = wide_page
    open_page(page, "flight")
    sent = count_posts(page)
    for field, value in [
        ("speed_kmh", 9999),
        ("speed_kmh", 0.5),
        ("z", 1234567.0),
        ("spin_rpm", -0.001),
        ("air_density", 2),
        ("heading_deg", -61),
        ("bounces", 1.5),
    ]:
        page.fill(f"#flight-{field}", str(value))
        msg = page.inner_text(f"#err-flight-{field}")
        assert msg == server_error(page, "/api/flight", {field: value})
        assert msg.startswith(F.FORMS["flight"].by_name()[field].label + ": ")
        page.fill(f"#flight-{field}", str(F.FORMS["flight"].by_name()[field].default))
        assert page.inner_text(f"#err-flight-{field}") == ""
    idle(page)
    sent.clear()
    page.fill("#flight-z", "abc")
    idle(page)
    assert page.inner_text("#err-flight-z") == "height: expected a number, got 'abc'"
    assert "bad" in page.get_attribute("#flight-z", "class")
    page.click("#submit-flight")
    idle(page)
    assert sent == []  # nothing is sent from a bad form
    assert results(page, "flight-result") == {}


# ---------------------------------------------------------------- serve: default, verdict
def test_default_serve_succeeds_and_shows_its_verdict(page):
    open_page(page, "serve")
    got = results(page, "serve-result")
    ref = features.serve(F.validate("serve", {}))
    assert ref["success"] is True
    assert got["success"] == "yes" and float(got["speed"]) == ref["speed"]
    assert page.get_attribute("#serve-verdict", "data-success") == "yes"
    assert page.inner_text("#serve-verdict-head").startswith("In")
    if "verdict" in ref and ref["verdict"].get("detail"):
        assert page.inner_text("#serve-verdict-detail") == ref["verdict"]["detail"]
    assert page.locator("#window-legend .legend-item").count() >= 2  # the window opens computed
    page.snap("serve-default")


def test_a_failing_serve_says_why_and_what_would_fix_it(page):
    open_page(page, "serve")
    verdict = {
        "success": False,
        "reason": "long",
        "detail": "lands 0.42 m beyond the service line",
        "advice": "increase the face angle β by about 1 deg",
    }

    def with_verdict(route):
        real = route.fetch()
        body = real.json()
        body.update(success=False, verdict=verdict, caveats=["placeholder ball data in the impact model"])
        route.fulfill(response=real, json=body)

    page.route("**/api/serve", with_verdict)
    fill(page, "serve", {"impact_angle": 36, "face_angle": 21})
    assert page.get_attribute("#serve-verdict", "data-success") == "no"
    assert page.get_attribute("#serve-verdict", "data-reason") == "long"
    assert page.inner_text("#serve-verdict-head") == "Fault: long"
    assert page.inner_text("#serve-verdict-detail") == verdict["detail"]
    assert page.inner_text("#serve-verdict-advice") == "To fix it: " + verdict["advice"]
    assert "placeholder ball data" in page.inner_text("#serve-caveats")
    page.unroute("**/api/serve")
    # the real answer for the same serve (α 36°, β 21° fails with this serve model)
    fill(page, "serve", {"face_angle": 21.0001})
    ref = features.serve(F.validate("serve", {"impact_angle": 36, "face_angle": 21.0001}))
    assert results(page, "serve-result")["success"] == ("yes" if ref["success"] else "no")
    if not ref["success"]:
        assert page.inner_text("#serve-verdict-head").startswith("Fault")
        assert page.get_attribute("#serve-verdict", "data-reason") == ref["verdict"]["reason"]  # always says why
        assert ref["verdict"]["advice"] in page.inner_text("#serve-verdict-advice")
    page.snap("serve-fault")


# ---------------------------------------------------------------- emptied and bad fields
def test_an_emptied_field_blocks_the_computation_and_clears_the_results(page):
    open_page(page, "flight")
    assert results(page, "flight-result")
    sent = count_posts(page)
    page.fill("#flight-speed_kmh", "")
    idle(page)
    page.wait_for_timeout(400)
    assert sent == []
    assert results(page, "flight-result") == {}
    assert page.locator("#flight-side path.traj, #flight-top path.traj").count() == 0
    assert page.evaluate("document.querySelector('#flight-3d').tlView.tracks.length") == 0
    assert page.inner_text("#flight-status") == "speed: a value is required"
    assert "error" in page.get_attribute("#flight-status", "class")
    assert page.inner_text("#err-flight-speed_kmh") == "speed: a value is required"
    assert page.is_disabled('button[data-csv="flight-results"]')
    page.fill("#flight-speed_kmh", "150")
    idle(page)
    assert float(results(page, "flight-result")["landing_x"]) > 0

    open_page(page, "serve")
    assert page.inner_text("#serve-verdict")
    page.fill("#serve-impact_angle", " ")
    idle(page)
    assert results(page, "serve-result") == {} and page.inner_text("#serve-verdict") == ""
    assert page.inner_text("#serve-status") == "impact angle α: a value is required"


def test_messages_use_the_labels_on_screen(page):
    open_page(page, "serve")
    page.fill("#serve-face_angle", "95")
    idle(page)
    msg = page.inner_text("#serve-status")
    assert msg == "face angle β: 95 deg is outside the allowed range [-10.0, 90.0] deg"
    assert msg == server_error(page, "/api/serve", {"face_angle": 95})
    page.select_option("#serve-player", "custom")
    page.fill("#serve-racket_speed", "-3")
    idle(page)
    assert page.inner_text("#err-serve-racket_speed").startswith("racket speed: -3 m/s")
    # a message from the server's own checks (an unreachable target) is shown and clears the results
    open_page(page, "launcher")
    assert results(page, "aim-result")
    fill(page, "aim", {"speed_kmh": 30, "target_x": 11.5, "target_y": 0})
    msg = page.inner_text("#aim-status")
    assert "error" in page.get_attribute("#aim-status", "class") and msg.startswith("target")
    assert results(page, "aim-result") == {}
    for shown in (msg, page.inner_text("#serve-status")):
        assert not [n for n in INTERNAL_NAMES if n in shown], shown


# ---------------------------------------------------------------- layout at 390 px
def test_no_horizontal_overflow_and_tabs_apart(page):
    for name in ("serve", "launcher", "linecall", "flight"):
        open_page(page, name)
        if name == "linecall":
            page.click("#call-sample")
            idle(page)
        width = page.evaluate("window.innerWidth")
        assert page.evaluate("document.documentElement.scrollWidth") <= width, name
        assert page.evaluate("getComputedStyle(document.documentElement).overflowX") == "visible"
        boxes = [page.locator(f"#tab-{t}").bounding_box() for t in ("serve", "launcher", "linecall", "flight")]
        for i, a in enumerate(boxes):
            assert a["x"] >= 0 and a["x"] + a["width"] <= width
            for b in boxes[i + 1 :]:
                apart = (
                    a["x"] + a["width"] <= b["x"]
                    or b["x"] + b["width"] <= a["x"]
                    or a["y"] + a["height"] <= b["y"]
                    or b["y"] + b["height"] <= a["y"]
                )
                assert apart, (a, b)
        page.snap(f"layout-{name}")


# ---------------------------------------------------------------- exports
def check_png(path) -> tuple[int, int]:
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    w, h = struct.unpack(">II", data[16:24])
    assert w >= 300 and h >= 150 and len(data) > 3000, (w, h, len(data))
    return w, h


def check_csv(path, min_rows: int) -> list[list[str]]:
    rows = list(csv.reader(io.StringIO(path.read_text())))
    assert len(rows) >= min_rows + 1, len(rows)
    assert all(len(r) == len(rows[0]) for r in rows)
    return rows


def export_all(pg, tmp_path, scope: str) -> dict:
    out = {}
    for b in pg.locator(f"{scope} button.export").all():
        assert b.is_enabled(), b.inner_text()
        with pg.expect_download(timeout=30000) as dl:
            b.click()
        p = tmp_path / dl.value.suggested_filename
        dl.value.save_as(str(p))
        out[p.name] = p
    return out


def test_exports_of_each_view(page, tmp_path):
    open_page(page, "flight")
    files = export_all(page, tmp_path, "#page-flight")
    assert sorted(files) == sorted(
        ["tennislab-flight-3d.png", "tennislab-flight-side.png", "tennislab-flight-top.png"]
        + ["tennislab-flight-results.csv", "tennislab-flight-trajectory.csv"]
    )
    for name, p in files.items():
        if name.endswith(".png"):
            check_png(p)
    traj = check_csv(files["tennislab-flight-trajectory.csv"], 100)
    assert traj[0] == ["x_m", "y_m", "z_m"] and float(traj[1][2]) == F.FORMS["flight"].by_name()["z"].default
    nums = {r[3]: r[2] for r in check_csv(files["tennislab-flight-results.csv"], 10)[1:] if r[0] == "result"}
    assert float(nums["landing_x"]) == float(results(page, "flight-result")["landing_x"])
    if page.width > 1000:  # the other pages once (their exports work the same way)
        open_page(page, "serve")
        files = export_all(page, tmp_path, "#page-serve")
        assert len(files) == 7
        win = check_csv(files["tennislab-serve-window.csv"], 100)
        assert win[0][:3] == ["alpha_deg", "beta_deg", "code"]
        open_page(page, "launcher")
        page.click("#add-shot")
        files = export_all(page, tmp_path, "#page-launcher")
        assert len(files) == 5 and len(check_csv(files["tennislab-drill.csv"], 1)) == 2
        open_page(page, "linecall")
        page.click("#call-sample")
        idle(page)
        files = export_all(page, tmp_path, "#page-linecall")
        assert len(files) == 4
        for name, p in files.items():
            if name.endswith(".png"):
                check_png(p)


# ---------------------------------------------------------------- the URL keeps the inputs
def test_a_url_keeps_the_inputs(page):
    open_page(page, "flight")
    fill(page, "flight", {"speed_kmh": 150, "elevation_deg": 3, "spin_rpm": 1200, "spin_axis_deg": 20, "bounces": 1})
    url, got = page.url, results(page, "flight-result")
    assert "speed_kmh=150" in url and "bounces=1" in url
    fresh = page.context.new_page()
    fresh.base = page.base
    open_page(fresh, "flight", "?" + url.split("?", 1)[1])
    assert fresh.input_value("#flight-speed_kmh") == "150" and fresh.input_value("#flight-bounces") == "1"
    assert results(fresh, "flight-result") == got

    open_page(page, "serve")
    fill(page, "serve", {"player": "junior", "impact_angle": 40, "face_angle": 14})
    page.fill("#window-step", "3")
    idle(page)
    url, got = page.url, results(page, "serve-result")
    fresh.goto(url)
    fresh.reload()
    fresh.wait_for_selector('body[data-ready="1"]')
    idle(fresh)
    assert fresh.input_value("#serve-player") == "junior" and fresh.input_value("#serve-impact_angle") == "40"
    assert fresh.input_value("#window-step") == "3"
    assert results(fresh, "serve-result") == got
    # a bad value in a link is shown as such, and nothing is computed from it
    fresh.goto(f"{page.base}/#flight?speed_kmh=abc")
    fresh.reload()
    fresh.wait_for_selector('body[data-ready="1"]')
    idle(fresh)
    assert fresh.inner_text("#flight-status") == "speed: expected a number, got 'abc'"
    assert results(fresh, "flight-result") == {}
    fresh.close()


# ---------------------------------------------------------------- the views frame what they draw
def test_a_lob_and_its_bounces_are_framed(page):
    open_page(page, "flight")
    lob = {"x": -11, "y": 0, "z": 1, "speed_kmh": 75, "elevation_deg": 62, "heading_deg": 0, "spin_rpm": 0}
    fill(page, "flight", lob | {"bounces": 2})
    apex = float(results(page, "flight-result")["apex_z"])
    assert apex > 6  # a lob well above the old fixed frame
    for svg in ("flight-side", "flight-top"):
        assert drawn_inside(page, svg), svg
    assert page.evaluate("document.querySelector('#flight-side').tlAxes.v1") >= apex
    assert view3d_inside(page, "flight-3d")
    box = page.locator("#flight-3d").bounding_box()  # turned by hand, still framed
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.mouse.down()
    page.mouse.move(box["x"] + box["width"] / 2 + 60, box["y"] + box["height"] / 2 + 40, steps=4)
    page.mouse.up()
    assert view3d_inside(page, "flight-3d")
    page.snap("lob")


# ---------------------------------------------------------------- serve window, launcher, line calls
def test_serve_window_heat_map_picks_a_serve(wide_page):
    page = wide_page
    open_page(page, "serve")
    page.select_option("#serve-player", "junior")
    assert float(page.input_value("#serve-height")) == 2.2
    page.fill("#window-step", "3")
    idle(page)
    legend = page.eval_on_selector_all(
        "#window-legend .legend-item", "els => els.map(e => [e.dataset.code, +e.dataset.n])"
    )
    win = features.serve_window(F.validate("window", {"player": "junior", "step": 3}))
    assert dict(legend) == {str(it["code"]): it["n"] for it in win["legend"]}
    code = np.array(win["code"])
    cells = np.argwhere(code == 2) if (code == 2).any() else np.argwhere(code > 0)  # prefer a topspin success
    ib, ia = cells[len(cells) // 2]
    want = ("flat", "topspin", "other")[code[ib, ia] - 1]
    page.locator("#serve-heatmap").scroll_into_view_if_needed()
    cw = page.eval_on_selector("#serve-heatmap", "c => [c.width, c.height, c.clientWidth]")
    assert abs(cw[0] - cw[2]) <= 2  # drawn at the size it is shown: labels at their size
    px, py = page.eval_on_selector("#serve-heatmap", "(c, [i, j]) => c.tlHeat.cellCenter(i, j)", [int(ia), int(ib)])
    inner = "c => { const r = c.getBoundingClientRect(); "
    inner += "return [r.x + c.clientLeft, r.y + c.clientTop, c.clientWidth, c.clientHeight]; }"
    x0, y0, w, h = page.eval_on_selector("#serve-heatmap", inner)  # the canvas inside its border
    page.mouse.click(x0 + px * w / cw[0], y0 + py * h / cw[1])
    idle(page)
    assert float(page.input_value("#serve-impact_angle")) == win["alpha"][ia]
    assert float(page.input_value("#serve-face_angle")) == win["beta"][ib]
    got = results(page, "serve-result")
    assert got["success"] == "yes" and got["category"] == want
    # the heat map spans where the window is: every success shown, beta far below 90
    shown = page.eval_on_selector("#serve-heatmap", "c => c.tlHeat.shown()")
    ok_b, ok_a = np.nonzero(code > 0)
    assert shown["b0"] <= ok_b.min() and ok_b.max() <= shown["b1"]
    assert shown["a0"] <= ok_a.min() and ok_a.max() <= shown["a1"]
    assert win["beta"][shown["b1"]] < 60
    assert "Shown where the window is" in page.inner_text("#window-note")
    # the 3-D view rotates when dragged
    page.locator("#serve-3d").scroll_into_view_if_needed()
    before = page.locator("#serve-3d").screenshot()
    box = page.locator("#serve-3d").bounding_box()
    page.mouse.move(box["x"] + 300, box["y"] + 200)
    page.mouse.down()
    page.mouse.move(box["x"] + 420, box["y"] + 240, steps=5)
    page.mouse.up()
    assert page.locator("#serve-3d").screenshot() != before
    page.snap("serve")


def _court_click(pg, x: float, y: float):
    """Click the launcher court at court coordinates (x, y) [m]."""
    pt = pg.evaluate(
        """([x, y]) => {
        const ax = document.querySelector('#launcher-court').tlAxes;
        const m = ax.svg.getScreenCTM(), p = ax.svg.createSVGPoint();
        p.x = ax.px(x); p.y = ax.py(y);
        const q = p.matrixTransform(m);
        return [q.x, q.y];
    }""",
        [x, y],
    )
    pg.mouse.click(pt[0], pt[1])
    idle(pg)


def test_launcher_planner_and_drill_download(wide_page, tmp_path, capsys):
    from tennislab.cli import main
    from tennislab.launcher.aim import aim

    page = wide_page
    open_page(page, "launcher")
    fill(page, "aim", {"speed_kmh": 95, "spin_rpm": 1200, "shot": "topspin"})
    shots = []
    for x, y in [(9.0, 2.5), (8.0, -3.0), (5.0, 0.5)]:
        _court_click(page, x, y)
        tx, ty = float(page.input_value("#aim-target_x")), float(page.input_value("#aim-target_y"))
        assert (tx, ty) == pytest.approx((x, y), abs=0.1)
        got = results(page, "aim-result")
        ref = aim((tx, ty), 95, 1200, 0.0, 1.0).to_dict()
        for k, v in ref["settings"].items():
            assert float(got[f"settings.{k}"]) == v, k
        assert float(got["rollers.rpm1"]) == pytest.approx(ref["rollers"]["rpm1"], rel=1e-12)
        assert float(got["miss_mm"]) == pytest.approx(ref["miss_mm"], abs=1e-6)
        page.click("#add-shot")
        shots.append(ref["settings"])
    assert page.inner_text("#drill-count") == "3"
    assert page.locator("#drill-table tbody tr").count() == 3
    page.snap("launcher")
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


def test_linecall_page(wide_page, tmp_path):
    from tennislab.app import linecall_adapter

    page = wide_page
    open_page(page, "linecall")
    text = features.sample_track()
    page.select_option("#linecall-target", "deuce-box")
    f = tmp_path / "track.csv"
    f.write_text(text)
    page.set_input_files("#track-file", str(f))
    idle(page)
    got = results(page, "call-result")
    ref = linecall_adapter.reference_call(text, target="deuce-box")
    assert got["call"] == ref["call"] and got["against"] == "deuce-box"
    assert float(got["p_in"]) == pytest.approx(ref["p_in"], abs=1e-12)
    assert float(got["distance_mm"]) == pytest.approx(ref["distance_mm"], abs=1e-3)
    assert float(got["bounce.x"]) == pytest.approx(ref["bounce"]["x"], abs=1e-6)
    assert page.locator("#call-mark").count() == 1
    assert drawn_inside(page, "call-side")
    # another surface: the call is made again at once
    page.select_option("#linecall-surface", "clay")
    idle(page)
    assert json.loads(page.get_attribute("#call-result", "data-for"))["surface"] == "clay"
    page.snap("linecall")
    # a broken file gives a clear message and clears the results
    bad = tmp_path / "bad.csv"
    bad.write_text("time,where\n1,2\n")
    page.set_input_files("#track-file", str(bad))
    idle(page)
    assert "error" in page.get_attribute("#call-status", "class")
    assert page.inner_text("#call-status").startswith("track file:")
    assert results(page, "call-result") == {}


def test_linecall_example_then_an_uploaded_track(page):
    """Issue 23 point 1: the example is called against the deuce box (and the page says so); a track file
    chosen next is called with the user's own target again (here the default: the singles court of the half
    it lands in), as ``tennislab call --track`` calls it."""
    from pathlib import Path

    from tennislab.app import linecall_adapter

    open_page(page, "linecall")
    page.click("#call-sample")
    idle(page)
    assert page.input_value("#linecall-target") == "deuce-box"
    assert results(page, "call-result")["against"] == "deuce-box"
    assert "deuce service box" in page.inner_text("#call-status")
    lob = Path(__file__).resolve().parents[2] / "examples" / "tracks" / "lob_baseline.csv"
    page.set_input_files("#track-file", str(lob))
    idle(page)
    assert page.input_value("#linecall-target") == "auto"
    got = results(page, "call-result")
    ref = linecall_adapter.reference_call(lob.read_text())  # as `tennislab call --track lob_baseline.csv`
    assert got["against"] == ref["target"] == "singles"
    assert got["call"] == ref["call"] == "out"
    assert float(got["distance_mm"]) == pytest.approx(ref["distance_mm"], abs=1e-3)
    assert -100 < ref["distance_mm"] < 0  # out by millimetres, not metres
    shown = page.inner_text('#call-result td[data-key="distance_mm"]')
    assert shown == f"out by {abs(ref['distance_mm']):.1f} mm"
    assert float(got["p_in"]) == pytest.approx(ref["p_in"], abs=1e-12)
    page.snap("linecall-upload")
    # a target the user picks after the example is the user's: kept for the next file
    page.click("#call-sample")
    idle(page)
    page.select_option("#linecall-target", "deuce-box")
    idle(page)
    page.set_input_files("#track-file", str(lob))
    idle(page)
    assert page.input_value("#linecall-target") == "deuce-box"
    assert results(page, "call-result")["against"] == "deuce-box"


# ---------------------------------------------------------------- the width of the screen, readable labels
def test_the_page_uses_its_width_and_labels_stay_readable(page):
    """At 1400 px the plots fill the column beside the form, two side by side; at 390 px they are one
    above the other and every axis label is drawn at its size (12 px), never shrunk with the plot."""
    for name, views in (
        ("flight", ("#flight-3d", "#flight-side")),
        ("serve", ("#serve-3d", "#serve-side")),
        ("launcher", ("#launcher-court", "#launcher-side")),
        ("linecall", ("#call-zoom", "#call-side")),
    ):
        open_page(page, name)
        if name == "linecall":
            page.click("#call-sample")
            idle(page)
        width = page.evaluate("window.innerWidth")
        a, b = (page.locator(v).bounding_box() for v in views)
        right = max(a["x"] + a["width"], b["x"] + b["width"])
        if width >= 1000:
            assert right >= 0.93 * width, (name, right, width)  # no empty half of the screen
            assert abs(a["y"] - b["y"]) < 40 and b["x"] > a["x"] + a["width"] - 1, (name, a, b)  # side by side
        else:
            assert b["y"] >= a["y"] + a["height"] - 1, (name, a, b)  # one above the other
        sizes = page.eval_on_selector_all(
            f"#page-{name} svg.plot text.ticklabel, #page-{name} svg.plot text.axislabel",
            "els => els.map(e => e.getBoundingClientRect().height)",
        )
        assert sizes and min(sizes) >= 11, (name, min(sizes) if sizes else None)
        for canvas in page.eval_on_selector_all(
            f"#page-{name} canvas", "els => els.filter(c => c.offsetParent).map(c => [c.width, c.clientWidth])"
        ):
            assert abs(canvas[0] - canvas[1]) <= 2, (name, canvas)  # a canvas is drawn at its shown size
        assert page.locator(f"#page-{name} .plot-legend .legend-entry").count() >= 3, name  # every marker named
        shown = page.inner_text(f"#page-{name}")
        assert not re.search(r"(?<![\d.])-0\.0+(?!\d)", shown), (name, "a negative zero is shown")
        page.snap(f"width-{name}")


def test_court_colours_follow_the_surface(wide_page):
    page = wide_page
    open_page(page, "flight")
    fill(page, "flight", {"bounces": 1, "surface": "clay"})
    colors = page.evaluate("tennislab.meta.court.surfaces")
    fill_of = page.eval_on_selector("#flight-top rect.court", "r => getComputedStyle(r).fill")
    clay = colors["clay"]["court"]
    assert fill_of == "rgb({}, {}, {})".format(*(int(clay[i : i + 2], 16) for i in (1, 3, 5)))
    assert "court: clay" in page.inner_text("#flight-legend")
