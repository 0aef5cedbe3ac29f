"""Why no serve of a window goes in, and whether turning toward the service box lets some in.

:func:`window_hint` is the workflow behind ``serve-window``'s ``hint`` (text and JSON): for a window
(:class:`~tennislab.serve.window.ServeWindow`) in which nothing goes in it counts the reasons of the
faults and, for a 3-D window (a target box), flies a coarser window of the same physics with the face
turned toward the box's centre.  The command renders it in words; nothing here knows about flags.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tennislab.core.flight import FlightParams
from tennislab.results import Result
from tennislab.serve.pipeline import box_name
from tennislab.serve.window import ServeWindow, angle_grid, window_of_setup

#: Coarsest grid step of the check at the box's azimuth [deg] (a window at least this coarse: the hint is a
#: pointer, not a second full window)
CHECK_STEP_DEG = 2.0
#: Azimuths are suggested on a grid of this step [deg]
AZIMUTH_STEP_DEG = 0.5


@dataclass(frozen=True)
class WindowHint(Result):
    """Why no serve of a window goes in (``failures``: reason code -> serves) and, for a 3-D window whose
    face does not point at the box's centre, the azimuth that does (``azimuth_deg`` [deg], rounded to
    :data:`AZIMUTH_STEP_DEG`) with the serves that go in there (``n_in``) on a grid of ``step_deg`` [deg];
    ``azimuth_deg`` None when there is nothing to turn (2-D, or already pointing at the box)."""

    failures: dict
    azimuth_deg: float | None = None
    step_deg: float | None = None
    n_in: int | None = None


def box_azimuth_deg(flight: FlightParams, target: str, server_x: float, server_y: float) -> float:
    """Azimuth [deg] from the server at (``server_x``, ``server_y``) [m] toward the centre of the
    ``target`` (``deuce``/``ad``) service box, rounded to :data:`AZIMUTH_STEP_DEG`."""
    x0, x1, y0, y1 = flight.court.area_bounds(box_name(target))
    psi = math.degrees(math.atan2(0.5 * (y0 + y1) - server_y, 0.5 * (x0 + x1) - server_x))
    return round(psi / AZIMUTH_STEP_DEG) * AZIMUTH_STEP_DEG


def window_hint(win: ServeWindow, step: float | None = None) -> WindowHint | None:
    """The hint for ``win`` (from :func:`~tennislab.serve.window.window`), None when some of its serves go
    in.  For a 3-D window whose face does not point at the box's centre, one more window of the same
    player, physics and options (``win.setup``) is flown at the box's azimuth on a grid of
    ``max(step, CHECK_STEP_DEG)`` [deg] (``step`` default: the window's alpha step)."""
    if win.success.any():
        return None
    fails = dict(win.failures())
    setup = win.setup
    if setup is None or setup.target is None:
        return WindowHint(fails)
    psi = box_azimuth_deg(setup.flight, setup.target, setup.criteria.server_x, setup.server_y)
    if abs(psi - win.azimuth_deg) < AZIMUTH_STEP_DEG:
        return WindowHint(fails)
    if step is None:
        step = float(np.min(np.diff(win.alpha_deg))) if win.alpha_deg.size > 1 else CHECK_STEP_DEG
    coarse = max(step, CHECK_STEP_DEG)
    grid = angle_grid(coarse)
    check = window_of_setup(setup, grid, grid, psi)
    return WindowHint(fails, psi, coarse, int(check.success.sum()))


__all__ = ["AZIMUTH_STEP_DEG", "CHECK_STEP_DEG", "WindowHint", "box_azimuth_deg", "window_hint"]
