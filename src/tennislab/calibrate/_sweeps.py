"""Compiled helpers of the track calibration: positions of one flight and their finite-difference
Jacobians, all through :func:`tennislab.core.integrators.sweep_positions` (core's RK4 on core's
right-hand side, :func:`tennislab.core.dynamics.derivative`); nothing here integrates on its own.

A flight's parameters ``q`` are its state at its *last* sample (position [m], velocity [m/s], spin
vector [rad/s]: 9 values) and optionally a drag scale s_D (a 10th value, drag constant k s_D); the
flight is swept backward from there over the earlier sample times.  The global parameters are the aero
model's parameter array followed by the spin-decay rate [1/s] and the wind (x, y, z) [m/s] (``ext``:
the aero model's kernel reads ``ext[:-4]`` as its parameters); ``consts`` are k = 1/2 rho A / m [1/m],
gravity [m/s^2] and the ball radius [m].
"""

from __future__ import annotations

import numba as nb
import numpy as np
from numba import types

from tennislab.core.aero import AERO_FUNCTION_TYPE
from tennislab.core.integrators import sweep_positions

_F = types.float64
_V = _F[::1]
_M = _F[:, ::1]
_I = types.int64[::1]
#: q, t, h, aero, ext, consts (k, g, r), out
_POS_SIG = types.void(_V, _V, _F, AERO_FUNCTION_TYPE, _V, _V, _M)
#: q, t, x, w (weights (n,)), h, aero, ext, consts, free q indices, steps, res (3n,), jac (3n, len(free))
_JAC_SIG = types.void(_V, _V, _M, _V, _F, AERO_FUNCTION_TYPE, _V, _V, _I, _V, _V, _M)


@nb.njit(cache=True)
def _sweep(q, t, h, aero, ext, consts, out, backward):
    """Positions (n, 3) at the times ``t`` (ascending) of the flight whose state is ``q`` at ``t[-1]``
    (``backward``) or at ``t[0]``."""
    n = t.size
    na = ext.size - 4
    ap = ext[:na]
    sd = q[9] if q.size > 9 else 1.0
    k = consts[0]
    y0 = q[:9].copy()
    at = n - 1 if backward else 0
    for c in range(3):
        out[at, c] = q[c]
    if n > 1:
        idx = (np.arange(n - 2, -1, -1) if backward else np.arange(1, n)).astype(np.int64)
        sweep_positions(
            y0, t[at], t, idx, n - 1, -h if backward else h, aero, ap, k * sd, k, consts[1], consts[2],
            ext[na + 1], ext[na + 2], ext[na + 3], ext[na], out,
        )  # fmt: skip


@nb.njit(_POS_SIG, cache=True)
def positions(q, t, h, aero, ext, consts, out):
    """Positions (n, 3) at the times ``t`` (ascending) of the flight whose state at ``t[-1]`` is ``q``."""
    _sweep(q, t, h, aero, ext, consts, out, True)


@nb.njit(_POS_SIG, cache=True)
def positions_forward(q, t, h, aero, ext, consts, out):
    """As :func:`positions` for a state ``q`` at ``t[0]`` (swept forward over the later samples)."""
    _sweep(q, t, h, aero, ext, consts, out, False)


@nb.njit(cache=True)
def _residual(q, t, x, w, h, aero, ext, consts, pos, res):
    positions(q, t, h, aero, ext, consts, pos)
    n = t.size
    for i in range(n):
        for c in range(3):
            res[3 * i + c] = w[i] * (pos[i, c] - x[i, c])


@nb.njit(cache=True)
def _fd_jacobian(q, t, x, w, h, aero, ext, consts, free, steps, res, jac, of_ext):
    """Weighted residuals and their forward-difference Jacobian with respect to ``ext[free]``
    (``of_ext``) or ``q[free]``."""
    n = t.size
    pos = np.empty((n, 3))
    _residual(q, t, x, w, h, aero, ext, consts, pos, res)
    r2 = np.empty(3 * n)
    q2 = q.copy()
    e2 = ext.copy()
    for j in range(free.size):
        i = free[j]
        if of_ext:
            e2[i] = ext[i] + steps[j]
        else:
            q2[i] = q[i] + steps[j]
        _residual(q2, t, x, w, h, aero, e2, consts, pos, r2)
        for m in range(3 * n):
            jac[m, j] = (r2[m] - res[m]) / steps[j]
        if of_ext:
            e2[i] = ext[i]
        else:
            q2[i] = q[i]


@nb.njit(_JAC_SIG, cache=True)
def shot_jacobian(q, t, x, w, h, aero, ext, consts, free, steps, res, jac):
    """Weighted residuals ``w (pos - x)`` (3n,) and their forward-difference Jacobian with respect to
    the flight parameters ``q[free]`` (steps ``steps``)."""
    _fd_jacobian(q, t, x, w, h, aero, ext, consts, free, steps, res, jac, False)


@nb.njit(_JAC_SIG, cache=True)
def global_jacobian(q, t, x, w, h, aero, ext, consts, free, steps, res, jac):
    """As :func:`shot_jacobian`, with respect to the global parameters ``ext[free]``."""
    _fd_jacobian(q, t, x, w, h, aero, ext, consts, free, steps, res, jac, True)
