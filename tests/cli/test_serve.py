"""CLI contract of `impact`, `serve`, `serve-window`, `serve-mc` (issue 3): JSON keys, flags, errors; the
commands print what the workflows' results say (verdict, caveats) and reject flags they would ignore."""

import csv
import json

import pytest

from tennislab.cli import main


def run(capsys, *args):
    rc = main(list(args))
    out = capsys.readouterr()
    return rc, out.out, out.err


def test_impact_json_contract(capsys, tmp_path):
    png = tmp_path / "imp.png"
    rc, out, _ = run(
        capsys,
        "impact",
        "--racket-speed",
        "40",
        "--impact-angle",
        "21",
        "--face-angle",
        "35",
        "--racket-mass",
        "0.25",
        "--string-stiffness",
        "45000",
        "--friction",
        "0.4",
        "--json",
        "--plot",
        str(png),
    )
    assert rc == 0 and png.stat().st_size > 10_000
    d = json.loads(out)
    for k in ("speed", "spin_rpm", "launch_angle"):
        assert isinstance(d["ball"][k], float)
    assert d["regime"] in ("slide", "roll") and d["contact_time_ms"] > 1
    assert d["inputs"]["racket_mass"] == 0.25 and d["inputs"]["friction"] == 0.4


def test_impact_zero_angle_and_ball_flags(capsys):
    rc, out, _ = run(
        capsys,
        "impact",
        "--racket-speed",
        "30",
        "--impact-angle",
        "0",
        "--face-angle",
        "0",
        "--mass",
        "0.057",
        "--radius",
        "0.0335",
        "--json",
    )
    d = json.loads(out)
    assert rc == 0 and d["ball"]["spin_rpm"] == 0 and d["ball"]["launch_angle"] == 0
    assert d["inputs"]["ball_mass"] == 0.057
    assert any("placeholder" in c for c in d["caveats"])


@pytest.mark.parametrize(
    "flag", [("--wind", "1", "0", "0"), ("--aero", "constant"), ("--cd", "0.6"), ("--cl", "0.2"), ("--gravity", "9.8")]
)
def test_impact_rejects_flight_flags(capsys, flag):
    """`impact` has no flight: the flight's physics flags are refused, not ignored."""
    with pytest.raises(SystemExit) as e:
        main(["impact", "--racket-speed", "30", "--impact-angle", "10", *flag])
    err = capsys.readouterr().err
    assert e.value.code == 2 and "unrecognized arguments" in err and flag[0] in err


def test_impact_seed_literal_scheme(capsys):
    args = ("impact", "--racket-speed", "40", "--impact-angle", "36", "--json")
    _, out, _ = run(capsys, *args, "--impact-scheme", "seed-literal")
    d = json.loads(out)
    assert d["inputs"]["friction_model"] == "seed-clamp" and d["inputs"]["approach_gap_m"] == 0.02
    assert d["inputs"]["integrator"] == "euler" and d["inputs"]["dt_s"] == 1e-4
    assert any("Euler" in c for c in d["caveats"]) and any("seed-clamp" in c for c in d["caveats"])
    # single flags override the scheme
    _, out2, _ = run(capsys, *args, "--impact-scheme", "seed-literal", "--integrator", "rk4", "--dt", "0")
    d2 = json.loads(out2)
    assert d2["inputs"]["integrator"] == "rk4" and not any("Euler" in c for c in d2["caveats"])


def test_serve_json_contract(capsys):
    rc, out, _ = run(capsys, "serve", "--player", "pro", "--impact-angle", "3", "--face-angle", "8", "--json")
    assert rc == 0
    d = json.loads(out)
    for k in ("speed", "spin_rpm", "launch_angle", "net_height", "landing_x"):
        assert isinstance(d[k], float)
    assert d["success"] is True and d["category"] == "flat"
    assert d["verdict"]["success"] is True and d["verdict"]["reason"] is None
    assert set(d["verdict"]) == {"success", "reason", "detail", "advice"} and isinstance(d["caveats"], list)


