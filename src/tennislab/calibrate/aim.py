"""Aim a batch of serves through their measured net points, and fly them to the bounce.

A serve is known by its impact point p0 [m], its speed just after impact v0 [m/s], its spin rate
w [rad/s] and the point (0, y_n, z_n) where it crossed the net plane.  Its direction (elevation a,
heading b) is not measured: :func:`aim_through_net` solves it so that the flight crosses x = 0 at
(y_n, z_n), by Newton's method on the two angles for all serves at once (each iteration one
:func:`~tennislab.core.flight.fly_batch` call holding every unconverged serve and its two
finite-difference neighbours).  The predicted bounce is then where that flight lands.

Spin vector: the tracker gives the rate only.  The axis is given relative to the launch direction
in the basis of :mod:`tennislab.core.launch` (h: horizontal, to the left of the flight = topspin
axis; u = d x h: "up" = sidespin curving the ball to its left; d: along the path) by two fractions
(f_top, f_side) of the rate, the rest along the path::

    omega = w (f_top h + f_side u + sqrt(1 - f_top^2 - f_side^2) d)

(pure topspin: (1, 0); an axis angle g in the plane across the path: (cos g, sin g)).  The spin
is set at launch and then evolves as the flight model says (constant unless ``spin_decay``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tennislab.core.flight import FlightParams, FlightTable, fly_batch
from tennislab.core.launch import direction, spin_basis
from tennislab.errors import InputError

#: finite-difference step of the angles [rad] (1.2 mm at the net for a 12 m flight: well above the
#: batch integrator's ~1e-6 m event noise at its default tolerance, far below any nonlinearity)
FD_STEP = 1e-4
NET_TOL = 1e-5  #: [m] the aim converges when the net point is matched to this distance
MAX_ITER = 25  #: Newton iterations at most
MAX_STEP = 0.1  #: [rad] largest change of an angle in one Newton step


def spin_vectors(rate, elevation, heading, f_top, f_side) -> np.ndarray:
    """Spin vectors (N, 3) [rad/s] from the rate [rad/s] and the axis fractions (module docstring)."""
    h, u = spin_basis(elevation, heading)
    d = direction(elevation, heading)
    ft = np.asarray(f_top, dtype=float)
    fs = np.asarray(f_side, dtype=float)
    norm = np.maximum(1.0, np.hypot(ft, fs))  # fractions beyond the unit circle: the axis direction only
    ft, fs = ft / norm, fs / norm
    fd = np.sqrt(np.clip(1.0 - ft * ft - fs * fs, 0.0, None))
    w = np.asarray(rate, dtype=float)
    return w[..., None] * (ft[..., None] * h + fs[..., None] * u + fd[..., None] * d)


def launch_states(position, speed, rate, elevation, heading, f_top, f_side) -> np.ndarray:
    """Initial states (N, 9) of serves launched at (elevation, heading) [rad]."""
    v = np.asarray(speed, dtype=float)[:, None] * direction(elevation, heading)
    w = spin_vectors(rate, elevation, heading, f_top, f_side)
    return np.ascontiguousarray(np.hstack([np.asarray(position, dtype=float), v, w]))


@dataclass(frozen=True)
class Aim:
    """Serves aimed through their net points (arrays of N; angles [rad], lengths [m]).

    ``net_miss`` is the distance left between the flight's net-plane crossing and the measured
    net point; ``converged`` marks serves matched to :data:`NET_TOL`; ``table`` is the event table
    of the aimed flights (landing = first contact of the ball centre at z = r).
    """

    elevation: np.ndarray
    heading: np.ndarray
    states: np.ndarray
    table: FlightTable
    net_miss: np.ndarray
    converged: np.ndarray
    iterations: int
    flights: int


def first_guess(position, speed, net_yz, gravity: float = 9.81) -> tuple[np.ndarray, np.ndarray]:
    """Elevation and heading [rad] of a drag-free straight shot at the net point (the Newton start)."""
    p = np.asarray(position, dtype=float)
    ny, nz = np.asarray(net_yz, dtype=float).T
    dx = -p[:, 0]
    dy = ny - p[:, 1]
    dist = np.hypot(dx, dy)
    t = 1.1 * dist / np.maximum(np.asarray(speed, dtype=float), 1.0)
    return np.arctan2(nz - p[:, 2] + 0.5 * gravity * t * t, dist), np.arctan2(dy, dx)


def aim_through_net(
    position,
    speed,
    rate,
    net_yz,
    params: FlightParams,
    *,
    f_top=1.0,
    f_side=0.0,
    start: tuple[np.ndarray, np.ndarray] | None = None,
    tol: float = NET_TOL,
    max_iter: int = MAX_ITER,
) -> Aim:
    """Solve elevation and heading of N serves so that each crosses x = 0 at its ``net_yz`` (N, 2) [m].

    ``position`` (N, 3) [m] ball-centre impact points (x != 0), ``speed`` (N,) [m/s], ``rate`` (N,)
    [rad/s], ``f_top``/``f_side`` scalars or (N,) (module docstring); ``start`` optional initial
    (elevation, heading) [rad] (e.g. a previous solution).  Serves that do not converge within
    ``max_iter`` keep their last angles and ``converged = False``.
    """
    p = np.ascontiguousarray(np.asarray(position, dtype=float))
    n = p.shape[0]
    if p.shape != (n, 3):
        raise InputError(f"position: expected an (N, 3) array, got shape {p.shape}")
    v = np.broadcast_to(np.asarray(speed, dtype=float), (n,))
    w = np.broadcast_to(np.asarray(rate, dtype=float), (n,))
    target = np.asarray(net_yz, dtype=float).reshape(n, 2)
    ft = np.broadcast_to(np.asarray(f_top, dtype=float), (n,))
    fs = np.broadcast_to(np.asarray(f_side, dtype=float), (n,))
    if np.any(p[:, 0] == 0.0):
        raise InputError("position: an impact point lies on the net plane x = 0")
    if start is None:
        a, b = first_guess(p, v, target, params.atmosphere.gravity)
    else:
        a, b = (np.array(s, dtype=float, copy=True) for s in start)
    active = np.arange(n)
    miss = np.full(n, np.inf)
    flights = 0
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007  (the count is reported)
        m = active.size
        if m == 0:
            break
        ia = active
        aa = np.concatenate([a[ia], a[ia] + FD_STEP, a[ia]])
        bb = np.concatenate([b[ia], b[ia], b[ia] + FD_STEP])
        idx = np.concatenate([ia, ia, ia])
        s = launch_states(p[idx], v[idx], w[idx], aa, bb, ft[idx], fs[idx])
        tab = fly_batch(s, params)
        flights += 3 * m
        ny, nz = tab["net_y"], tab["net_z"]
        f0 = np.stack([ny[:m], nz[:m]], axis=1) - target[ia]
        ja = (np.stack([ny[m : 2 * m], nz[m : 2 * m]], axis=1) - target[ia] - f0) / FD_STEP
        jb = (np.stack([ny[2 * m :], nz[2 * m :]], axis=1) - target[ia] - f0) / FD_STEP
        miss[ia] = np.hypot(f0[:, 0], f0[:, 1])
        ok = np.isfinite(miss[ia])
        done = ok & (miss[ia] < tol)
        det = ja[:, 0] * jb[:, 1] - ja[:, 1] * jb[:, 0]
        good = ok & np.isfinite(det) & (np.abs(det) > 1e-12) & ~done
        # Newton step: J (da, db) = -f0
        da = np.where(good, -(jb[:, 1] * f0[:, 0] - jb[:, 0] * f0[:, 1]) / np.where(good, det, 1.0), 0.0)
        db = np.where(good, -(-ja[:, 1] * f0[:, 0] + ja[:, 0] * f0[:, 1]) / np.where(good, det, 1.0), 0.0)
        scale = np.maximum(1.0, np.maximum(np.abs(da), np.abs(db)) / MAX_STEP)
        a[ia] += da / scale
        b[ia] += db / scale
        # a serve whose flight never reached the net: aim higher and retry
        lost = ~ok
        a[ia[lost]] += 0.02
        active = ia[~done]
    s = launch_states(p, v, w, a, b, ft, fs)
    tab = fly_batch(s, params)
    flights += n
    f0 = np.stack([tab["net_y"], tab["net_z"]], axis=1) - target
    miss = np.hypot(f0[:, 0], f0[:, 1])
    conv = np.isfinite(miss) & (miss < 10 * tol) & tab.ok
    return Aim(a, b, s, tab, miss, conv, it, flights)
