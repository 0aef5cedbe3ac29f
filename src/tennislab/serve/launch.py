"""The serve pipeline shared by the workflows: racket-frame impact -> launch -> flight -> judgement.

:func:`outcomes` simulates arrays of serves (impact angle, face angle, azimuth) for one
:class:`Setup` (player, physics, criteria, 3-D options): the single serve
(:mod:`tennislab.serve.single`), the advice scans (:mod:`tennislab.serve.verdict`) use it;
the window and the Monte Carlo use :func:`launch_3d` and :func:`judge` on their own batches.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tennislab.core.court import ITF_COURT
from tennislab.core.flight import FlightParams, fly_batch
from tennislab.core.impact import ImpactParams, impact_batch
from tennislab.core.impact_3d import face_basis
from tennislab.errors import InputError, check_range
from tennislab.serve.players import PlayerProfile
from tennislab.serve.setup import SeedCriteria

TARGETS = {"deuce": "deuce-box", "ad": "ad-box"}

#: Why a serve fails (``verdict.reason``); ``None`` when it goes in.
REASONS = {
    "net": "the ball does not clear the net (the paper's 2-D test: its centre passes below 0.943 m)",
    "short": "the ball lands on the server's side, before the net",
    "long": "the ball lands beyond the service line",
    "wide": "the ball lands beside the service box (3-D targets only)",
    "no-landing": "the ball does not land within the flight's time limit",
}


def launch_3d(v_n, v_t, omega, beta, azimuth=0.0, brush=0.0):
    """Court-frame (velocity (..., 3), spin (..., 3)) of a ball leaving a face (beta, azimuth [rad])
    with racket-frame (v_n, v_t, omega) in the plane of the brush direction."""
    n, tu, tl = face_basis(beta, azimuth)
    ph = np.asarray(brush, float)[..., None]
    t = np.cos(ph) * tu + np.sin(ph) * tl
    vel = np.asarray(v_n, float)[..., None] * n + np.asarray(v_t, float)[..., None] * t
    spin = np.asarray(omega, float)[..., None] * np.cross(t, n)
    return vel, spin


def box_name(target: str) -> str:
    """The court area of a 3-D target (``deuce`` -> ``deuce-box``)."""
    try:
        return TARGETS[target]
    except KeyError:
        raise InputError(f"target: unknown {target!r}; choose from {', '.join(TARGETS)}") from None


#: ``reason`` codes of :func:`judge`: index -> name (0 = the serve goes in; the rest as :data:`REASONS`)
REASON_CODES = ("in", "net", "short", "long", "wide", "no-landing")


def judge(table, criteria: SeedCriteria, target: str | None, court=None) -> dict[str, np.ndarray]:
    """Per-row ``landing_x`` (from the impact point), ``net_height``, ``success`` and ``reason`` (an
    index of :data:`REASON_CODES`, the first failed test in the order of :func:`tennislab.serve.verdict.describe`:
    no landing, short, net, long, wide)."""
    X = table["land_x"] - criteria.server_x
    Y = table["net_z"]
    landed = table.ok & (table["net_status"] > 0) & (table["land_x"] > 0)
    reason = np.zeros(len(X), np.int8)
    if target is None:
        net = Y <= criteria.net_top
        long = X > criteria.service_line
        wide = np.zeros(len(X), bool)
    else:
        c = court or ITF_COURT
        x0, x1, y0, y1 = c.area_bounds(box_name(target))
        net = table["net_status"] == 2
        long = table["land_x"] > x1
        wide = (table["land_y"] < y0) | (table["land_y"] > y1)
    # the first failed test wins: set in the reverse order
    for name, fails in (("wide", wide), ("long", long), ("net", net), ("short", ~landed), ("no-landing", ~table.ok)):
        reason[np.asarray(fails, bool)] = REASON_CODES.index(name)
    if target is None:
        success = landed & (Y > criteria.net_top) & (X <= criteria.service_line)
    else:
        success = landed & (table["net_status"] == 1) & c.contains(box_name(target), table["land_x"], table["land_y"])
    success = np.asarray(success, bool)
    reason[success] = 0
    return {"landing_x": X, "net_height": Y, "success": success, "reason": reason}


def check_serve_options(target, azimuth_deg, brush_deg, server_y) -> tuple[float, float]:
    """Validate the 3-D options; (azimuth, brush) [rad]."""
    psi = math.radians(check_range("azimuth_deg", azimuth_deg, -90.0, 90.0, "deg"))
    ph = math.radians(check_range("brush_deg", brush_deg, -180.0, 180.0, "deg"))
    check_range("server_y", server_y, -10.0, 10.0, "m")
    if target is None and (psi != 0 or ph != 0 or server_y != 0):
        raise InputError("azimuth_deg: the 3-D options (azimuth, brush, server_y) need a deuce or ad target")
    if target is not None:
        box_name(target)
    return psi, ph


@dataclass(frozen=True)
class Setup:
    """Everything but the angles of a serve: player, physics, criteria and the 3-D options (SI, rad)."""

    player: PlayerProfile
    flight: FlightParams
    impact_params: ImpactParams
    criteria: SeedCriteria
    target: str | None
    brush: float  #: [rad]
    server_y: float  #: [m]
    toss_vz: float  #: [m/s]
    dt: float  #: [s]
    method: str


def outcomes(setup: Setup, alpha_deg, beta_deg, azimuth_deg) -> dict:
    """Serves at arrays (broadcast) of impact angle, face angle and azimuth [deg]: the impacts
    (``impact_batch`` rows), the launch ``velocity``/``spin`` (N, 3), the flight table and :func:`judge`."""
    a, b, z = (np.atleast_1d(np.asarray(x, float)) for x in np.broadcast_arrays(alpha_deg, beta_deg, azimuth_deg))
    A, B, Z = np.radians(a), np.radians(b), np.radians(z)
    n, tu, tl = face_basis(B, Z)
    t = math.cos(setup.brush) * tu + math.sin(setup.brush) * tl
    toss = np.array([0.0, 0.0, setup.toss_vz])
    tn, tt = n @ toss, t @ toss
    imp = impact_batch(
        setup.player.racket_speed,
        A,
        setup.impact_params,
        toss_n=tn,
        toss_t=tt,
        dt=setup.dt,
        method=setup.method,
    )
    off_plane = toss[None, :] - tn[:, None] * n - tt[:, None] * t
    vel, spin = launch_3d(imp["v_n"], imp["v_t"], imp["omega"], B, Z, setup.brush)
    vel = vel + off_plane
    m = a.size
    states = np.column_stack(
        [
            np.full(m, setup.criteria.server_x),
            np.full(m, setup.server_y),
            np.full(m, setup.player.impact_height),
            vel,
            spin,
        ]
    )
    table = fly_batch(states, setup.flight)
    return {"impact": imp, "velocity": vel, "spin": spin, "table": table, **judge(table, setup.criteria, setup.target)}
