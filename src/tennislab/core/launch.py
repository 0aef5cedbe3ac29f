"""Launch vocabulary: speed, elevation and heading <-> velocity; spin rate and axis <-> spin vector.

One convention for every command that launches a ball (``fly``, the launcher, the web app), the
launcher paper's (seed 002 section 2: elevation a, heading b, spin-axis rotation g):

* direction of motion d = (cos a cos b, cos a sin b, sin a): elevation a above the horizontal,
  heading b from +x, positive toward +y (to the left of a player facing +x);
* spin basis h = unit(e_z x d) (horizontal, to the left of the flight) and u = d x h (up,
  perpendicular to d); the spin vector is omega = w (cos g h + sin g u) for a spin rate w and an
  axis angle g, so that
  g = 0 is pure topspin (the Magnus force omega x v points down), g = 180 backspin / slice (up),
  g = +90 sidespin curving the ball to its left (+y for a ball moving +x), g = -90 to its right.

Spin along the path (rifle / gyro spin, no Magnus force) has no axis angle: give the spin vector.
All angles in radians here; degrees and rpm are converted at the edges (:mod:`tennislab.units`).

References
----------
.. [1] Wojcicki, Pucilowski & Kulesza (2010), Acta Mechanica et Automatica (seed 002),
    section 2 (elevation, heading, spin-axis rotation)
"""

from __future__ import annotations

import math

import numpy as np

from tennislab.errors import InputError

#: Named spin axes -> axis angle g [deg] (module docstring).  ``slice`` is the groundstroke slice
#: (backspin); a slice *serve* curves sideways: give its angle (e.g. -60) instead.
SPIN_AXES_DEG: dict[str, float] = {
    "topspin": 0.0,
    "backspin": 180.0,
    "slice": 180.0,
    "sidespin": 90.0,
    "sidespin-left": 90.0,
    "sidespin-right": -90.0,
}


def spin_axis_angle(axis) -> float:
    """Axis angle g [rad] from a name of :data:`SPIN_AXES_DEG` or a number of degrees."""
    if isinstance(axis, str):
        key = axis.strip().lower()
        if key in SPIN_AXES_DEG:
            return math.radians(SPIN_AXES_DEG[key])
        try:
            value = float(key)
        except ValueError:
            allowed = ", ".join(SPIN_AXES_DEG)
            raise InputError(f"spin_axis: unknown axis {axis!r}; allowed: {allowed} or an angle in degrees") from None
    else:
        value = float(axis)
    if not math.isfinite(value) or not -360.0 <= value <= 360.0:
        raise InputError(f"spin_axis: {value:g} deg is outside the allowed range [-360, 360] deg")
    return math.radians(value)


def direction(elevation, heading) -> np.ndarray:
    """Unit direction d (..., 3) for elevation and heading [rad] (broadcast together)."""
    a, b = np.broadcast_arrays(np.asarray(elevation, dtype=float), np.asarray(heading, dtype=float))
    ca, sa, cb, sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
    return np.stack((ca * cb, ca * sb, sa), axis=-1)


def spin_basis(elevation, heading) -> tuple[np.ndarray, np.ndarray]:
    """(h, u) (..., 3): h horizontal to the left of the flight, u = d x h (module docstring)."""
    a, b = np.broadcast_arrays(np.asarray(elevation, dtype=float), np.asarray(heading, dtype=float))
    ca, sa, cb, sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
    h = np.stack((-sb, cb, np.zeros_like(cb)), axis=-1)
    u = np.stack((-sa * cb, -sa * sb, ca), axis=-1)
    return h, u


def path_spin_basis(velocity) -> tuple[np.ndarray, np.ndarray]:
    """(h, u) (3,) of :func:`spin_basis` for the direction of a velocity vector (3,), built from the vector.

    The same basis, perpendicular to the path: h = unit(e_z x d) (the topspin axis), u = d x h, d the
    unit velocity; computed by cross products of the vector itself instead of through its elevation and
    heading (:func:`describe_velocity`, then :func:`spin_basis`), so the two differ by round-off only
    (~1e-15).  A fit whose parameters are spin components about these axes (the track identification,
    :mod:`tennislab.calibrate.identify`) uses this form.  A vertical path (no horizontal direction) takes
    h = e_x.
    """
    v = np.asarray(velocity, dtype=float)
    d = v / max(float(np.linalg.norm(v)), 1e-9)
    h = np.cross([0.0, 0.0, 1.0], d)
    if np.linalg.norm(h) < 1e-6:  # a vertical path: any horizontal axis
        h = np.array([1.0, 0.0, 0.0])
    h /= np.linalg.norm(h)
    if np.cross(h, d)[2] > 0.0:  # h = the topspin axis: h x v points down (the Magnus force of topspin)
        h = -h
    return h, np.cross(d, h)


def launch_velocity(speed, elevation, heading) -> np.ndarray:
    """Velocity (..., 3) [m/s] from speed [m/s], elevation and heading [rad]."""
    return np.asarray(speed, dtype=float)[..., None] * direction(elevation, heading)


