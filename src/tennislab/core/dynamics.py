"""The one right-hand side of ball flight, shared by every integration path.

State y (9): position (x, y, z) [m], velocity (vx, vy, vz) [m/s], spin vector
(wx, wy, wz) [rad/s], in the court frame (see :mod:`tennislab.core.court`).

    m dv/dt = -m g e_z - 1/2 rho A s_D C_D |u| u + 1/2 rho A s_L C_L |u|^2 (w x u)/(|w||u|)
    dw/dt   = -lambda w

where u = v - wind is the air-relative velocity, C_D and C_L come from the aero
model at (|u|, |w|), and lambda [1/s] is an optional exponential spin-decay rate
(default 0: the seeds neglect spin decay; seed 002 section 3 reports video
showing almost none).  Cross & Lindsey 2014 measured about 2 % spin loss over
6.4 m at 15-30 m/s, i.e. lambda ~ 0.05-0.1 /s.  Drag: seed 000 eq 1, seed 002
eq 1; lift: seed 000 eq 2, seed 002 eqs 3 and 5-7 (whose component form is
omega x v; its eq 3 writes v x omega, a sign slip noted in docs/seeds.md).
s_D and s_L are scales of the aero model's coefficients (1 for a flight as
modelled; the line-calling track fit frees them per shot), passed in as
kd = k s_D and kl = k s_L.

References
----------
.. [1] Grosen, Kousted & Treichel (2021), 2-dimensional tennis serves show similar successful mechanical
    parameter across physiological differences, Aalborg University (seed 000), eqs 1-2 (drag, lift)
.. [2] Wojcicki, Pucilowski & Kulesza (2010), Acta Mechanica et Automatica (seed 002), eqs 1, 3, 5-7
.. [3] Cross & Lindsey (2014), Sports Eng. 17:89 (spin loss in flight)
"""

from __future__ import annotations

import math

import numba as nb
from numba import types

from tennislab.core._jit import JIT
from tennislab.core.aero import AERO_FUNCTION_TYPE, aero_coefficients

_F = types.float64
DERIVATIVE_SIGNATURE = types.void(_F[::1], _F[::1], AERO_FUNCTION_TYPE, _F[::1], _F, _F, _F, _F, _F, _F, _F, _F)


@nb.njit(**JIT, inline="always")
def acceleration(vx, vy, vz, wx, wy, wz, aero, aero_p, kd, kl, g, r, wind_x, wind_y, wind_z):
    """(ax, ay, az) [m/s^2] of a ball moving at (vx, vy, vz) spinning at (wx, wy, wz): the force law
    of :func:`derivative` on scalars."""
    w = math.sqrt(wx * wx + wy * wy + wz * wz)
    return acceleration_at_spin(vx, vy, vz, wx, wy, wz, w, aero, aero_p, kd, kl, g, r, wind_x, wind_y, wind_z)


@nb.njit(**JIT, inline="always")
def spin_rate(Y, lane):
    """|w| [rad/s] of the spin in column ``lane`` of ``Y`` (9, lanes): :func:`acceleration`'s, for
    :func:`derivative_lanes`'s ``wn``."""
    return math.sqrt(Y[6, lane] * Y[6, lane] + Y[7, lane] * Y[7, lane] + Y[8, lane] * Y[8, lane])


@nb.njit(**JIT, inline="always")
def lane_spin_rate(Y, lane, wn, dec):
    """|w| [rad/s] of column ``lane`` of ``Y``: the lane's kept ``wn[lane]`` (:func:`spin_rate` of its
    start) without spin decay (``dec`` 0: the stages keep the spin to the bit), else computed from ``Y``."""
    return wn[lane] if dec == 0.0 else spin_rate(Y, lane)


