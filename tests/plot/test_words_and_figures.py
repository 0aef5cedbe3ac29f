"""What people read: signed distances, spin axes, fitted values with their ±, players by their numbers
(tennislab.plot.text); every marker of a flight figure explained, the court in its surface's colours,
Monte Carlo faults told apart; importing the plotting package chooses no Matplotlib backend."""

from __future__ import annotations

import os
import subprocess
import sys

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from tennislab.core.court import ITF_COURT
from tennislab.plot import text as T
from tennislab.serve import PlayerProfile


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    import matplotlib.pyplot as plt

    plt.close("all")


# ------------------------------------------------------------------ words
@pytest.mark.parametrize(
    "mm, said",
    [(7.6, "in by 7.6 mm"), (-0.6, "out by 0.6 mm"), (0.0, "in by 0.0 mm"), (-5488.05, "out by 5.49 m"), (None, "–")],
)
def test_signed_distances_in_words(mm, said):
    assert T.in_out_by(mm) == said


@pytest.mark.parametrize(
    "deg, said",
    [
        (0.0, "topspin"),
        (1e-9, "topspin"),
        (180.0, "backspin"),
        (-180.0, "backspin"),
        (540.0, "backspin"),
        (90.0, "sidespin (curving left)"),
        (-90.0, "sidespin (curving right)"),
        (30.0, "topspin and sidespin to the left (axis 30°)"),
        (-120.0, "backspin and sidespin to the right (axis -120°)"),
        (None, "along the path"),
    ],
)
def test_spin_axes_by_name(deg, said):
    assert T.spin_axis_name(deg) == said


def test_numbers_rounded_for_people():
    assert T.spin_words(1500.0000000000002, 0.0) == "1500 rpm topspin"
    assert T.spin_words(0.2, None) == "no spin"
    assert T.num(-0.04) == "0.0" and T.num(float("nan")) == "–"
    assert T.plus_minus(1115.3, 4922.1, "rpm") == "1115 ± 4922 rpm"
    assert T.plus_minus(1.0006, None, digits=3) == "1.001"


def test_a_fitted_spin_is_said_with_its_uncertainty():
    sp = {"rpm": 1115.0, "topspin_rpm": 10.0, "sidespin_rpm": -5.0, "along_path_rpm": 1100.0}
    sp |= {"topspin_sigma_rpm": 300.0, "sidespin_sigma_rpm": 200.0, "along_path_sigma_rpm": 4922.0}
    said = T.spin_fit_words(sp)
    total = np.sqrt(300.0**2 + 200.0**2 + 4922.0**2)
    assert said.startswith(f"1115 ± {total:.0f} rpm, not told apart from no spin (")
    assert "along path +1100 ± 4922" in said
    clear = dict(sp, rpm=2600.0, along_path_sigma_rpm=100.0)
    assert "not told apart" not in T.spin_fit_words(clear)


def test_players_by_their_numbers_not_a_star():
    p = PlayerProfile("professional", 3.0, 40.0).with_overrides(impact_height=2.5, racket_speed=35.0)
    assert p.name == "professional*"  # the JSON's name, unchanged
    assert T.player_words(p) == "professional, 2.5 m, 35 m/s"
    assert T.player_words(PlayerProfile("junior", 2.2, 25.0)) == "junior"


def test_court_judges_long_wide_short():
    c = ITF_COURT
    assert c.judge("ad-box", 5.0, -1.0) == "in" and c.judge("ad-box", 7.4, -0.1) == "long"
    assert c.judge("ad-box", 5.0, 1.0) == "wide" and c.judge("singles", -2.0, 0.0) == "short"
    assert c.judge("near-deuce-box", -7.0, -1.0) == "long" and c.judge("near-deuce-box", 1.0, -1.0) == "short"
    assert c.judge("full-singles", 12.5, 0.0) == "long" and c.judge("full-singles", -12.5, 0.0) == "long"
    assert c.judge("singles", 11.885 + 1e-9, 0.0) == "long" and c.judge("singles", 11.885, 4.115) == "in"


# ------------------------------------------------------------------ figures
def _legend_texts(ax) -> list[str]:
    return [t.get_text() for t in ax.get_legend().get_texts()]


