"""Trajectory figures: side and top views of one or more flights on the court.

Every flight is one colour; its bounces are marked (o) and its last point too.  The views are
framed (:func:`tennislab.plot.court.frame_views`) so that every bounce and the whole apex are inside
the axes.  Drawn flight lines carry ``gid="flight"``, bounce markers ``gid="bounce"`` and end markers
``gid="end"`` (tests find them by these ids).
"""

from __future__ import annotations

import numpy as np

from tennislab.core.court import ITF_COURT
from tennislab.plot.court import court_figure, frame_views


def _segments(item) -> list:
    """The segments of one flight: a result with ``segments``, a trajectory, a list of trajectories,
    or ``(t, states)`` samples."""
    segs = getattr(item, "segments", None)
    if segs is not None:
        return list(segs)
    if hasattr(item, "sample"):
        return [item]
    if isinstance(item, (list, tuple)) and len(item) == 2 and np.ndim(item[1]) == 2:
        return [item]
    return list(item)


def _path(seg, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(states (n, >=3) along one segment, extra points (k, 3) to keep in frame: its apex)."""
    if hasattr(seg, "sample"):
        _, ys = seg.sample(n)
        apex = getattr(seg, "apex", None)
        extra = np.asarray(apex.position, dtype=float).reshape(1, 3) if apex is not None else np.empty((0, 3))
        return np.asarray(ys, dtype=float), extra
    return np.asarray(seg[1], dtype=float), np.empty((0, 3))


def plot_trajectories(flights, labels=None, title: str | None = None, court=None, n: int = 400):
    """Side and top views of flights; returns the figure.

    ``flights``: a list whose items are each one flight - a :class:`~tennislab.trajectory.FlightResult`
    (all its segments, bounces marked), a :class:`~tennislab.core.flight.Trajectory`, a list of
    trajectories (segments of one flight), or ``(t, states)`` samples.  ``labels``: one per flight.
    """
    court = court or ITF_COURT
    fig, ax_side, ax_top = court_figure(court=court, title=title)
    drawn = []
    for i, item in enumerate(flights):
        segs = _segments(item)
        color = None
        for k, seg in enumerate(segs):
            path, extra = _path(seg, n)
            lab = labels[i] if labels and k == 0 else None
            (line,) = ax_side.plot(path[:, 0], path[:, 2], lw=1.8, label=lab, color=color, gid="flight")
            color = line.get_color()
            ax_top.plot(path[:, 0], path[:, 1], lw=1.8, color=color, gid="flight")
            drawn.extend([path[:, :3], extra])
            end = path[-1]
            kind, ms = ("bounce", 5) if k < len(segs) - 1 else ("end", 6)  # a segment that continues bounced
            ax_side.plot(end[0], end[2], "o", ms=ms, color=color, mec="k", gid=kind)
            ax_top.plot(end[0], end[1], "o", ms=ms, color=color, mec="k", gid=kind)
    frame_views(ax_side, ax_top, np.vstack(drawn) if drawn else np.empty((0, 3)), court)
    if labels:
        ax_side.legend(loc="upper right", fontsize=8)
    return fig
