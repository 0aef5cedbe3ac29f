"""The flight use case: one ball launched from a state, to its landing or through N bounces.

:func:`fly` is the workflow behind ``tennislab fly``, the web app's Flight page and the report's
flight section; its :class:`FlightResult` gives each of them the same numbers (``to_dict()``).

A launch is given either as vectors (``position`` [m], ``velocity`` [m/s], ``spin`` [rad/s]) or in
the launch vocabulary of :mod:`tennislab.core.launch` (``speed_ms``, ``elevation_deg``,
``heading_deg``, ``spin_rpm`` about ``spin_axis``: a name such as ``topspin``, an angle [deg], or a
vector).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from tennislab.core.court import ITF_COURT
from tennislab.core.flight import FlightParams, Trajectory
from tennislab.core.flight import fly as _fly
from tennislab.core.launch import describe_spin, describe_velocity, launch_spin, launch_velocity, spin_axis_angle
from tennislab.core.rally import Rally, fly_bounces
from tennislab.core.surfaces import get_surface
from tennislab.errors import InputError, check_range, check_vector
from tennislab.results import Result
from tennislab.units import DEG, KMH, RPM

__all__ = ["FlightResult", "fly", "launch_vectors"]


def launch_vectors(
    velocity=None,
    spin=None,
    *,
    speed_ms=None,
    elevation_deg=None,
    heading_deg=0.0,
    spin_rpm=None,
    spin_axis=None,
) -> tuple[tuple, tuple]:
    """(velocity [m/s], spin [rad/s]) from vectors or from the launch vocabulary (module docstring)."""
    if velocity is not None and (speed_ms is not None or elevation_deg is not None):
        raise InputError("velocity: give either a velocity vector or speed with elevation, not both")
    if velocity is None:
        if speed_ms is None or elevation_deg is None:
            raise InputError("velocity: give a velocity vector, or a speed with an elevation [deg]")
        check_range("speed_ms", speed_ms, 0.0, None, "m/s")
        check_range("elevation_deg", elevation_deg, -90.0, 90.0, "deg")
        check_range("heading_deg", heading_deg, -180.0, 180.0, "deg")
        a, b = elevation_deg * DEG, heading_deg * DEG
        v = tuple(float(c) for c in launch_velocity(speed_ms, a, b))
    else:
        v = check_vector("velocity", velocity)
    if spin is not None and (spin_rpm is not None or spin_axis is not None):
        raise InputError("spin: give either a spin vector or spin_rpm with spin_axis, not both")
    if spin_rpm is None and spin_axis is None:
        w = check_vector("spin", spin) if spin is not None else (0.0, 0.0, 0.0)
        return v, w
    if spin_rpm is None or spin_axis is None:
        raise InputError("spin_rpm: give spin_rpm and spin_axis together")
    rate = check_range("spin_rpm", spin_rpm, 0.0, None, "rpm") * RPM
    if isinstance(spin_axis, (str, int, float)):
        _, a, b = describe_velocity(v)
        w_arr = launch_spin(rate, a, b, spin_axis_angle(spin_axis))
    else:
        ax = np.array(check_vector("spin_axis", spin_axis))
        n = float(np.linalg.norm(ax))
        if n == 0.0:
            raise InputError("spin_axis: must not be the zero vector")
        w_arr = ax / n * rate
    return v, tuple(float(c) for c in w_arr)


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


@dataclass(frozen=True)
class FlightResult(Result):
    """One flight: the first segment's landing, net crossing and apex, and the bounces if asked for.

    ``to_dict()`` is the JSON of ``tennislab fly --json`` (keys in SI by the rule of
    docs/conventions.md, ``_kmh``/``_rpm``/``_mm`` where suffixed).
    """

    trajectory: Trajectory = field(repr=False)
    rally: Rally | None = field(default=None, repr=False)
    surface: str | None = None

    @property
    def params(self) -> FlightParams:
        return self.trajectory.params

    @property
    def segments(self) -> list[Trajectory]:
        return list(self.rally.segments) if self.rally is not None else [self.trajectory]

    def points(self, n: int = 160) -> list[list[float]]:
        """Ball-centre positions [m] (rounded to 0.1 mm) along every segment, for plots."""
        out: list[list[float]] = []
        per = max(2, n // len(self.segments))
        for seg in self.segments:
            _, ys = seg.sample(per)
            out.extend(np.round(ys[:, 0:3], 4).tolist())
        return out

    def to_dict(self) -> dict:
        tr = self.trajectory
        land = tr.landing
        p = tr.params
        y0 = tr.y[0]
        speed, elev, head = describe_velocity(y0[3:6])
        spin = describe_spin(y0[6:9], y0[3:6])
        landing = None
        if land is not None:
            sp = float(np.linalg.norm(land.velocity))
            landing = {
                "x": land.x,
                "y": land.y,
                "t": land.t,
                "velocity": land.velocity,
                "speed": sp,
                "speed_kmh": sp / KMH,
                "spin": land.spin,
                "areas": ITF_COURT.areas_at(land.x, land.y),
            }
        out = {
            "launch": {
                "position": y0[0:3],
                "velocity": y0[3:6],
                "spin": y0[6:9],
                "speed_ms": speed,
                "speed_kmh": speed / KMH,
                "elevation_deg": elev / DEG,
                "heading_deg": head / DEG,
                "spin_rpm": spin["rate"] / RPM,
                "spin_axis_deg": _finite(spin["axis_angle"] / DEG),
            },
            "bounce": landing,
            "landing": landing,
            "net": {
                "z": tr.net.z,
                "y": tr.net.y,
                "t": tr.net.t,
                "height": tr.net.net_height,
                "clearance": tr.net.clearance,
                "result": tr.net.result,
            },
            "apex": {"z": tr.apex.z, "x": float(tr.apex.position[0]), "y": float(tr.apex.position[1]), "t": tr.apex.t},
            "physics": {
                "aero": p.aero.name,
                "mass": p.ball.mass,
                "radius": p.ball.radius,
                "air_density": p.atmosphere.density,
                "gravity": p.atmosphere.gravity,
                "wind": p.atmosphere.wind,
            },
        }
        if self.rally is not None:
            out["surface"] = self.surface
            out["bounces"] = [_bounce_dict(b) for b in self.rally.bounces]
        return out


def _bounce_dict(b) -> dict:
    d = b.as_dict()
    d["mark"] = {
        "length": b.mark.length,
        "width": b.mark.width,
        "x": float(b.mark.center[0]),
        "y": float(b.mark.center[1]),
        "skid": b.mark.skid,
        "contact_time": b.mark.contact_time,
        "compression": b.mark.compression,
    }
    return d


def fly(
    position,
    velocity=None,
    spin=None,
    *,
    speed_ms=None,
    elevation_deg=None,
    heading_deg=0.0,
    spin_rpm=None,
    spin_axis=None,
    params: FlightParams | None = None,
    surface="hard",
    bounces: int = 0,
) -> FlightResult:
    """Fly one ball from ``position`` [m] to its landing (``bounces=0``) or through ``bounces`` bounces
    on ``surface`` (a registered name or :class:`~tennislab.core.surfaces.Surface`).

    Raises :class:`~tennislab.errors.InputError` when the ball does not land within ``params.t_max``.
    """
    params = params or FlightParams()
    v, w = launch_vectors(
        velocity,
        spin,
        speed_ms=speed_ms,
        elevation_deg=elevation_deg,
        heading_deg=heading_deg,
        spin_rpm=spin_rpm,
        spin_axis=spin_axis,
    )
    if not isinstance(bounces, int) or isinstance(bounces, bool) or not 0 <= bounces <= 100:
        raise InputError(f"bounces: {bounces} is outside the allowed range [0, 100]")
    surf = get_surface(surface)
    rally = None
    if bounces > 0:
        rally = fly_bounces(position, v, w, params, surface=surf, bounces=bounces)
        tr = rally.first
    else:
        tr = _fly(position, v, w, params)
    if tr.landing is None:
        raise InputError(f"flight: the ball does not land within t_max = {params.t_max:g} s")
    return FlightResult(tr, rally, surf.name if rally is not None else None)
