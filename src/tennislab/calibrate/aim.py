"""Aim a batch of serves through their measured net points, and fly them to the bounce.

A serve is known by its impact point p0 [m], its speed just after impact v0 [m/s], its spin rate
w [rad/s] and the point (0, y_n, z_n) where it crossed the net plane.  Its direction (elevation a,
heading b) is not measured: :func:`aim_through_net` solves it so that the flight crosses x = 0 at
(y_n, z_n), by Newton's method on the two angles for all serves at once: the aiming primitive
:func:`tennislab.core.shoot.shoot` with ``at="net"`` (each iteration one
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

import warnings
from dataclasses import dataclass

import numpy as np

from tennislab.core import launch
from tennislab.core.flight import FlightParams, FlightTable
from tennislab.core.shoot import FD_STEP, MAX_ITER, MAX_STEP, first_guess, shoot
from tennislab.core.shoot import TOL as NET_TOL
from tennislab.errors import InputError

__all__ = [
    "FD_STEP",
    "MAX_ITER",
    "MAX_STEP",
    "NET_TOL",
    "Aim",
    "aim_through_net",
    "first_guess",
    "serve_states",
    "spin_from_fractions",
    "spin_vectors",
]


def spin_from_fractions(rate, f_top, f_side) -> np.ndarray:
    """Spin components (..., 3) (topspin, sidespin, along the path) [rad/s] from the rate [rad/s] and the
    axis fractions (module docstring; fractions beyond the unit circle give the axis direction only)."""
    ft = np.asarray(f_top, dtype=float)
    fs = np.asarray(f_side, dtype=float)
    norm = np.maximum(1.0, np.hypot(ft, fs))
    ft, fs = ft / norm, fs / norm
    fd = np.sqrt(np.clip(1.0 - ft * ft - fs * fs, 0.0, None))
    w = np.asarray(rate, dtype=float)
    return np.stack(np.broadcast_arrays(w * ft, w * fs, w * fd), axis=-1)


def spin_vectors(rate, elevation, heading, f_top, f_side) -> np.ndarray:
    """Spin vectors (N, 3) [rad/s] from the rate [rad/s] and the axis fractions (built by
    :func:`tennislab.core.launch.spin_vector`)."""
    c = spin_from_fractions(rate, f_top, f_side)
    return launch.spin_vector(elevation, heading, c[..., 0], c[..., 1], c[..., 2])


def serve_states(position, speed, rate, elevation, heading, f_top, f_side) -> np.ndarray:
    """Initial states (N, 9) of serves launched at (elevation, heading) [rad] with a spin rate [rad/s] about
    the axis of the fractions (module docstring): :func:`tennislab.core.launch.launch_states` of
    :func:`spin_from_fractions`."""
    c = spin_from_fractions(rate, f_top, f_side)
    return launch.launch_states(position, speed, elevation, heading, c[..., 0], c[..., 1], c[..., 2])


def __getattr__(name: str):
    """``launch_states`` and ``spin_components``: the old names of :func:`serve_states` and
    :func:`spin_from_fractions`, kept working with a :class:`DeprecationWarning`
    (``core.launch.launch_states`` takes the launch-frame components: one name, one thing)."""
    if name == "launch_states":
        warnings.warn(
            "tennislab.calibrate.aim.launch_states is now serve_states (tennislab.core.launch.launch_states "
            "takes the spin's launch-frame components)",
            DeprecationWarning,
            stacklevel=2,
        )
        return serve_states
    if name == "spin_components":
        warnings.warn(
            "tennislab.calibrate.aim.spin_components is now spin_from_fractions (linecall's spin_components "
            "describes a fitted spin)",
            DeprecationWarning,
            stacklevel=2,
        )
        return spin_from_fractions
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


@dataclass(frozen=True)
class Aim:
    """Serves aimed through their net points (arrays of N; angles [rad], lengths [m]).

    ``net_miss`` is the distance left between the flight's net-plane crossing and the measured
    net point; ``converged`` marks serves matched to 10 x :data:`NET_TOL`; ``table`` is the event table
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
    ``max_iter`` keep their last angles and ``converged = False``.  The aiming itself is
    :func:`tennislab.core.shoot.shoot` (``at="net"``).
    """
    p = np.ascontiguousarray(np.asarray(position, dtype=float))
    n = p.shape[0]
    if p.ndim != 2 or p.shape != (n, 3):
        raise InputError(f"position: expected an (N, 3) array, got shape {p.shape}")
    v = np.broadcast_to(np.asarray(speed, dtype=float), (n,))
    w = np.broadcast_to(np.asarray(rate, dtype=float), (n,))
    target = np.asarray(net_yz, dtype=float).reshape(n, 2)
    ft = np.broadcast_to(np.asarray(f_top, dtype=float), (n,))
    fs = np.broadcast_to(np.asarray(f_side, dtype=float), (n,))
    if np.any(p[:, 0] == 0.0):
        raise InputError("position: an impact point lies on the net plane x = 0")
    s = shoot(
        p, v, target, params, spin=spin_from_fractions(w, ft, fs), at="net", start=start, tol=tol, max_iter=max_iter
    )
    return Aim(s.elevation, s.heading, s.states, s.table, s.miss, s.converged, s.iterations, s.flights)
