"""Physics services of the web app and the report: validated values in, JSON-able dicts out.

Nothing here knows about HTTP.  Each service takes the parsed values of its
form (:mod:`tennislab.app.fields`, user units) and calls the physics API only.
The modules of the serve analysis, line calling and launcher are optional:
:func:`availability` reports which are importable, and a service whose module
is missing raises :class:`Unavailable` (HTTP 503 in the server, a "not
available" section in the report) instead of breaking the rest.
"""

from __future__ import annotations

import importlib
import math
import os

import numpy as np

from tennislab.core.court import ITF_COURT
from tennislab.core.flight import FlightParams, fly
from tennislab.errors import InputError, TennisLabError
from tennislab.units import DEG, KMH, RPM

#: module -> attributes the app needs from it
REQUIREMENTS = {
    "serve": [
        ("tennislab.serve.single", "simulate_serve"),
        ("tennislab.serve.window", "serve_window"),
        ("tennislab.serve.players", "get_player"),
    ],
    "linecall": [
        ("tennislab.io.track", "parse_track"),
        ("tennislab.linecall.fit", "fit_track"),
        ("tennislab.linecall.decide", "call_mark"),
        ("tennislab.core.mark", "ball_mark"),
    ],
    "launcher": [("tennislab.launcher.machine", "MachineSpec"), ("tennislab.launcher.machine", "launch_states")],
}


class Unavailable(TennisLabError):
    """A feature whose module is not installed (yet)."""


def _check(reqs) -> str | None:
    for mod, attr in reqs:
        try:
            m = importlib.import_module(mod)
        except Exception as exc:
            return f"{mod} cannot be imported ({type(exc).__name__}: {exc})"
        if attr is not None and not hasattr(m, attr):
            return f"{mod}.{attr} is missing"
    return None


def _disabled(feature: str) -> str | None:
    """Features switched off by ``TENNISLAB_APP_DISABLE=serve,linecall,...`` (to check the degraded pages)."""
    off = {f.strip() for f in os.environ.get("TENNISLAB_APP_DISABLE", "").split(",")}
    return "disabled by TENNISLAB_APP_DISABLE" if feature in off else None


def availability() -> dict[str, dict]:
    """``{feature: {"available": bool, "reason": str}}`` for serve, linecall and launcher."""
    out = {}
    for name, reqs in REQUIREMENTS.items():
        why = _disabled(name) or _check(reqs)
        out[name] = {"available": why is None, "reason": why or ""}
    return out


def require(feature: str) -> None:
    """Raise :class:`Unavailable` if a feature's module is missing."""
    why = _disabled(feature) or _check(REQUIREMENTS[feature])
    if why:
        raise Unavailable(f"{feature}: not available in this installation ({why})")


# ------------------------------------------------------------------ helpers
def physics_params(v: dict, default_aero: str = "stepanek1988", **overrides) -> FlightParams:
    """:class:`FlightParams` from the physics fields of a form (aero, air_density, wind_x, wind_y)."""
    kw = dict(
        aero=v.get("aero", default_aero),
        air_density=v.get("air_density"),
        wind=(v.get("wind_x", 0.0), v.get("wind_y", 0.0), 0.0),
    )
    kw.update({k: val for k, val in overrides.items() if val is not None})
    return FlightParams.from_options(**kw)


def direction(elevation_deg: float, heading_deg: float) -> np.ndarray:
    """Unit vector of a launch at an elevation above the horizontal and a heading from +x toward +y."""
    e, h = elevation_deg * DEG, heading_deg * DEG
    return np.array([math.cos(e) * math.cos(h), math.cos(e) * math.sin(h), math.sin(e)])


def spin_vector(d: np.ndarray, spin_rpm: float, spin_axis_deg: float) -> np.ndarray:
    """Spin vector [rad/s] of a ball moving along ``d``.

    Axis angle 0 = topspin (axis horizontal, perpendicular to the motion: +y for
    a ball moving +x), 180 = backspin, +90 = sidespin curving the ball to its
    left (axis up), -90 to its right; the axis turns about the direction of motion.
    """
    dh = np.array([d[0], d[1], 0.0])
    if np.linalg.norm(dh) < 1e-9:
        dh = np.array([1.0, 0.0, 0.0])
    t = np.cross([0.0, 0.0, 1.0], dh)
    t /= np.linalg.norm(t)
    u = np.cross(d, t)
    u /= np.linalg.norm(u)
    a = spin_axis_deg * DEG
    return (math.cos(a) * t + math.sin(a) * u) * spin_rpm * RPM


def trajectory_points(tr, n: int = 160) -> list[list[float]]:
    """Sampled ball-centre positions [m] (rounded to 0.1 mm) of a trajectory for plotting."""
    _, ys = tr.sample(n)
    return np.round(ys[:, 0:3], 4).tolist()


def flight_result(tr) -> dict:
    """Landing, net crossing and apex of a :class:`Trajectory` plus plot points."""
    land = tr.landing
    net = tr.net
    return {
        "landing": None
        if land is None
        else {
            "x": land.x,
            "y": land.y,
            "t": land.t,
            "speed_kmh": float(np.linalg.norm(land.velocity)) / KMH,
            "areas": ITF_COURT.areas_at(land.x, land.y),
        },
        "net": {
            "result": net.result,
            "clearance": None if not math.isfinite(net.clearance) else net.clearance,
            "z": None if not math.isfinite(net.z) else net.z,
            "y": None if not math.isfinite(net.y) else net.y,
        },
        "apex": {"z": tr.apex.z, "x": float(tr.apex.position[0]), "t": tr.apex.t},
        "points": trajectory_points(tr),
    }


# ------------------------------------------------------------------ court
def court_geometry() -> dict:
    """Lines, areas and net of the ITF court for drawing in the page."""
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
    }


# ------------------------------------------------------------------ flight
def flight(v: dict) -> dict:
    """One flight from a launch (position, speed, elevation, heading, spin, axis); see form ``flight``."""
    params = physics_params(v)
    d = direction(v["elevation_deg"], v["heading_deg"])
    vel = d * v["speed_kmh"] * KMH
    w = spin_vector(d, v["spin_rpm"], v["spin_axis_deg"])
    pos = (v["x"], v["y"], v["z"])
    if pos[2] < params.ball.radius:
        raise InputError(f"z: {pos[2]:g} m is below the ball radius {params.ball.radius:g} m")
    tr = fly(pos, tuple(vel), tuple(w), params)
    if tr.landing is None:
        raise InputError("flight: the ball does not land within 20 s; lower the speed or elevation")
    out = flight_result(tr)
    out["launch"] = {"position": list(pos), "velocity": vel.tolist(), "spin": w.tolist()}
    return out