def test_serve_text_says_why_it_failed(capsys):
    rc, out, _ = run(capsys, "serve", "--player", "pro", "--impact-angle", "36", "--face-angle", "21")
    lines = out.splitlines()
    assert rc == 0 and any(ln.startswith("FAULT (net): ") for ln in lines)
    assert any(ln.startswith("advice: Open the face") for ln in lines)
    assert sum(ln.startswith("note: ") for ln in lines) == 2  # placeholder ball data, 2-D criteria
    assert "seed 000" not in out and "seed-2d" not in out and "the paper's 2-D test" in out


def test_serve_3d_and_plot(capsys, tmp_path):
    png = tmp_path / "s.png"
    rc, out, _ = run(
        capsys,
        "serve",
        "--player",
        "rec",
        "--impact-angle",
        "40",
        "--face-angle",
        "15",
        "--target",
        "deuce",
        "--azimuth",
        "5",
        "--server-y",
        "-0.4",
        "--brush",
        "-30",
        "--plot",
        str(png),
        "--gravity",
        "9.81",
    )
    assert rc == 0 and png.stat().st_size > 10_000 and "the real net and deuce-box" in out


def test_serve_window_contract(capsys, tmp_path):
    f = tmp_path / "w.csv"
    png = tmp_path / "w.png"
    rc, out, _ = run(
        capsys, "serve-window", "--player", "junior", "--step", "2", "--json", "--csv", str(f), "--plot", str(png)
    )
    assert rc == 0
    d = json.loads(out)
    for cat in ("flat", "topspin"):
        s = d["summary"][cat]
        assert isinstance(s["n"], int)
        for k in ("beta", "alpha", "spin_rpm", "speed", "landing_x", "net_height", "launch_angle"):
            assert len(s[k]) == 2 and s[k][0] <= s[k][1]
        assert d["optimum"][cat]["success"] is True
    assert isinstance(d["peak_spin_alpha"], float)
    assert len(d["by_alpha"]["spin_rpm"]) == 46 and d["by_alpha"]["regime"][0] == "roll"
    assert all(r[1] <= r[2] for r in d["alpha_range_by_beta"]["topspin"])
    assert d["published"]["summary"]["flat"]["n"] == 17 and d["caveats"]
    rows = list(csv.DictReader(f.open()))
    assert len(rows) == 46 * 46 and set(rows[0]) >= {"alpha", "beta", "success", "category"}
    assert png.stat().st_size > 10_000


def test_serve_window_text_and_aliases(capsys):
    rc, out, _ = run(capsys, "serve-window", "--player", "rec", "--step", "3")
    assert rc == 0 and "  paper" in out and "peak spin" in out and "(paper 35)" in out and "note: " in out


def test_serve_mc_contract(capsys, tmp_path):
    png = tmp_path / "mc.png"
    args = (
        "serve-mc",
        "--player",
        "pro",
        "--impact-angle",
        "40",
        "--face-angle",
        "19",
        "--sd-angle",
        "1",
        "--sd-speed",
        "1",
        "--n",
        "2000",
        "--seed",
        "3",
        "--json",
    )
    rc, out, _ = run(capsys, *args, "--plot", str(png))
    assert rc == 0 and png.stat().st_size > 10_000
    d = json.loads(out)
    assert 0 <= d["p_success"] <= 1
    assert len(d["landing"]["mean"]) == 2 and len(d["landing"]["cov"]) == 2
    rc, out2, _ = run(capsys, *args)
    assert json.loads(out2)["p_success"] == d["p_success"]


def test_serve_mc_scheduler_flag(capsys):
    pytest.importorskip("tennislab.batch")
    rc, out, _ = run(
        capsys,
        "serve-mc",
        "--player",
        "junior",
        "--impact-angle",
        "45",
        "--face-angle",
        "10",
        "--n",
        "1000",
        "--scheduler",
        "local",
        "--chunk-size",
        "300",
        "--json",
    )
    rc0, out0, _ = run(
        capsys, "serve-mc", "--player", "junior", "--impact-angle", "45", "--face-angle", "10", "--n", "1000", "--json"
    )
    assert rc == rc0 == 0 and json.loads(out) == json.loads(out0)


