"""The three front-ends give the same numbers for the same inputs (issue 14: one test per use case).

For each use case the workflow's ``to_dict()`` is the reference: ``tennislab ... --json`` prints it
exactly (same process), the web app answers it (its worker processes may run separately compiled
kernels: floats to 1e-9, docs/batch.md "Reproducibility"), and the report prints its numbers.
"""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from tennislab.cli import main
from tennislab.core.flight import FlightParams
from tennislab.linecall import call_track
from tennislab.linecall.synth import sample_serve
from tennislab.plot.text import in_out_by
from tennislab.report import html as H
from tennislab.results import jsonable
from tennislab.trajectory import fly


def cli_json(capsys, *args) -> dict:
    rc = main([str(a) for a in args])
    out = capsys.readouterr()
    assert rc == 0, out.err
    return json.loads(out.out)


#: wall-clock keys and the provenance of a cache (``reach_map``: whether this call built the launcher's
#: reach map or found it in memory, and what that took): differ between any two runs
TIMINGS = {"elapsed_ms", "lookup_ms", "reach_map"}


def untimed(d):
    """``d`` without its wall-clock and cache-provenance keys."""
    if isinstance(d, dict):
        return {k: untimed(v) for k, v in d.items() if k not in TIMINGS}
    if isinstance(d, list):
        return [untimed(v) for v in d]
    return d


def same(a, b, path="", rel=0.0):
    """``a`` (a front-end's answer) holds ``b`` (the reference): every key of ``b``, equal values (floats
    within ``rel``)."""
    if isinstance(b, dict):
        assert isinstance(a, dict), path
        for k in b:
            if k in TIMINGS:
                continue
            assert k in a, f"{path}.{k} missing"
            same(a[k], b[k], f"{path}.{k}", rel)
    elif isinstance(b, list):
        assert isinstance(a, list) and len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            same(x, y, f"{path}[{i}]", rel)
    elif isinstance(b, float) and isinstance(a, float) and rel:
        assert a == pytest.approx(b, rel=rel, abs=1e-12), path
    else:
        assert a == b, path


@pytest.fixture(scope="module")
def report_html(tmp_path_factory):
    pytest.importorskip("matplotlib")
    from tennislab.report.build import build_report

    out = tmp_path_factory.mktemp("report") / "r.html"
    build_report(str(out), progress=None, only=["flight", "line-calling", "serve-windows", "launcher-drill"])
    return out.read_text(encoding="utf-8")


def cells(*values) -> str:
    """Adjacent table cells as the report writes them."""
    return "".join(f"<td>{v}</td>" for v in values)


# ------------------------------------------------------------------ flight
def test_flight(client, capsys, report_html):
    launch = dict(speed_kmh=180, elevation_deg=-4, heading_deg=-1.5, spin_rpm=2000, spin_axis=30)
    params = FlightParams.from_options(aero="stepanek1988")
    ref = jsonable(fly((-11.885, 0.5, 2.8), **launch, params=params, bounces=1, surface="clay").to_dict())
    cli = cli_json(
        capsys, "fly", "--position", -11.885, 0.5, 2.8, "--speed-kmh", 180, "--elevation-deg", -4,
        "--heading-deg", -1.5, "--spin-rpm", 2000, "--spin-axis", 30, "--aero", "stepanek1988",
        "--bounces", 1, "--surface", "clay", "--json",
    )  # fmt: skip
    assert cli == ref
    body = {"x": -11.885, "y": 0.5, "z": 2.8, "speed_kmh": 180, "elevation_deg": -4, "heading_deg": -1.5,
            "spin_rpm": 2000, "spin_axis_deg": 30, "aero": "stepanek1988", "bounces": 1, "surface": "clay"}  # fmt: skip
    app = client.post("/api/flight", json=body).json()
    same(app, ref, rel=1e-9)
    # the report's aero-model table: the flat serve of report/flight_section.py under each model
    from tennislab.report.flight_section import MODELS

    for m in MODELS:
        d = cli_json(
            capsys, "fly", "--position", -11.885, 0.5, 2.8, "--velocity", 49.5, -1.5, -4.5, "--aero", m, "--json"
        )
        row = cells(H.num(d["landing"]["x"], 2), H.num(d["landing"]["y"], 2), H.num(d["apex"]["z"], 2))
        assert row in report_html, m


# ------------------------------------------------------------------ one serve
def test_serve(client, capsys):
    from tennislab.serve import simulate
    from tennislab.serve.pipeline import default_flight

    ref = jsonable(simulate("professional", 40, 19).to_dict())
    cli = cli_json(capsys, "serve", "--player", "professional", "--impact-angle", 40, "--face-angle", 19, "--json")
    physics = {"physics": jsonable(default_flight().to_dict()), "physics_preset": "standard"}
    assert cli == {**ref, **physics}  # the result's to_dict() and the physics it flew
    app = client.post("/api/serve", json={"player": "professional", "impact_angle": 40, "face_angle": 19}).json()
    same(app, {**ref, **physics}, rel=1e-9)


