"""Drawing the court: top view (x-y) and side view (x-z) with the net, and framing what is drawn on it.

:func:`frame_views` sets the limits of both views so that the court *and* everything drawn on it
(every bounce, the whole apex of a lob, a ball that bounces out past the baseline) are inside the axes.
"""

from __future__ import annotations

import numpy as np

from tennislab.core.court import ITF_COURT, Court

COURT_GREEN = "#3a7d44"
SURROUND_GREEN = "#2d5e35"
LINE_WHITE = "#ffffff"
#: smallest height shown in a side view [m] (a little above the net posts)
MIN_SIDE_HEIGHT = 3.0
#: (court, surround) colours of each registered surface as it looks: blue acrylic with a green
#: surround, red-brown clay, green grass, grey-blue carpet; an unknown surface (one's own file)
#: is drawn as hard
SURFACE_COLORS = {
    "hard": ("#3d6fa3", "#4f7f4a"),
    "clay": ("#c4673a", "#a9552f"),
    "grass": ("#4c8b3b", "#3d7330"),
    "carpet": ("#5f7186", "#4a5a6b"),
}


def surface_colors(surface: str | None) -> tuple[str, str]:
    """(court, surround) colours of a surface by name (:data:`SURFACE_COLORS`; hard when unknown or None)."""
    return SURFACE_COLORS.get(str(surface or "hard").lower(), SURFACE_COLORS["hard"])


def draw_court_top(
    ax, court: Court = ITF_COURT, margin: float = 3.0, color: str | None = None, surface: str | None = None
) -> None:
    """Draw the court seen from above on ``ax`` (x along, y across, metres) in the colours of
    ``surface`` (:func:`surface_colors`; ``color`` overrides the court's)."""
    from matplotlib.patches import Rectangle  # drawing only: keeps Matplotlib out of the CLI's start-up

    L, d = court.half_length, court.doubles_width / 2
    inner, around = surface_colors(surface)
    ax.set_facecolor(around)  # the surround, however far the limits are moved
    ax.add_patch(Rectangle((-L, -d), 2 * L, 2 * d, color=color or inner, zorder=0.5))
    for x0, x1, y0, y1 in court.lines().values():
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color=LINE_WHITE, lw=0, zorder=1))
    ax.plot([0, 0], [-court.y_post, court.y_post], color="#222222", lw=2, zorder=2)
    ax.set_xlim(-L - margin, L + margin)
    ax.set_ylim(-d - margin, d + margin)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")


def draw_court_side(
    ax, court: Court = ITF_COURT, margin: float = 3.0, zmax: float = 4.0, surface: str | None = None
) -> None:
    """Draw the side view (x-z): the ground in the colour of ``surface``, baselines, service lines
    (dashed) and the net at the centre strap."""
    L = court.half_length
    ax.axhline(0, color=surface_colors(surface)[0], lw=3)
    ax.plot([0, 0], [0, court.net_center_height], color="#222222", lw=3, label="net (centre)")
    ax.plot([0, 0], [court.net_center_height, court.net_post_height], color="#999999", lw=1, ls=":")
    for x in (-L, L, -court.service_line, court.service_line):
        ax.axvline(x, color="#bbbbbb", lw=0.8, ls="--", zorder=0)
    ax.set_xlim(-L - margin, L + margin)
    ax.set_ylim(0, zmax)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")


def data_extent(points) -> tuple[np.ndarray, np.ndarray] | None:
    """(lower, upper) corners (3,) of the finite rows of ``points`` (N, 3) [m]; None if there are none."""
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    p = p[np.all(np.isfinite(p), axis=1)]
    if p.size == 0:
        return None
    return p.min(axis=0), p.max(axis=0)


def frame_views(
    ax_side, ax_top, points, court: Court = ITF_COURT, margin: float = 3.0, pad: float = 1.0, headroom: float = 0.08
) -> None:
    """Set both views' limits to hold the court (with ``margin`` [m] around it) and every point of
    ``points`` (N, 3) [m] with ``pad`` [m] to spare; the side view starts at the ground and its
    height gets ``headroom`` (a fraction) above the highest point, at least :data:`MIN_SIDE_HEIGHT`.

    Either axis may be None (a figure with one view)."""
    L, d = court.half_length, court.doubles_width / 2
    lo = np.array([-L - margin, -d - margin, 0.0])
    hi = np.array([L + margin, d + margin, MIN_SIDE_HEIGHT])
    ext = data_extent(points)
    if ext is not None:
        lo = np.minimum(lo, ext[0] - pad)
        hi = np.maximum(hi, ext[1] + pad)
        hi[2] = max(hi[2], ext[1][2] * (1.0 + headroom) + 0.2)
    lo[2] = 0.0  # the ground: a ball centre is never below it
    if ax_side is not None:
        ax_side.set_xlim(lo[0], hi[0])
        ax_side.set_ylim(lo[2], hi[2])
    if ax_top is not None:
        ax_top.set_xlim(lo[0], hi[0])
        ax_top.set_ylim(lo[1], hi[1])


def court_figure(court: Court = ITF_COURT, title: str | None = None, surface: str | None = None):
    """A figure with side view (top) and top view (bottom) in the colours of ``surface``; returns
    (fig, ax_side, ax_top)."""
    # pyplot is imported here, not at the top: it adds about 0.5 s to every `tennislab` command's start-up
    # (measured with python -X importtime), and most commands never draw.
    import matplotlib.pyplot as plt

    fig, (ax_side, ax_top) = plt.subplots(2, 1, figsize=(10, 8.5), height_ratios=[1, 1.25])
    draw_court_side(ax_side, court, surface=surface)
    draw_court_top(ax_top, court, surface=surface)
    if title:
        fig.suptitle(title)
    return fig, ax_side, ax_top