def spin_vector(elevation, heading, topspin=0.0, sidespin=0.0, along=0.0) -> np.ndarray:
    """The spin vector (..., 3) [rad/s] of a launch, from its components in the launch frame.

    omega = topspin h + sidespin u + along d (module docstring: h horizontal to the left of the
    flight, u = d x h, d the direction of motion), every component in rad/s; all arguments
    broadcast together.  The one builder of a launch's spin vector: every spin description
    (rate and axis angle, axis fractions, components in rpm) is turned into these components at
    its edge (:func:`axis_components`) and then built here (:func:`launch_states` too).
    """
    a, b, top, side, al = np.broadcast_arrays(
        *(np.asarray(x, dtype=float) for x in (elevation, heading, topspin, sidespin, along))
    )
    return np.stack(_spin_xyz(np.cos(a), np.sin(a), np.cos(b), np.sin(b), top, side, al), axis=-1)


def _spin_xyz(ca, sa, cb, sb, top, side, along):
    """(wx, wy, wz) of top h + side u + along d for the launch frame of cos/sin of elevation and heading."""
    return (
        -top * sb - side * sa * cb + along * ca * cb,
        top * cb - side * sa * sb + along * ca * sb,
        side * ca + along * sa,
    )


def frame(elevation, heading) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The launch frame (d, h, u), each (..., 3): direction of motion, topspin axis, up axis (module docstring)."""
    a, b = np.broadcast_arrays(np.asarray(elevation, dtype=float), np.asarray(heading, dtype=float))
    ca, sa, cb, sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
    d = np.stack((ca * cb, ca * sb, sa), axis=-1)
    h = np.stack((-sb, cb, np.zeros_like(cb)), axis=-1)
    u = np.stack((-sa * cb, -sa * sb, ca), axis=-1)
    return d, h, u


def axis_components(spin_rate, axis_angle) -> tuple[np.ndarray, np.ndarray]:
    """(topspin, sidespin) components [rad/s] of a spin rate [rad/s] about the axis angle g [rad]: w (cos g, sin g)."""
    w = np.asarray(spin_rate, dtype=float)
    g = np.asarray(axis_angle, dtype=float)
    return w * np.cos(g), w * np.sin(g)


def launch_spin(spin_rate, elevation, heading, axis_angle) -> np.ndarray:
    """Spin vector (..., 3) [rad/s] from spin rate |omega| [rad/s] and axis angle g [rad] about the flight."""
    return spin_vector(elevation, heading, *axis_components(spin_rate, axis_angle))


def launch_states(position, speed, elevation, heading, topspin=0.0, sidespin=0.0, along=0.0) -> np.ndarray:
    """Initial flight states (N, 9) [m, m/s, rad/s] of launches (the one launch-state builder).

    ``position`` (3,) or (N, 3) [m]; ``speed`` [m/s], ``elevation`` and ``heading`` [rad] and the
    spin components in the launch frame [rad/s] (:func:`spin_vector`) scalars or (N,) arrays,
    broadcast together to N rows of (x, y, z, vx, vy, vz, wx, wy, wz) for
    :func:`tennislab.core.flight.fly_batch`.  No range check (a hot path): the flight marks rows
    outside the physical range.
    """
    p = np.asarray(position, dtype=float)
    cols = [np.asarray(x, dtype=float).reshape(-1) for x in (speed, elevation, heading, topspin, sidespin, along)]
    n = max(p.shape[0] if p.ndim == 2 else 1, *(c.size for c in cols))
    if any(c.size not in (1, n) for c in cols) or (p.ndim == 2 and p.shape[0] not in (1, n)):
        raise InputError("launch_states: position, speed, angles and spin do not broadcast to one number of launches")
    return launch_rows(p, n, *cols)


def launch_rows(p, n, v, a, b, top, side, al) -> np.ndarray:
    """:func:`launch_states` of inputs already checked (a hot path: no broadcasting, no check): position (3,) or
    (n, 3) [m], speed [m/s], elevation, heading [rad] and the spin components [rad/s] scalars or (n,)."""
    ca, sa, cb, sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
    out = np.empty((n, 9))
    out[:, 0:3] = p
    out[:, 3] = v * ca * cb
    out[:, 4] = v * ca * sb
    out[:, 5] = v * sa
    out[:, 6], out[:, 7], out[:, 8] = _spin_xyz(ca, sa, cb, sb, top, side, al)
    return out


def describe_velocity(velocity) -> tuple[float, float, float]:
    """(speed [m/s], elevation [rad], heading [rad]) of a velocity vector."""
    v = np.asarray(velocity, dtype=float)
    speed = float(np.linalg.norm(v))
    if speed == 0.0:
        return 0.0, 0.0, 0.0
    return speed, math.asin(max(-1.0, min(1.0, v[2] / speed))), math.atan2(v[1], v[0])


def describe_spin(spin, velocity) -> dict[str, float]:
    """A spin vector described relative to the flight: rate [rad/s], the components along the
    topspin axis h, the up axis u and the path d [rad/s], and the axis angle g [rad] of its part
    perpendicular to the path (NaN when that part is zero)."""
    w = np.asarray(spin, dtype=float)
    _, a, b = describe_velocity(velocity)
    h, u = spin_basis(a, b)
    d = direction(a, b)
    wh, wu, wd = float(w @ h), float(w @ u), float(w @ d)
    angle = math.atan2(wu, wh) if (wh or wu) else float("nan")
    return {"rate": float(np.linalg.norm(w)), "topspin": wh, "sidespin": wu, "along_path": wd, "axis_angle": angle}
