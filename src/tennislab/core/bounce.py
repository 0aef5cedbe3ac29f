"""Ball-court impact: vertical restitution plus friction, sliding or gripping.

Rigid-ball impulse model (Brody 1984, Phys. Teach. 22:494; extended to 3-D
and to a gripping ball after Cross 2002, Am. J. Phys. 70:1093 and Cross 2005,
Am. J. Phys. 73:914).  Frame: ground z = 0, ball centre at height r at contact,
contact point at -r e_z from the centre.

* Normal impulse (per unit mass): P_n = (1 + e) |v_in,z|;  v_out,z = e |v_in,z|.
* Slip of the contact point (horizontal): u = (v_x - r w_y, v_y + r w_x).
* A horizontal impulse P (per unit mass) changes v_t by P and spin by
  dw = (P_y, -P_x, 0) / (alpha r), alpha = I / (m r^2) (thin shell: 2/3,
  the seeds' choice; ``Ball.inertia_factor``), so the slip changes by
  P (1 + 1/alpha).
* Sliding throughout (Brody): P = -mu P_n u/|u|, when
  mu P_n (1 + 1/alpha) < (1 + e_x) |u|.
* Otherwise the ball grips: the slip goes to -e_x u (e_x = 0: rolls out,
  Brody's v_x2 = (v_x1 + alpha r w_1)/(1 + alpha), 3/5 v_x1 for a thin shell
  without spin; e_x > 0: leaves overspinning, the friction having reversed
  as Cross 2002 measured):  P = -(1 + e_x) alpha u / (1 + alpha).
* The vertical spin component w_z is unchanged (no drilling friction).

The normal force acting off-centre (Cross 2002) is represented only through
e_x.  ``e`` is constant (real balls' e falls with impact speed).

:func:`court_pace_rating` simulates the ITF court-pace test on a surface with
this model (the surfaces and the CPR formula live in
:mod:`tennislab.core.surfaces`, which knows nothing of the bounce).

References
----------
.. [1] Brody (1984), Phys. Teach. 22:494
.. [2] Cross (2002), Am. J. Phys. 70:1093
.. [3] Cross (2005), Am. J. Phys. 73:914
.. [4] ITF CS 01/02, court pace rating (ITF Technical Booklet 2015)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba as nb
import numpy as np

from tennislab.core._jit import JIT
from tennislab.core.ball import Ball
from tennislab.core.surfaces import ITF_CPR_ANGLE, ITF_CPR_SPEED, cpr_category, cpr_formula, get_surface
from tennislab.errors import InputError, check_vector

MODES = ("slide", "roll", "grip")  #: mode codes 0, 1, 2 of the kernel


@nb.njit(**JIT)
def bounce_kernel(vin, win, r, alpha, e, mu, ex, vout, wout):
    """Outgoing velocity and spin of one impact; returns the mode code (0 slide, 1 roll, 2 grip).

    vin, win : incoming velocity [m/s] and spin [rad/s] (3,) with vin[2] < 0
    r : ball radius [m]; alpha : I/(m r^2) [-]
    e, mu, ex : vertical COR, sliding friction, tangential COR of a gripping ball [-]
    vout, wout : outputs (3,)
    """
    vz = -vin[2]
    pn = (1.0 + e) * vz
    ux = vin[0] - r * win[1]
    uy = vin[1] + r * win[0]
    u = math.sqrt(ux * ux + uy * uy)
    mode = 0
    if u <= 0.0:
        px = 0.0
        py = 0.0
        mode = 1 if ex == 0.0 else 2
    elif mu * pn * (1.0 + 1.0 / alpha) < (1.0 + ex) * u:
        px = -mu * pn * ux / u
        py = -mu * pn * uy / u
    else:
        f = (1.0 + ex) * alpha / (1.0 + alpha)
        px = -f * ux
        py = -f * uy
        mode = 1 if ex == 0.0 else 2
    vout[0] = vin[0] + px
    vout[1] = vin[1] + py
    vout[2] = e * vz
    wout[0] = win[0] + py / (alpha * r)
    wout[1] = win[1] - px / (alpha * r)
    wout[2] = win[2]
    return mode


@nb.njit(**JIT)
def bounce_batch_kernel(vin, win, r, alpha, e, mu, ex, vout, wout, modes):
    """:func:`bounce_kernel` over rows of (N, 3) arrays."""
    for i in range(vin.shape[0]):
        modes[i] = bounce_kernel(vin[i], win[i], r, alpha, e, mu, ex, vout[i], wout[i])


@dataclass(frozen=True)
class BounceResult:
    """One impact: outgoing velocity [m/s] and spin [rad/s], mode (slide/roll/grip),
    incoming slip speed of the contact point [m/s] and the friction impulse per mass [m/s]."""

    velocity_out: np.ndarray
    spin_out: np.ndarray
    mode: str
    slip_in: np.ndarray
    friction_impulse: np.ndarray


def bounce(velocity_in, spin_in, surface, ball=None) -> BounceResult:
    """Outgoing velocity and spin of a ball hitting the court.

    Parameters
    ----------
    velocity_in : incoming velocity [m/s], v_z < 0
    spin_in : incoming spin vector [rad/s]
    surface : :class:`~tennislab.core.surfaces.Surface` or a registered name
    ball : :class:`~tennislab.core.ball.Ball` (radius, inertia factor); default ITF ball
    """
    s = get_surface(surface)
    ball = ball or Ball()
    vin = np.array(check_vector("velocity_in", velocity_in), dtype=np.float64)
    win = np.array(check_vector("spin_in", spin_in), dtype=np.float64)
    if not vin[2] < 0:
        raise InputError(f"velocity_in[2]: {vin[2]:g} m/s must be < 0 (ball moving down at impact)")
    vout = np.empty(3)
    wout = np.empty(3)
    code = bounce_kernel(vin, win, ball.radius, ball.inertia_factor, s.e, s.mu, s.e_x, vout, wout)
    slip = np.array([vin[0] - ball.radius * win[1], vin[1] + ball.radius * win[0]])
    return BounceResult(vout, wout, MODES[code], slip, vout[:2] - vin[:2])


def bounce_batch(velocity_in, spin_in, surface, ball=None):
    """Vectorised :func:`bounce`: (N, 3) arrays in, (vout, wout, mode codes) out."""
    s = get_surface(surface)
    ball = ball or Ball()
    vin = np.ascontiguousarray(velocity_in, dtype=np.float64).reshape(-1, 3)
    win = np.ascontiguousarray(spin_in, dtype=np.float64).reshape(-1, 3)
    vout = np.empty_like(vin)
    wout = np.empty_like(win)
    modes = np.empty(vin.shape[0], dtype=np.int64)
    bounce_batch_kernel(vin, win, ball.radius, ball.inertia_factor, s.e, s.mu, s.e_x, vout, wout, modes)
    return vout, wout, modes


def court_pace_rating(
    surface, ball=None, speed: float = ITF_CPR_SPEED, angle: float = ITF_CPR_ANGLE, spin: float = 0.0
) -> dict:
    """Simulate the ITF court-pace test (ITF CS 01/02) on a surface with the bounce model.

    Parameters
    ----------
    surface : :class:`~tennislab.core.surfaces.Surface` or name
    ball : :class:`~tennislab.core.ball.Ball` (default ITF type 2, thin shell)
    speed : incoming speed [m/s] (ITF: 30 +- 2)
    angle : incoming angle to the surface [rad] (ITF: 16 +- 2 deg)
    spin : incoming topspin [rad/s] (ITF: <= 3 rev/s)

    Returns a dict with the apparent ``e`` and ``mu`` (ITF definitions), ``cpr``
    (:func:`~tennislab.core.surfaces.cpr_formula`), ``category`` and the bounce ``mode``.
    """
    s = get_surface(surface)
    ball = ball or Ball()
    vin = (speed * math.cos(angle), 0.0, -speed * math.sin(angle))
    res = bounce(vin, (0.0, spin, 0.0), s, ball)
    e_app = res.velocity_out[2] / -vin[2]
    mu_app = (vin[0] - res.velocity_out[0]) / (-vin[2] * (1.0 + e_app))
    cpr = cpr_formula(e_app, mu_app)
    return {"surface": s.name, "e": e_app, "mu": mu_app, "cpr": cpr, "category": cpr_category(cpr), "mode": res.mode}
