"""One serve: impact, launch and flight, judged by the seed's 2-D criteria or a real service box.

2-D (default, the seed's): ball centre at (baseline, y = 0, impact height), face
normal in the x-z plane, success = net_top / service_line of :class:`SeedCriteria`.
3-D (``target="deuce"`` or ``"ad"``): the server at (baseline, ``server_y``), the
face turned by ``azimuth`` and brushed along ``brush`` (see
:mod:`tennislab.core.impact_3d`); success = over the real net (ITF profile) and
first bounce inside the far deuce/ad service box (lines are in).
"""

from __future__ import annotations

import math

import numpy as np

from tennislab.core.flight import FlightParams, fly, fly_batch
from tennislab.core.impact import ImpactParams, impact
from tennislab.core.impact_3d import face_basis
from tennislab.errors import InputError, check_range
from tennislab.serve.players import get_player
from tennislab.serve.setup import CATEGORIES, SeedCriteria, seed_flight_params, seed_impact_params
from tennislab.units import RPM

TARGETS = {"deuce": "deuce-box", "ad": "ad-box"}


def launch_3d(v_n, v_t, omega, beta, azimuth=0.0, brush=0.0):
    """Court-frame (velocity (..., 3), spin (..., 3)) of a ball leaving a face (beta, azimuth [rad])
    with racket-frame (v_n, v_t, omega) in the plane of the brush direction."""
    n, tu, tl = face_basis(beta, azimuth)
    ph = np.asarray(brush, float)[..., None]
    t = np.cos(ph) * tu + np.sin(ph) * tl
    vel = np.asarray(v_n, float)[..., None] * n + np.asarray(v_t, float)[..., None] * t
    spin = np.asarray(omega, float)[..., None] * np.cross(t, n)
    return vel, spin


def judge(table, criteria: SeedCriteria, target: str | None, court=None) -> dict[str, np.ndarray]:
    """Per-row ``landing_x`` (from the impact point), ``net_height`` and ``success``."""
    X = table["land_x"] - criteria.server_x
    Y = table["net_z"]
    landed = table.ok & (table["net_status"] > 0) & (table["land_x"] > 0)
    if target is None:
        success = landed & (Y > criteria.net_top) & (X <= criteria.service_line)
    else:
        try:
            box = TARGETS[target]
        except KeyError:
            raise InputError(f"target: unknown {target!r}; choose from {', '.join(TARGETS)}") from None
        from tennislab.core.court import ITF_COURT

        c = court or ITF_COURT
        success = landed & (table["net_status"] == 1) & c.contains(box, table["land_x"], table["land_y"])
    return {"landing_x": X, "net_height": Y, "success": np.asarray(success, bool)}


def simulate_serve(
    player,
    alpha_deg: float,
    beta_deg: float,
    *,
    flight: FlightParams | None = None,
    impact_params: ImpactParams | None = None,
    criteria: SeedCriteria | None = None,
    target: str | None = None,
    azimuth_deg: float = 0.0,
    brush_deg: float = 0.0,
    server_y: float = 0.0,
    toss_vz: float = 0.0,
    trajectory: bool = False,
    dt: float = 0.0,
    method: str = "rk4",
) -> dict:
    """Simulate one serve; returns the ``tennislab serve`` JSON object (SI, angles in degrees).

    ``toss_vz``: vertical ball velocity at impact [m/s] (negative: falling), as a Galilean
    shift of the impact.  ``trajectory=True`` adds the SciPy :class:`Trajectory` under
    ``"_trajectory"`` (for plots).
    """
    player = get_player(player)
    flight = flight or seed_flight_params()
    impact_params = impact_params or seed_impact_params(ball=flight.ball)
    crit = criteria or SeedCriteria()
    a = math.radians(check_range("impact angle", alpha_deg, -89.999, 89.999, "deg"))
    b = math.radians(check_range("face angle", beta_deg, -90.0, 90.0, "deg"))
    psi = math.radians(check_range("azimuth", azimuth_deg, -90.0, 90.0, "deg"))
    ph = math.radians(check_range("brush", brush_deg, -180.0, 180.0, "deg"))
    check_range("server_y", server_y, -10.0, 10.0, "m")
    if target is None and (psi != 0 or ph != 0 or server_y != 0):
        raise InputError("azimuth/brush/server_y: 3-D options need --target deuce or ad")
    # toss velocity (0, 0, toss_vz) in the impact plane of (n, t)
    n, tu, tl = face_basis(b, psi)
    t = math.cos(ph) * tu + math.sin(ph) * tl
    toss = np.array([0.0, 0.0, float(toss_vz)])
    res = impact(
        player.racket_speed, a, impact_params, toss_n=float(toss @ n), toss_t=float(toss @ t), dt=dt, method=method
    )
    off_plane = toss - (toss @ n) * n - (toss @ t) * t
    vel, spin = launch_3d(res.v_n, res.v_t, res.omega, b, psi, ph)
    vel = vel + off_plane
    state = np.concatenate([[crit.server_x, server_y, player.impact_height], vel, spin])
    table = fly_batch(state[None], flight)
    j = judge(table, crit, target)
    spin_rpm = res.omega / RPM
    cat = CATEGORIES[int(crit.category(spin_rpm))]
    gamma = math.degrees(math.atan2(vel[2], math.hypot(vel[0], vel[1])))
    out = {
        "player": player.name,
        "alpha": alpha_deg,
        "beta": beta_deg,
        "speed": float(np.linalg.norm(vel)),
        "spin_rpm": float(spin_rpm),
        "launch_angle": gamma,
        "net_height": float(j["net_height"][0]),
        "landing_x": float(j["landing_x"][0]),
        "success": bool(j["success"][0]),
        "category": cat,
        "landing": {"x": float(table["land_x"][0]), "y": float(table["land_y"][0]), "t": float(table["land_t"][0])},
        "impact": {
            "contact_time_ms": res.contact_time * 1e3,
            "regime": res.regime,
            "v_n": res.v_n,
            "v_t": res.v_t,
            "omega": res.omega,
        },
        "velocity": vel,
        "spin": spin,
        "criteria": "seed-2d" if target is None else f"{target}-box",
    }
    if trajectory:
        out["_trajectory"] = fly(state[:3], vel, spin, flight)
    return out