def test_flight_figure_says_what_was_flown_and_explains_every_marker():
    from tennislab.plot.court import SURFACE_COLORS
    from tennislab.plot.trajectory import plot_trajectories
    from tennislab.trajectory import fly

    res = fly((-11.885, 0, 1.0), speed_kmh=88.4, elevation_deg=8, heading_deg=-3, spin_rpm=1500, spin_axis="slice")
    res2 = fly(
        (-11.885, 0, 1.0), speed_kmh=88.4, elevation_deg=8, spin_rpm=1500, spin_axis="slice", bounces=2, surface="clay"
    )
    fig = plot_trajectories([res2])
    ax_side, ax_top = fig.axes[:2]
    title = fig._suptitle.get_text()
    assert title.startswith("88 km/h, elevation 8.0°, heading 0.0°, 1500 rpm backspin, from (-11.88, 0.00, 1.00) m")
    assert "2 bounces on clay" in title and "aero choppin2018" in title
    legend = _legend_texts(ax_side)
    gids = {ln.get_gid() for ln in ax_top.get_lines()}
    assert {"launch", "bounce", "end"} <= gids
    assert "launch" in legend and any(t.startswith("bounce") for t in legend)
    assert "landing 3: the flight shown ends (2 bounces asked)" in legend  # the third dot, explained
    court = [p for p in ax_top.patches if p.get_width() > 20][0]
    assert matplotlib.colors.to_hex(court.get_facecolor()) == SURFACE_COLORS["clay"][0]
    one = plot_trajectories([res])
    assert "landing" in _legend_texts(one.axes[0]) and "bounce" not in " ".join(_legend_texts(one.axes[0]))
    court = [p for p in one.axes[1].patches if p.get_width() > 20][0]
    assert matplotlib.colors.to_hex(court.get_facecolor()) == SURFACE_COLORS["hard"][0]


def test_monte_carlo_figure_tells_net_long_and_wide_apart():
    from tennislab.plot.serve import plot_mc
    from tennislab.serve import monte_carlo

    res = monte_carlo("professional", 40, 19, n=600, seed=3, sd_angle=3.0, samples=True)
    reason = res.samples["reason"]
    assert np.array_equal(reason == 0, res.samples["success"])
    codes = {r["reason"] for r in res.rows()}
    assert {"in", "net", "long"} <= codes, codes
    legend = " ".join(_legend_texts(plot_mc(res).axes[0]))
    assert "net (drawn where it would land)" in legend and "long:" in legend and "in:" in legend
    wide = monte_carlo("professional", 40, 19, n=400, seed=3, sd_angle=3.0, target="deuce", samples=True)
    assert "wide" in {r["reason"] for r in wide.rows()}


def test_window_maps_span_where_the_window_is():
    from tennislab.plot.serve import plot_window_maps, window_span
    from tennislab.serve import window

    w = window("junior", step=3.0)
    a0, a1, b0, b1 = window_span(w)
    ib, ia = np.nonzero(w.success)
    assert b0 <= w.beta_deg[ib].min() and w.beta_deg[ib].max() <= b1 < 60
    assert a0 <= w.alpha_deg[ia].min() and w.alpha_deg[ia].max() <= a1
    ax = plot_window_maps([w]).axes[0]
    assert ax.get_ylim()[1] < 60 and "junior" in ax.get_title()


# ------------------------------------------------------------------ the backend is the entry point's
def _python(code: str, **env) -> str:
    e = {k: v for k, v in os.environ.items() if k != "MPLBACKEND"} | env
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=e).stdout


def test_importing_the_plot_package_chooses_no_backend():
    code = (
        "import sys\n"
        "import tennislab.plot, tennislab.plot.court, tennislab.plot.trajectory, tennislab.plot.serve\n"
        "import tennislab.plot.linecall, tennislab.plot.launcher, tennislab.plot.calibrate, tennislab.plot.save\n"
        "print('matplotlib' in sys.modules)\n"
        "import matplotlib\n"
        "print(matplotlib.get_backend())\n"
    )
    assert _python(code, MPLBACKEND="svg").split() == ["False", "svg"]


def test_the_command_line_chooses_agg():
    code = (
        "import os, tennislab.cli as c\n"
        "try:\n    c.main(['--version'])\nexcept SystemExit:\n    pass\n"
        "print(os.environ.get('MPLBACKEND'))\n"
    )
    assert _python(code).split()[-1] == "Agg"
