"""Why no serve of a window goes in, and whether turning toward the service box lets some in.

:func:`window_hint` is the workflow behind ``serve-window``'s ``hint`` (text and JSON): for a window
(:class:`~tennislab.serve.window.ServeWindow`) in which nothing goes in it counts the reasons of the
faults and, for a 3-D window (a target box), flies a coarser window of the same physics with the face
turned toward the box's centre.  The command renders it in words; nothing here knows about flags.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from tennislab.core.flight import FlightParams
from tennislab.core.impact import ImpactParams
from tennislab.results import Result

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
    from tennislab.serve.pipeline import box_name

    x0, x1, y0, y1 = flight.court.area_bounds(box_name(target))
    psi = math.degrees(math.atan2(0.5 * (y0 + y1) - server_y, 0.5 * (x0 + x1) - server_x))
    return round(psi / AZIMUTH_STEP_DEG) * AZIMUTH_STEP_DEG


def window_hint(
    win,
    *,
    target: str | None = None,
    server_y: float = 0.0,
    azimuth_deg: float = 0.0,
    brush_deg: float = 0.0,
    step: float = 1.0,
    flight: FlightParams | None = None,
    impact_params: ImpactParams | None = None,
    method: str = "rk4",
    dt: float = 0.0,
) -> WindowHint | None:
    """The hint for ``win`` (a :class:`~tennislab.serve.window.ServeWindow` run with these options and
    physics), None when some of its serves go in.  With a ``target`` box and a face that does not point at
    its centre, one more window of the same player and physics is flown at the box's azimuth on a grid of
    ``max(step, CHECK_STEP_DEG)`` [deg]."""
    if win.success.any():
        return None
    fails = dict(win.failures())
    if target is None:
        return WindowHint(fails)
    from tennislab.serve.pipeline import default_flight
    from tennislab.serve.window import window

    flight = flight or default_flight()
    psi = box_azimuth_deg(flight, target, win.criteria.server_x, server_y)
    if abs(psi - azimuth_deg) < AZIMUTH_STEP_DEG:
        return WindowHint(fails)
    coarse = max(step, CHECK_STEP_DEG)
    check = window(
        win.player,
        step=coarse,
        target=target,
        server_y=server_y,
        azimuth_deg=psi,
        brush_deg=brush_deg,
        flight=flight,
        impact_params=impact_params,
        method=method,
        dt=dt,
    )
    return WindowHint(fails, psi, coarse, int(check.success.sum()))


__all__ = ["AZIMUTH_STEP_DEG", "CHECK_STEP_DEG", "WindowHint", "box_azimuth_deg", "window_hint"]