def test_serve_mc_json_keys_and_resume(capsys, tmp_path):
    """Contract keys stay; --out-dir stores per-block statistics (3 blocks of 1024 serves), a rerun resumes
    them and prints the same JSON."""
    pytest.importorskip("pyarrow")
    args = (
        "serve-mc",
        "--player",
        "rec",
        "--impact-angle",
        "40",
        "--face-angle",
        "15",
        "--n",
        "2500",
        "--seed",
        "9",
        "--out-dir",
        str(tmp_path / "mc"),
        "--no-progress",
        "--json",
    )
    rc, out, _ = run(capsys, *args)
    d = json.loads(out)
    assert rc == 0 and {"p_success", "p_success_se", "landing", "landing_x", "n_landed", "n", "seed"} <= set(d)
    assert {"mean", "cov", "ellipse_95"} <= set(d["landing"]) and d["n"] == 2500
    assert len(list((tmp_path / "mc").glob("part-*.parquet"))) == 3
    rc, out2, _ = run(capsys, *args)
    assert rc == 0 and json.loads(out2) == d


@pytest.mark.parametrize(
    "args, field",
    [
        (("impact", "--racket-speed", "40", "--impact-angle", "95"), "--impact-angle"),
        (("impact", "--racket-speed", "40", "--impact-angle", "10", "--friction", "-1"), "--friction"),
        (("impact", "--racket-speed", "400", "--impact-angle", "10"), "--racket-speed"),
        (("impact", "--racket-speed", "40", "--impact-angle", "10", "--approach-gap", "1"), "--approach-gap"),
        (("serve", "--player", "nobody", "--impact-angle", "3", "--face-angle", "8"), "--player"),
        (("serve", "--impact-angle", "3", "--face-angle", "8", "--azimuth", "5"), "target"),
        (("serve", "--impact-angle", "3", "--face-angle", "95"), "--face-angle"),
        (("serve", "--impact-angle", "3", "--face-angle", "8", "--toss-velocity", "99"), "--toss-vz"),
        (("serve-window", "--step", "0"), "--step"),
        (("serve-mc", "--impact-angle", "3", "--face-angle", "8", "--n", "0"), "--n"),
        (("serve", "--impact-angle", "3", "--face-angle", "8", "--ball-model", "rubber"), "--ball-model"),
        (("serve", "--impact-angle", "3", "--face-angle", "8", "--impact-height", "9"), "--impact-height"),
    ],
)
def test_bad_input_exit_2(capsys, args, field):
    rc, out, err = run(capsys, *args)
    assert rc == 2 and field in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_no_half_written_csv_on_error(capsys, tmp_path):
    f = tmp_path / "w.csv"
    rc, _, _ = run(capsys, "serve-window", "--step", "-1", "--csv", str(f))
    assert rc == 2 and not f.exists()


def test_serve_window_all_players(capsys, tmp_path):
    f = tmp_path / "all.csv"
    rc, out, _ = run(capsys, "serve-window", "--player", "all", "--step", "5", "--json", "--csv", str(f))
    assert rc == 0
    d = json.loads(out)["players"]
    assert set(d) == {"professional", "recreational", "junior"}
    assert all("flat" in d[p]["summary"] and "published" in d[p] for p in d)
    rows = list(csv.DictReader(f.open()))
    assert len(rows) == 3 * 19 * 19 and {r["player"] for r in rows} == set(d)


@pytest.mark.parametrize("cmd", ["impact", "serve", "serve-window", "serve-mc"])
def test_help(capsys, cmd):
    with pytest.raises(SystemExit) as e:
        main([cmd, "--help"])
    out = capsys.readouterr().out
    assert e.value.code == 0 and "--json" in out
    # the paper by name, not the project's internal "seed 000"; the scheme values are explained
    assert "seed 000" not in out and "seed-2d" not in out
    assert "--impact-scheme" in out and "Grosen" in out
