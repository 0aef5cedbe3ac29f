"""Trajectory figures: side and top views of one or more flights on the court."""

from __future__ import annotations

import numpy as np

from tennislab.plot.court import court_figure


def plot_trajectories(trajectories, labels=None, title: str | None = None, court=None):
    """Side and top views of :class:`~tennislab.core.flight.Trajectory` objects (or lists of
    (t, states) samples).  Returns the figure."""
    kw = {} if court is None else {"court": court}
    fig, ax_side, ax_top = court_figure(title=title, **kw)
    zmax = 3.0
    for i, tr in enumerate(trajectories):
        if hasattr(tr, "sample"):
            _, ys = tr.sample(400)
        else:
            ys = np.asarray(tr[1])
        lab = labels[i] if labels else None
        (line,) = ax_side.plot(ys[:, 0], ys[:, 2], lw=1.8, label=lab)
        ax_top.plot(ys[:, 0], ys[:, 1], lw=1.8, color=line.get_color())
        ax_top.plot(ys[-1, 0], ys[-1, 1], "o", ms=5, color=line.get_color(), mec="k")
        zmax = max(zmax, float(np.nanmax(ys[:, 2])) + 0.5)
    ax_side.set_ylim(0, zmax)
    if labels:
        ax_side.legend(loc="upper right", fontsize=8)
    return fig
