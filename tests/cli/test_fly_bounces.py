"""`tennislab fly --surface NAME --bounces N`: the JSON `bounces` list (issue 4)."""

import json

import numpy as np
import pytest

from tennislab.cli import main

ARGS = ["fly", "--position", "-11.885", "0", "2.8", "--velocity", "50", "0", "-3", "--spin", "0", "200", "0"]


def run(capsys, *args):
    rc = main(list(args))
    out = capsys.readouterr()
    return rc, out.out, out.err


def test_bounces_json_contract(capsys):
    rc, out, _ = run(capsys, *ARGS, "--surface", "clay", "--bounces", "2", "--json")
    assert rc == 0
    d = json.loads(out)
    assert d["bounce"]["x"] == pytest.approx(d["bounces"][0]["x"])  # existing keys kept
    assert d["net"]["result"] == "over" and "apex" in d
    assert len(d["bounces"]) == 2
    for b in d["bounces"]:
        for k in ("x", "y", "t"):
            assert isinstance(b[k], float)
        for k in ("velocity_in", "velocity_out", "spin_out"):
            assert len(b[k]) == 3
        assert 0.02 < b["mark"]["length"] < 0.3 and 0.02 < b["mark"]["width"] <= 0.067
        assert b["velocity_out"][2] > 0 > b["velocity_in"][2]
    assert d["bounces"][1]["t"] > d["bounces"][0]["t"]


def test_surface_changes_the_bounce(capsys):
    outs = {}
    for s in ("clay", "grass"):
        rc, out, _ = run(capsys, *ARGS, "--surface", s, "--bounces", "1", "--json")
        outs[s] = json.loads(out)["bounces"][0]
    # grass keeps more horizontal speed and bounces lower than clay (reference-data.md)
    h = {s: np.hypot(*outs[s]["velocity_out"][:2]) / np.hypot(*outs[s]["velocity_in"][:2]) for s in outs}
    assert h["grass"] > h["clay"]
    assert outs["grass"]["velocity_out"][2] < outs["clay"]["velocity_out"][2]


def test_without_bounces_no_list(capsys):
    rc, out, _ = run(capsys, *ARGS, "--json")
    assert rc == 0 and "bounces" not in json.loads(out)


def test_text_output_and_plot(capsys, tmp_path):
    png = tmp_path / "b.png"
    rc, out, _ = run(capsys, *ARGS, "--bounces", "2", "--plot", str(png))
    assert rc == 0 and "bounce 2 (hard" in out and png.stat().st_size > 10_000


@pytest.mark.parametrize(
    "bad,msg", [(["--surface", "ice", "--bounces", "1"], "surface"), (["--bounces", "-1"], "--bounces")]
)
def test_bad_input(capsys, bad, msg):
    rc, out, err = run(capsys, *ARGS, *bad)
    assert rc == 2 and msg in err and len(err.strip().splitlines()) == 1