@nb.njit(**JIT, inline="always")
def acceleration_at_spin(vx, vy, vz, wx, wy, wz, w, aero, aero_p, kd, kl, g, r, wind_x, wind_y, wind_z):
    """:func:`acceleration` with the spin rate ``w`` = |(wx, wy, wz)| [rad/s] given (the one statement
    of the force law; the lockstep kernel of :mod:`tennislab.core.lockstep` evaluates it lane by lane,
    each lane's |w| computed once a flight when the spin does not decay)."""
    ux = vx - wind_x
    uy = vy - wind_y
    uz = vz - wind_z
    u = math.sqrt(ux * ux + uy * uy + uz * uz)
    cd, cl = aero_coefficients(aero, u, w, r, aero_p)
    d = -kd * cd * u
    ax = d * ux
    ay = d * uy
    az = d * uz - g
    if w > 0.0 and u > 0.0:
        f = kl * cl * u / w
        ax += f * (wy * uz - wz * uy)
        ay += f * (wz * ux - wx * uz)
        az += f * (wx * uy - wy * ux)
    return ax, ay, az


@nb.njit(**JIT, inline="always")
def derivative_lanes(Y, F, n, aero, ap, k, g, r, wx, wy, wz, dec, wn):
    """``F[:, l]`` = dy/dt at ``Y[:, l]`` for every lane ``l < n`` (states in columns: the structure of
    arrays of the lockstep kernel, :mod:`tennislab.core.lockstep`): :func:`derivative` lane by lane, through
    :func:`acceleration_at_spin`, inlined so that LLVM evaluates the lanes in SIMD registers.  Without
    spin decay (``dec`` 0) a flight's spin is constant, stage by stage to the bit (its slopes are 0), and
    the lane's |w| is ``wn[l]`` (:func:`lane_spin_rate`: one square root of three per evaluation spared);
    otherwise it is computed from ``Y``.  Without spin decay the spin's slopes (0) are not written: the
    caller's ``F`` holds them (the lockstep kernel's stages start as zeros)."""
    for lane in range(n):
        w = lane_spin_rate(Y, lane, wn, dec)
        ax, ay, az = acceleration_at_spin(
            Y[3, lane], Y[4, lane], Y[5, lane], Y[6, lane], Y[7, lane], Y[8, lane], w, aero, ap, k, k, g, r, wx, wy, wz
        )
        F[0, lane] = Y[3, lane]
        F[1, lane] = Y[4, lane]
        F[2, lane] = Y[5, lane]
        F[3, lane] = ax
        F[4, lane] = ay
        F[5, lane] = az
    if dec != 0.0:
        for lane in range(n):
            F[6, lane] = -dec * Y[6, lane]
            F[7, lane] = -dec * Y[7, lane]
            F[8, lane] = -dec * Y[8, lane]


@nb.njit(**JIT)
def derivative(y, out, aero, aero_p, kd, kl, g, r, wind_x, wind_y, wind_z, decay):
    """Fill ``out`` with dy/dt.

    Parameters
    ----------
    y : state (9,) [m, m/s, rad/s]
    out : output (9,)
    aero : aero kernel (v, w, r, p) -> (C_D, C_L) as a first-class function,
        or its inline tag (:func:`tennislab.core.aero.inline_tag`: the formula
        is compiled into the caller)
    aero_p : its parameters
    kd, kl : 1/2 rho A / m [1/m] times the drag and the lift scale s_D, s_L
    g : gravity [m/s^2]
    r : ball radius [m]
    wind_x, wind_y, wind_z : wind velocity [m/s]
    decay : spin-decay rate lambda [1/s]
    """
    wx = y[6]
    wy = y[7]
    wz = y[8]
    ax, ay, az = acceleration(y[3], y[4], y[5], wx, wy, wz, aero, aero_p, kd, kl, g, r, wind_x, wind_y, wind_z)
    out[0] = y[3]
    out[1] = y[4]
    out[2] = y[5]
    out[3] = ax
    out[4] = ay
    out[5] = az
    out[6] = -decay * wx
    out[7] = -decay * wy
    out[8] = -decay * wz


@nb.njit(DERIVATIVE_SIGNATURE, **JIT)
def derivative_call(y, out, aero, aero_p, kd, kl, g, r, wind_x, wind_y, wind_z, decay):
    """:func:`derivative` with a fixed signature, for calls from Python (the SciPy path).

    The aero kernel arrives as a first-class function, so this one compiled
    (and cached) entry point serves every model without recompiling.
    """
    derivative(y, out, aero, aero_p, kd, kl, g, r, wind_x, wind_y, wind_z, decay)
