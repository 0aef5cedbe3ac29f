"""Launcher figures frame everything they draw (issue 17)."""

import matplotlib

matplotlib.use("Agg")

from tennislab.launcher import aim
from tennislab.launcher.aim import fly_settings
from tennislab.plot.launcher import plot_aim


def test_aimed_lob_is_inside_both_views():
    r = aim((10.0, 3.0), 75, 1000, 0.0, 1.0, trajectory="high")
    tr = fly_settings(r.settings, r.spec, r.params)
    fig = plot_aim(r.solution, tr)
    for ax in fig.axes[:2]:
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        for line in ax.get_lines():
            xs, ys = line.get_xdata(), line.get_ydata()
            assert x0 <= min(xs) and max(xs) <= x1 and y0 <= min(ys) and max(ys) <= y1
    assert tr.apex.z > 4 and fig.axes[0].get_ylim()[1] > tr.apex.z
