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


# ------------------------------------------------------------------ plots frame everything they draw (issue 17)
def _inside(ax, xs, ys, tol=1e-9):
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    xs, ys = np.asarray(xs, float), np.asarray(ys, float)
    return bool(np.all((xs >= x0 - tol) & (xs <= x1 + tol) & (ys >= y0 - tol) & (ys <= y1 + tol)))


def _check_framed(fig, result):
    """Every drawn flight point, every bounce, the apex and the end are inside both views' limits."""
    import matplotlib.pyplot as plt

    ax_side, ax_top = fig.axes[:2]
    d = result.to_dict()
    try:
        for ax in (ax_side, ax_top):
            lines = [ln for ln in ax.get_lines() if ln.get_gid() in ("flight", "bounce", "end")]
            assert lines
            for ln in lines:
                assert _inside(ax, ln.get_xdata(), ln.get_ydata()), ln.get_gid()
        assert len([ln for ln in ax_top.get_lines() if ln.get_gid() == "bounce"]) == len(d.get("bounces", []))
        for b in d.get("bounces", []):
            assert _inside(ax_top, [b["x"]], [b["y"]]) and _inside(ax_side, [b["x"]], [0.0])
        assert _inside(ax_side, [d["apex"]["x"]], [d["apex"]["z"]])
        assert ax_side.get_ylim()[1] > d["apex"]["z"]
    finally:
        plt.close(fig)


@pytest.mark.parametrize(
    "launch",
    [
        # the case: the second bounce used to be off the axes
        dict(
            position=(-11.885, 0, 1.0),
            velocity=(27, 0, 7),
            spin_rpm=2500,
            spin_axis="topspin",
            bounces=2,
            surface="clay",
        ),
        # a high lob: its apex is far above the default 3 m
        dict(position=(-11.0, 0, 0.8), speed_kmh=80, elevation_deg=55, bounces=1),
        # a wide, long ball bouncing out of the court to the side
        dict(position=(-11.885, 3, 1.0), speed_kmh=150, elevation_deg=8, heading_deg=25, bounces=3),
    ],
)
def test_plots_frame_every_bounce_and_the_apex(launch):
    from tennislab.plot.trajectory import plot_trajectories
    from tennislab.trajectory import fly

    res = fly(**launch)
    _check_framed(plot_trajectories([res]), res)


def test_fly_plot_frames_the_second_bounce(capsys, tmp_path, monkeypatch):
    """Through the command: the figure `fly --bounces 2 --plot` saves holds both bounces."""
    from tennislab.cli import fly as fly_cli

    figs = []
    monkeypatch.setattr(fly_cli, "save_figure", lambda fig, path: figs.append(fig))
    args = [
        "fly",
        "--position",
        "-11.885",
        "0",
        "1.0",
        "--velocity",
        "27",
        "0",
        "7",
        "--spin-rpm",
        "2500",
        "--spin-axis",
        "0",
        "1",
        "0",
        "--surface",
        "clay",
        "--bounces",
        "2",
        "--plot",
        str(tmp_path / "f.png"),
    ]
    rc, out, err = run(capsys, *args)
    assert rc == 0, err
    from tennislab.trajectory import fly

    res = fly((-11.885, 0, 1.0), (27, 0, 7), spin_rpm=2500, spin_axis=(0, 1, 0), surface="clay", bounces=2)
    assert res.to_dict()["bounces"][1]["x"] > 15  # beyond the old fixed limit of 14.885 m
    _check_framed(figs[0], res)
