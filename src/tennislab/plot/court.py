"""Drawing the court: top view (x-y) and side view (x-z) with the net."""

from __future__ import annotations

import matplotlib.pyplot as plt
from matplotlib.patches import Rectangle

from tennislab.core.court import ITF_COURT, Court

COURT_GREEN = "#3a7d44"
LINE_WHITE = "#ffffff"


def draw_court_top(ax, court: Court = ITF_COURT, margin: float = 3.0, color: str = COURT_GREEN) -> None:
    """Draw the court seen from above on ``ax`` (x along, y across, metres)."""
    L, d = court.half_length, court.doubles_width / 2
    ax.add_patch(Rectangle((-L - margin, -d - margin), 2 * (L + margin), 2 * (d + margin), color="#2d5e35", zorder=0))
    ax.add_patch(Rectangle((-L, -d), 2 * L, 2 * d, color=color, zorder=0.5))
    for x0, x1, y0, y1 in court.lines().values():
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color=LINE_WHITE, lw=0, zorder=1))
    ax.plot([0, 0], [-court.y_post, court.y_post], color="#222222", lw=2, zorder=2)
    ax.set_xlim(-L - margin, L + margin)
    ax.set_ylim(-d - margin, d + margin)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")


def draw_court_side(ax, court: Court = ITF_COURT, margin: float = 3.0, zmax: float = 4.0) -> None:
    """Draw the side view (x-z): ground, baselines, service lines and the net at the centre strap."""
    L = court.half_length
    ax.axhline(0, color="#5a4632", lw=2)
    ax.plot([0, 0], [0, court.net_center_height], color="#222222", lw=3, label="net (centre)")
    ax.plot([0, 0], [court.net_center_height, court.net_post_height], color="#999999", lw=1, ls=":")
    for x in (-L, L, -court.service_line, court.service_line):
        ax.axvline(x, color="#bbbbbb", lw=0.8, ls="--", zorder=0)
    ax.set_xlim(-L - margin, L + margin)
    ax.set_ylim(0, zmax)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")


def court_figure(court: Court = ITF_COURT, title: str | None = None):
    """A figure with side view (top) and top view (bottom); returns (fig, ax_side, ax_top)."""
    fig, (ax_side, ax_top) = plt.subplots(2, 1, figsize=(10, 8.5), height_ratios=[1, 1.25])
    draw_court_side(ax_side, court)
    draw_court_top(ax_top, court)
    if title:
        fig.suptitle(title)
    return fig, ax_side, ax_top
