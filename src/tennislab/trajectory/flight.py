"""The flight workflow (:func:`fly`, :class:`FlightResult`) and its launch vocabulary (:func:`launch_vectors`).

See :mod:`tennislab.trajectory` (the public API).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from tennislab.core.court import ITF_COURT
from tennislab.core.flight import (
    DEFAULT_NET,
    MAX_DISTANCE_M,
    MAX_SPEED_MS,
    MAX_SPIN_RPM,
    NET_MODES,
    FlightParams,
    Trajectory,
    with_net,
)
from tennislab.core.flight import fly_dense as _fly
from tennislab.core.launch import describe_spin, describe_velocity, launch_spin, launch_velocity, spin_axis_angle
from tennislab.core.rally import Rally, fly_bounces
from tennislab.core.surfaces import get_surface
from tennislab.errors import InputError, check_range, check_vector
from tennislab.results import DEFAULT_STEP_S, TRAJECTORY_COLUMNS, Table, trajectory_rows
from tennislab.units import DEG, KMH, RPM, _nice, speed_in_ms

__all__ = ["MAX_DISTANCE_M", "MAX_SPEED_MS", "MAX_SPIN_RPM", "NET_MODES", "FlightResult", "fly", "launch_vectors"]


def launch_vectors(
    velocity=None,
    spin=None,
    *,
    speed_ms=None,
    elevation_deg=None,
    heading_deg=None,
    spin_rpm=None,
    spin_axis=None,
    speed_kmh=None,
    speed_mph=None,
) -> tuple[tuple, tuple]:
    """(velocity [m/s], spin [rad/s]) from vectors or from the launch vocabulary (module docstring).

    The speed is refused above :data:`MAX_SPEED_MS` and the spin above :data:`MAX_SPIN_RPM`, each in
    the unit it was given in.
    """
    speeds = {"speed_ms": speed_ms, "speed_kmh": speed_kmh, "speed_mph": speed_mph}
    given = [k for k, val in speeds.items() if val is not None]
    if len(given) > 1:
        raise InputError(f"{given[0]}: give one speed ({' or '.join(given)}), not {len(given)}")
    if velocity is not None and (given or elevation_deg is not None or heading_deg is not None):
        what = given[0] if given else ("elevation_deg" if elevation_deg is not None else "heading_deg")
        raise InputError(f"{what}: give either a velocity vector or a speed with an elevation, not both")
    if velocity is None:
        if not given:
            what = "elevation_deg" if elevation_deg is not None else "velocity"
            raise InputError(f"{what}: give a velocity vector, or a speed with an elevation [deg]")
        key = given[0]
        if elevation_deg is None:
            raise InputError(f"elevation_deg: give the launch elevation [deg] with {key}")
        _, speed = speed_in_ms(0.0, MAX_SPEED_MS, **speeds)  # type: ignore[misc]
        check_range("elevation_deg", elevation_deg, -90.0, 90.0, "deg")
        heading = check_range("heading_deg", 0.0 if heading_deg is None else heading_deg, -180.0, 180.0, "deg")
        a, b = elevation_deg * DEG, heading * DEG
        v = tuple(float(c) for c in launch_velocity(speed, a, b))
    else:
        v = check_vector("velocity", velocity)
        sp = math.hypot(*v)
        if sp > MAX_SPEED_MS:
            raise InputError(f"velocity: |v| = {sp:.4g} m/s is outside the allowed range [0, {MAX_SPEED_MS:g}] m/s")
    if spin is not None and (spin_rpm is not None or spin_axis is not None):
        raise InputError("spin: give either a spin vector or spin_rpm with spin_axis, not both")
    if spin_rpm is None and spin_axis is None:
        w = check_vector("spin", spin) if spin is not None else (0.0, 0.0, 0.0)
        rate_w = math.hypot(*w)
        if rate_w > MAX_SPIN_RPM * RPM:
            raise InputError(
                f"spin: |omega| = {rate_w:.4g} rad/s ({rate_w / RPM:.0f} rpm) is outside the allowed range "
                f"[0, {MAX_SPIN_RPM * RPM:.1f}] rad/s ({MAX_SPIN_RPM:g} rpm)"
            )
        return v, w
    if spin_rpm is None or spin_axis is None:
        missing = "spin_axis" if spin_rpm is not None else "spin_rpm"
        raise InputError(f"{missing}: give spin_rpm and spin_axis together")
    rate = check_range("spin_rpm", spin_rpm, 0, _nice(MAX_SPIN_RPM), "rpm") * RPM
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
class FlightResult(Table):
    """One flight: the first segment's landing, net crossing and apex, and the bounces if asked for.

    ``to_dict()`` is the JSON of ``tennislab fly --json`` (keys in SI by the rule of
    docs/conventions.md, ``_kmh``/``_rpm``/``_mm`` where suffixed); ``rows(step_s)`` /
    ``to_frame(step_s=...)`` the flight sampled every ``step_s`` [s] (default 0.01 s) through every
    segment (:func:`tennislab.results.trajectory_rows`).
    """

    COLUMNS = TRAJECTORY_COLUMNS

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

    def rows(self, step_s: float = DEFAULT_STEP_S) -> list[dict]:
        """The flight every ``step_s`` [s]: time [s], position [m], velocity and speed [m/s], spin [rpm]."""
        return trajectory_rows(self.segments, step_s)

    @property
    def caveats(self) -> list[str]:
        """What the numbers do not model, in plain words (shown next to them by the CLI, app and report)."""
        out = []
        net = self.trajectory.net
        contact = self.trajectory.net_contact
        if contact is not None:
            out.append(
                f"The ball hits the net ({contact.part}, {contact.z:.2f} m high): the flight ends there; what the "
                "net then does to the ball is not modelled."
            )
        elif net.result == "net":
            out.append(
                f"The ball hits the net (clearance {net.clearance:.3f} m). It was flown with the net switched off "
                "(net='through'): the landing shown is where it would land if the net were not there."
            )
        if self.rally is not None and len(self.rally.segments) <= len(self.rally.bounces):
            n = len(self.rally.bounces)
            out.append(f"The ball leaves the ground too slowly to fly after bounce {n}: it rolls from there.")
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
        out: dict[str, object] = {
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
            "physics": p.to_dict(),
        }
        contact = tr.net_contact
        out["net_contact"] = (
            None
            if contact is None
            else {
                "t": contact.t,
                "x": float(contact.position[0]),
                "y": contact.y,
                "z": contact.z,
                "velocity": contact.velocity,
                "spin": contact.spin,
                "part": contact.part,
            }
        )
        if self.rally is not None:
            out["surface"] = self.surface
            out["bounces"] = [b.to_dict() for b in self.rally.bounces]
        out["caveats"] = self.caveats
        return out


def fly(
    position,
    velocity=None,
    spin=None,
    *,
    speed_ms=None,
    elevation_deg=None,
    heading_deg=None,
    spin_rpm=None,
    spin_axis=None,
    speed_kmh=None,
    speed_mph=None,
    params: FlightParams | None = None,
    surface="hard",
    bounces: int = 0,
    net: str = DEFAULT_NET,
) -> FlightResult:
    """Fly one ball from ``position`` [m] to its landing (``bounces=0``) or through ``bounces`` bounces
    on ``surface`` (a registered name or :class:`~tennislab.core.surfaces.Surface`).

    The launch is ``velocity`` [m/s] or one of ``speed_ms`` / ``speed_kmh`` / ``speed_mph`` with
    ``elevation_deg`` (and ``heading_deg``, default 0); the spin is ``spin`` [rad/s] or ``spin_rpm``
    about ``spin_axis`` (module docstring).  Raises :class:`~tennislab.errors.InputError` for a launch
    outside the guard rails, when the ball does not land within ``params.t_max``, or when the
    integration gives non-finite numbers.

    ``net``: ``obstacle`` (default) ends the flight where the ball meets the net (the result's
    ``net_contact``; no landing); ``through`` lets it pass, as the seeds' models do.
    """
    params = with_net(params, net)
    pos = check_vector("position", position)
    for i, c in enumerate(pos):
        if abs(c) > MAX_DISTANCE_M:
            raise InputError(
                f"position[{i}]: {c:g} m is outside the allowed range [-{MAX_DISTANCE_M:g}, {MAX_DISTANCE_M:g}] m"
            )
    v, w = launch_vectors(
        velocity,
        spin,
        speed_ms=speed_ms,
        elevation_deg=elevation_deg,
        heading_deg=heading_deg,
        spin_rpm=spin_rpm,
        spin_axis=spin_axis,
        speed_kmh=speed_kmh,
        speed_mph=speed_mph,
    )
    if not isinstance(bounces, (int, np.integer)) or isinstance(bounces, bool) or not 0 <= bounces <= 100:
        raise InputError(f"bounces: {bounces} is outside the allowed range [0, 100]")
    surf = get_surface(surface)
    rally = None
    if bounces > 0:
        rally = fly_bounces(pos, v, w, params, surface=surf, bounces=int(bounces))
        tr = rally.first
    else:
        tr = _fly(pos, v, w, params)
    if tr.landing is None and tr.net_contact is None:
        raise InputError(f"flight: the ball does not land within t_max = {params.t_max:g} s")
    for seg in [tr] if rally is None else rally.segments:
        if not (np.all(np.isfinite(seg.y)) and (seg.landing is None or np.all(np.isfinite(seg.landing.velocity)))):
            raise InputError("flight: the integration gave non-finite numbers (check the physics options)")
    return FlightResult(tr, rally, surf.name if rally is not None else None)
