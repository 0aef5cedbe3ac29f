"""The court's restitution and friction fitted to measured bounces, and the surface file it writes."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from tennislab.calibrate import calibrate_surface
from tennislab.cli import main
from tennislab.core.bounce import bounce_batch
from tennislab.core.surfaces import Surface
from tennislab.errors import InputError
from tennislab.io.surface_file import read_surface

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "points" / "synthetic_points.json"


def _bounces(surface: Surface, n: int = 80, noise: float = 0.15, seed: int = 3):
    """Incoming balls of real play (serves, drives, lobs: 10-40 m/s, 5-40 deg down, up to 3,000 rpm)."""
    g = np.random.default_rng(seed)
    speed, angle = g.uniform(10, 40, n), np.radians(g.uniform(5, 40, n))
    heading = np.radians(g.uniform(-15, 15, n))
    vin = np.column_stack([speed * np.cos(angle) * np.cos(heading), speed * np.cos(angle) * np.sin(heading),
                           -speed * np.sin(angle)])  # fmt: skip
    win = g.normal(0, 150, (n, 3))
    vout, _, _ = bounce_batch(vin, win, surface)
    return vin, win, vout + g.normal(0, noise, vout.shape)


def test_recovers_a_known_court():
    """Synthetic truth from the same bounce model: proves the fit, not the model."""
    truth = Surface("truth", e=0.72, mu=0.55)
    vin, win, vout = _bounces(truth)
    r = calibrate_surface(vin, win, vout, base="hard")
    s, sd = r.surface, r.sd
    assert abs(s.e - 0.72) < max(3 * sd["e"], 0.01) and abs(s.mu - 0.55) < max(3 * sd["mu"], 0.01)
    assert r.rms_after_ms < r.rms_before_ms and r.rms_after_ms == pytest.approx(0.15, rel=0.3)
    d = r.to_dict()
    assert d["n_bounces"] == 80 and d["free"] == ["e", "mu"]
    assert d["cpr_category"] in {"slow", "medium-slow", "medium", "medium-fast", "fast"}
    assert len(r.rows()) == 80 and set(r.rows()[0]) >= {"vin_z_ms", "res_x_ms"}


def test_bad_requests_name_the_parameter():
    vin, win, vout = _bounces(Surface("t", e=0.8, mu=0.6), n=5)
    with pytest.raises(InputError, match="^fit: unknown parameter 'k'"):
        calibrate_surface(vin, win, vout, fit=("e", "k"))
    with pytest.raises(InputError, match="^velocity_out: 2 usable bounces"):
        calibrate_surface(vin[:2], win[:2], vout[:2])
    with pytest.raises(InputError, match="^velocity_in: expected an \\(N, 3\\) array"):
        calibrate_surface(vin[:, :2], win, vout)
    vout[:, 2] = -1.0  # nothing goes up after the "bounce"
    with pytest.raises(InputError, match="usable bounces"):
        calibrate_surface(vin, win, vout)


def test_surface_file_round_trip_and_every_command_reads_it(tmp_path, capsys):
    vin, win, vout = _bounces(Surface("t", e=0.7, mu=0.5), n=30)
    r = calibrate_surface(vin, win, vout, name="club-court")
    f = tmp_path / "court.toml"
    f.write_text(r.surface_toml())
    d = read_surface(str(f))
    assert d["name"] == "club-court" and d["e"] == pytest.approx(r.surface.e, abs=1e-4)
    assert d["mu"] == pytest.approx(r.surface.mu, abs=1e-4)
    args = ["fly", "--speed-kmh", "100", "--elevation-deg", "10", "--bounces", "1", "--json"]
    assert main([*args, "--surface", str(f)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["surface"] == "club-court"
    assert main([*args, "--surface", "hard"]) == 0
    assert json.loads(capsys.readouterr().out)["bounces"][0]["velocity_out"] != out["bounces"][0]["velocity_out"]


def test_cli_calibrates_from_a_rally_and_writes_the_surface(tmp_path, capsys):
    out = tmp_path / "court.toml"
    rc = main(["calibrate", "surface", "--rally", str(EXAMPLE), "--out-surface", str(out), "--json", "--quiet"])
    assert rc == 0
    d = json.loads(capsys.readouterr().out)
    assert d["n_bounces"] >= 3 and 0 < d["surface"]["e"] <= 1 and out.exists()
    # the example was made on the hard court (e 0.80, mu 0.65): the fit agrees within its uncertainty
    assert abs(d["surface"]["e"] - 0.80) < 3 * d["sd"]["e"] + 0.02
    assert abs(d["surface"]["mu"] - 0.65) < 3 * d["sd"]["mu"] + 0.02


@pytest.mark.parametrize(
    "text,frag",
    [
        ("e = 0.8\n", "mu: missing"),
        ("e = 0.8\nmu = 'x'\n", "mu: expected a finite number"),
        ("e = 0.8\nmu = 0.6\nfoo = 1\n", "foo: unknown key"),
        ("e = [\n", "not valid TOML"),
        ("e = 1.5\nmu = 0.6\n", "surface e: 1.5"),
    ],
)
def test_bad_surface_files_are_one_line(tmp_path, capsys, text, frag):
    f = tmp_path / "bad.toml"
    f.write_text(text)
    rc = main(["fly", "--speed-kmh", "100", "--elevation-deg", "10", "--bounces", "1", "--surface", str(f)])
    err = capsys.readouterr().err
    assert rc == 2 and frag in err and err.count("\n") == 1 and "Traceback" not in err


def test_measured_bounces_take_only_post_fit_bounces():
    from tennislab.calibrate import measured_bounces

    b = {"velocity_in": [20.0, 0.0, -5.0], "spin_in": [0.0, 100.0, 0.0], "velocity_out": [15.0, 0.0, 4.0]}
    calls = [
        {"bounce": b, "fit": {"velocity_out_from": "post-fit"}},
        {"bounce": b, "fit": {"velocity_out_from": "bounce-model"}},  # the model's own answer: not a measurement
        {"bounce": None, "fit": None},  # a net ball
        {"bounce": {**b, "velocity_out": None}, "fit": {"velocity_out_from": "post-fit"}},
    ]
    vi, wi, vo = measured_bounces(calls)
    assert vi == [b["velocity_in"]] and wi == [b["spin_in"]] and vo == [b["velocity_out"]]
