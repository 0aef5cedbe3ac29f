"""What the web app draws: the court's geometry, and the flight page's call of the flight workflow.

Nothing here knows about HTTP, and nothing here is physics: the flight page calls
:func:`tennislab.trajectory.fly` (the workflow behind ``tennislab fly``) with its
physics built by :meth:`FlightParams.from_options`; :func:`flight_of` answers the
flight of a serve or an aimed shot as that workflow's result (``to_dict()``) plus the points
the page draws.
"""

from __future__ import annotations

import numpy as np

from tennislab.core.court import ITF_COURT
from tennislab.core.flight import FlightParams
from tennislab.plot import SURFACE_COLORS
from tennislab.trajectory import FlightResult, fly
from tennislab.units import KMH

#: points sampled along a trajectory for the page's plots
PLOT_POINTS = 160


def physics_params(v: dict) -> FlightParams:
    """:class:`FlightParams` from the physics fields of a form (aero, air_density, wind_x, wind_y)."""
    return FlightParams.from_options(aero=v["aero"], air_density=v["air_density"], wind=(v["wind_x"], v["wind_y"], 0.0))


def trajectory_points(tr, n: int = PLOT_POINTS) -> list[list[float]]:
    """Sampled ball-centre positions [m] (rounded to 0.1 mm) of a trajectory for plotting."""
    _, ys = tr.sample(n)
    return np.round(ys[:, 0:3], 4).tolist()


def flight_of(tr) -> dict:
    """A flight the serve or launcher page draws, as the flight workflow answers it: the
    :class:`~tennislab.trajectory.FlightResult` of the trajectory (``to_dict()``: the JSON of
    ``tennislab fly --json``: ``landing``, ``net``, ``apex``, ``physics`` ...) plus its plot ``points``."""
    res = FlightResult(tr)
    out = res.to_dict()
    out["points"] = res.points(PLOT_POINTS)
    return out


# ------------------------------------------------------------------ court
def court_geometry() -> dict:
    """Lines, areas and net of the ITF court for drawing in the page, and each surface's colours (those
    of the figures: :data:`tennislab.plot.court.SURFACE_COLORS`)."""
    c = ITF_COURT
    return {
        "half_length": c.half_length,
        "singles_width": c.singles_width,
        "doubles_width": c.doubles_width,
        "service_line": c.service_line,
        "y_post": c.y_post,
        "net_center_height": c.net_center_height,
        "net_post_height": c.net_post_height,
        "lines": {k: list(v) for k, v in c.lines().items()},
        "areas": {k: list(c.area_bounds(k)) for k in c.area_names()},
        "surfaces": {k: {"court": v[0], "surround": v[1]} for k, v in SURFACE_COLORS.items()},
    }


# ------------------------------------------------------------------ flight
def flight(v: dict) -> dict:
    """One flight (form ``flight``): :func:`tennislab.trajectory.fly` from a position, speed,
    elevation, heading, spin and spin axis, through ``bounces`` bounces on ``surface``.

    Returns :meth:`FlightResult.to_dict` (the JSON of ``tennislab fly --json``) plus the plot
    ``points`` of every segment.
    """
    res = fly(
        (v["x"], v["y"], v["z"]),
        speed_ms=v["speed_kmh"] * KMH,
        elevation_deg=v["elevation_deg"],
        heading_deg=v["heading_deg"],
        spin_rpm=v["spin_rpm"],
        spin_axis=v["spin_axis_deg"],
        params=physics_params(v),
        bounces=v["bounces"],
        surface=v["surface"],
    )
    out = res.to_dict()
    out["points"] = res.points(PLOT_POINTS * max(1, len(res.segments)))
    return out
