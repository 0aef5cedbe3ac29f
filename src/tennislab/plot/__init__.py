"""Matplotlib figures of every result (nothing here computes physics), and the words people read in
titles, tables and command output (:mod:`tennislab.plot.text`).

Importing this package loads no Matplotlib and chooses no backend: a notebook keeps its interactive
backend; the entry points that only write files (``tennislab`` on the command line, the report it
builds) choose Agg themselves.  Each figure function imports pyplot when it draws.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from tennislab._lazy import attach_stub

if TYPE_CHECKING:
    from tennislab.plot.calibrate import plot_misses
    from tennislab.plot.court import (
        SURFACE_COLORS,
        court_figure,
        draw_court_side,
        draw_court_top,
        frame_views,
        surface_colors,
    )
    from tennislab.plot.launcher import plot_aim, plot_drill
    from tennislab.plot.linecall import call_title, plot_call, plot_rally
    from tennislab.plot.save import FIGURE_SUFFIXES, close_figure, figure_data_uri, figure_png, save_figure
    from tennislab.plot.serve import (
        WINDOW_COLORS,
        plot_impact_history,
        plot_mc,
        plot_optimum,
        plot_optimum_serves,
        plot_speed_spin,
        plot_window,
        plot_window_maps,
        window_codes,
        window_labels,
        window_span,
    )
    from tennislab.plot.text import (
        format_duration,
        in_out_by,
        length_mm,
        num,
        player_words,
        plus_minus,
        spin_axis_name,
        spin_fit_words,
        spin_words,
    )
    from tennislab.plot.trajectory import flight_title, plot_trajectories

__all__ = [
    "FIGURE_SUFFIXES",
    "SURFACE_COLORS",
    "WINDOW_COLORS",
    "num",
    "window_codes",
    "window_labels",
    "window_span",
    "call_title",
    "close_figure",
    "court_figure",
    "draw_court_side",
    "draw_court_top",
    "figure_data_uri",
    "figure_png",
    "flight_title",
    "format_duration",
    "frame_views",
    "in_out_by",
    "length_mm",
    "player_words",
    "plot_aim",
    "plot_call",
    "plot_drill",
    "plot_impact_history",
    "plot_mc",
    "plot_misses",
    "plot_optimum",
    "plot_optimum_serves",
    "plot_rally",
    "plot_speed_spin",
    "plot_trajectories",
    "plot_window",
    "plot_window_maps",
    "plus_minus",
    "save_figure",
    "spin_axis_name",
    "spin_fit_words",
    "spin_words",
    "surface_colors",
]
__getattr__, __dir__ = attach_stub(__name__, __file__)
