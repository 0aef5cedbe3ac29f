"""3-D racket-ball impact: a racket velocity and face orientation in 3-D.

The 2-D model of :mod:`tennislab.core.impact` is isotropic in the face plane,
so a 3-D impact is the 2-D one in the plane spanned by the face normal n and
the direction t of the racket's tangential velocity relative to the ball:

* relative racket velocity U = V_racket - u_ball (Galilean shift: the ball is at
  rest in its own frame; the ball's pre-impact velocity u is added back);
* U_n = U.n, U_t = U - U_n n, t = U_t/|U_t|, impact angle alpha = atan2(|U_t|, U_n);
* ball velocity u + v_n n + v_t t, spin vector omega (t x n) (the contact point
  is at -r n; a tangential force along +t gives a torque along t x n).

For n and U in the x-z plane with n = (cos b, 0, -sin b) this is exactly the 2-D
model (t x n = +y: topspin), tests/test_impact_3d.py.

Serve parametrisation (:func:`face_normal`, :func:`racket_velocity`): the face
normal is tilted down by the face angle beta and turned left by the azimuth psi
(rotation about +z); the racket moves at speed V at the impact angle alpha to
the normal, its tangential part along the *brush angle* phi in the face:
phi = 0 brushes straight up the back of the ball (topspin), phi = -90 deg
brushes toward the server's right (-y; a right-hander's slice, spin about +z,
curving left), phi in between (e.g. -45 deg, "7 to 1 o'clock") a kick serve
(topspin and sidespin).

References
----------
.. [1] Grosen, Kousted & Treichel (2021), 2-dimensional tennis serves show similar successful mechanical
    parameter across physiological differences, Aalborg University (seed 000) (the 2-D model it extends)
"""

from __future__ import annotations

import numpy as np

from tennislab.core.impact import ImpactParams, impact_batch
from tennislab.errors import InputError


def face_basis(beta, azimuth=0.0):
    """(n, t_up, t_left), each (..., 3): face normal, the face's "up" and "left" tangents.

    beta [rad] tilts the normal below the horizontal, azimuth [rad] turns it toward +y.
    """
    b, p = np.broadcast_arrays(np.asarray(beta, float), np.asarray(azimuth, float))
    cb, sb, cp, sp = np.cos(b), np.sin(b), np.cos(p), np.sin(p)
    z = np.zeros_like(b)
    n = np.stack([cb * cp, cb * sp, -sb], axis=-1)
    t_up = np.stack([sb * cp, sb * sp, cb], axis=-1)
    t_left = np.stack([-sp, cp, z], axis=-1)
    return n, t_up, t_left


def face_normal(beta, azimuth=0.0):
    """Unit face normal (..., 3) for face angle beta and azimuth [rad]."""
    return face_basis(beta, azimuth)[0]


def racket_velocity(speed, alpha, beta, azimuth=0.0, brush=0.0):
    """Racket velocity (..., 3) [m/s]: speed V at impact angle alpha to the normal, tangential part
    along the brush angle (0 = up the back of the ball, -pi/2 = toward the server's right)."""
    n, tu, tl = face_basis(beta, azimuth)
    V, a, ph = (np.asarray(x, float)[..., None] for x in np.broadcast_arrays(speed, alpha, brush))
    return V * (np.cos(a) * n + np.sin(a) * (np.cos(ph) * tu + np.sin(ph) * tl))


def impact_3d(
    racket_velocity,
    normal,
    params: ImpactParams | None = None,
    ball_velocity=(0.0, 0.0, 0.0),
    *,
    steps: int = 400,
    dt: float = 0.0,
    method: str = "rk4",
) -> dict[str, np.ndarray]:
    """Impacts of racket velocities (N, 3) [m/s] on faces with unit normals (N, 3).

    Returns ``velocity`` (N, 3) [m/s] and ``spin`` (N, 3) [rad/s] of the ball after
    impact, plus ``alpha`` [rad], ``contact_time`` [s], ``regime`` (0 slide, 1 roll)
    and the 2-D results ``v_n``, ``v_t``, ``omega`` in the impact plane.
    """
    Vr = np.atleast_2d(np.asarray(racket_velocity, float))
    n = np.atleast_2d(np.asarray(normal, float))
    u = np.atleast_2d(np.asarray(ball_velocity, float))
    Vr, n, u = np.broadcast_arrays(Vr, n, u)
    if Vr.shape[-1] != 3:
        raise InputError("racket_velocity, normal, ball_velocity: expected (N, 3) arrays")
    nn = np.linalg.norm(n, axis=-1, keepdims=True)
    if np.any(nn == 0) or not np.all(np.isfinite(Vr)):
        raise InputError("normal: must be a non-zero vector; velocities finite")
    n = n / nn
    U = Vr - u
    Un = np.sum(U * n, axis=-1)
    Ut = U - Un[:, None] * n
    ut = np.linalg.norm(Ut, axis=-1)
    # any unit vector in the face when there is no tangential motion
    helper = np.where(np.abs(n[:, 2:3]) < 0.9, np.array([[0.0, 0.0, 1.0]]), np.array([[1.0, 0.0, 0.0]]))
    fallback = np.cross(np.cross(n, helper), n)
    fallback /= np.linalg.norm(fallback, axis=-1, keepdims=True)
    t = np.where(
        ut[:, None] > 1e-12 * np.maximum(np.abs(Un)[:, None], 1.0), Ut / np.maximum(ut, 1e-300)[:, None], fallback
    )
    speed = np.hypot(Un, ut)
    alpha = np.arctan2(ut, Un)
    if np.any(alpha >= np.pi / 2):
        raise InputError("impact: the racket must approach the ball (U.n > 0)")
    r = impact_batch(speed, alpha, params, steps=steps, dt=dt, method=method)
    vel = u + r["v_n"][:, None] * n + r["v_t"][:, None] * t
    spin = r["omega"][:, None] * np.cross(t, n)
    return {
        "velocity": vel,
        "spin": spin,
        "alpha": alpha,
        "contact_time": r["contact_time"],
        "regime": r["regime"],
        "v_n": r["v_n"],
        "v_t": r["v_t"],
        "omega": r["omega"],
        "normal": n,
        "tangent": t,
    }