# ------------------------------------------------------------------ the serve window (Table 1)
def test_serve_window(client, capsys, report_html):
    from tennislab.serve import window

    ref = jsonable(window("junior", step=1.0).to_dict())
    cli = cli_json(capsys, "serve-window", "--player", "junior", "--step", 1, "--json")
    same(cli, ref)
    app = client.post("/api/serve/window", json={"player": "junior", "step": 1}).json()
    same(app["summary"], ref["summary"], rel=1e-9)
    same(app["optimum"], ref["optimum"], rel=1e-9)
    # the report's Table 1 row of the junior (the paper's constants, as serve-window --preset seed000):
    # the counts of successful flat and topspin serves
    paper = jsonable(window("junior", step=1.0, preset="seed000").to_dict())
    cli = cli_json(capsys, "serve-window", "--player", "junior", "--step", 1, "--preset", "seed000", "--json")
    same(cli, paper)
    assert cli["physics_preset"] == "seed000" and paper["summary"] != ref["summary"]
    sec = report_html[report_html.index('id="serve-windows"') : report_html.index('id="line-calling"')]
    assert "preset seed000" in sec
    for cat in ("flat", "topspin"):
        n = paper["summary"][cat]["n"]
        row = rf'<td class="l">junior</td><td class="l">{cat}</td><td class="l">tennislab</td><td>{n}</td>'
        assert re.search(row, sec), cat


# ------------------------------------------------------------------ line call
def test_line_call(client, capsys, tmp_path, report_html):
    tr = sample_serve(seed=7)  # the report's example track
    ref = jsonable(call_track(tr.t, tr.xyz, np.full(tr.t.size, 3e-3), surface="hard", target="deuce-box").to_dict())
    text = client.get("/api/linecall/sample").text  # the app's example track: the same samples, full precision
    path = tmp_path / "sample.csv"
    path.write_text(text)
    cli = cli_json(capsys, "call", "--track", path, "--target", "deuce-box", "--json")
    assert untimed(cli) == untimed(ref)
    app = client.post("/api/linecall", json={"csv": text, "target": "deuce-box"}).json()
    same(app, ref, rel=1e-9)
    sec = report_html[report_html.index('id="line-calling"') : report_html.index('id="launcher-drill"')]
    assert f"{H.num(ref['bounce']['x'], 4)}, {H.num(ref['bounce']['y'], 4)}" in sec
    assert f">{in_out_by(ref['distance_mm'])}</td>" in sec and f">{H.num(ref['p_in'], 3)}</td>" in sec


# ------------------------------------------------------------------ launcher aim
def test_launcher_aim(client, capsys):
    from tennislab.launcher import aim

    ref = {**jsonable(aim((9.0, 2.0), 80, 1500, 0.0, 1.0).to_dict()), "physics_preset": "standard"}
    cli = cli_json(
        capsys, "launcher", "aim", "--target", 9, 2, "--speed-kmh", 80, "--spin-rpm", 1500, "--height", 1, "--json"
    )
    assert untimed(cli) == untimed(ref)
    searched = cli_json(capsys, "launcher", "aim", "--target", 9, 2, "--speed-kmh", 80, "--spin-rpm", 1500, "--json")
    searched_ref = {**jsonable(aim((9.0, 2.0), 80, 1500).to_dict()), "physics_preset": "standard"}
    assert untimed(searched) == untimed(searched_ref) and searched["height_searched"]
    body = {"target_x": 9, "target_y": 2, "speed_kmh": 80, "spin_rpm": 1500, "shot": "topspin"}
    app = client.post("/api/launcher/aim", json=body).json()
    same(untimed(app), untimed(ref), rel=1e-9)


# ------------------------------------------------------------------ a drill
def test_drill(capsys, report_html):
    d = cli_json(capsys, "launcher", "drill", "baseline_rally", "--json")
    sec = report_html[report_html.index('id="launcher-drill"') :]
    keys = ("speed_kmh", "elevation_deg", "heading_deg", "spin_rpm", "spin_axis_deg", "rpm1", "rpm2")
    distinct = {tuple(s[k] for k in keys) for s in d["shots"]}
    assert len(distinct) == d["n_distinct"] > 1
    for key in distinct:  # every distinct shot of the CLI is a row of the report's table, same settings
        row = cells(*(H.num(v, 0) for v in key))
        assert row in sec, key
