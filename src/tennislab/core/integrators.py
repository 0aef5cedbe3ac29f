"""Compiled batch integrator: Dormand-Prince 5(4) with dense output and events.

One trajectory per initial state, integrated in parallel (``numba.prange``)
with the adaptive Dormand & Prince (1980) 5(4) pair (J. Comput. Appl. Math.
6:19), its free 4th-order continuous extension (Shampine 1986, Math. Comp.
46:135; the coefficients SciPy's RK45 uses) for locating events, and the
standard step-size controller (Hairer, Norsett & Wanner, Solving ODEs I,
section II.4).  Events are found by safeguarded Newton iteration on the
interpolant, to ~1e-14 in the step fraction, never at a step end.  The right-hand side is
:func:`tennislab.core.dynamics.derivative`, the same one the SciPy path uses.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numba import types

from tennislab.core.aero import AERO_FUNCTION_TYPE
from tennislab.core.court import net_height_linear
from tennislab.core.dynamics import derivative
from tennislab.core.events import (
    COL,
    NCOLS,
    NET_HIT,
    NET_NONE,
    NET_OVER,
    STATUS_BAD_START,
    STATUS_NO_LANDING,
    STATUS_OK,
)

# Dormand-Prince 5(4) tableau
_C = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0])
_A = np.array(
    [
        [0, 0, 0, 0, 0],
        [1 / 5, 0, 0, 0, 0],
        [3 / 40, 9 / 40, 0, 0, 0],
        [44 / 45, -56 / 15, 32 / 9, 0, 0],
        [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0],
        [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656],
    ]
)
_B = np.array([35 / 384, 0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84])
_E = np.array([-71 / 57600, 0, 71 / 16695, -71 / 1920, 17253 / 339200, -22 / 525, 1 / 40])
_P = np.array(
    [
        [1, -8048581381 / 2820520608, 8663915743 / 2820520608, -12715105075 / 11282082432],
        [0, 0, 0, 0],
        [0, 131558114200 / 32700410799, -68118460800 / 10900136933, 87487479700 / 32700410799],
        [0, -1754552775 / 470086768, 14199869525 / 1410260304, -10690763975 / 1880347072],
        [0, 127303824393 / 49829197408, -318862633887 / 49829197408, 701980252875 / 199316789632],
        [0, -282668133 / 205662961, 2019193451 / 616988883, -1453857185 / 822651844],
        [0, 40617522 / 29380423, -110615467 / 29380423, 69997945 / 29380423],
    ]
)

# scalar copies of the tableau for the unrolled stages
_A21 = _A[1, 0]
_A31, _A32 = _A[2, 0], _A[2, 1]
_A41, _A42, _A43 = _A[3, 0], _A[3, 1], _A[3, 2]
_A51, _A52, _A53, _A54 = _A[4, 0], _A[4, 1], _A[4, 2], _A[4, 3]
_A61, _A62, _A63, _A64, _A65 = _A[5, 0], _A[5, 1], _A[5, 2], _A[5, 3], _A[5, 4]
_B1, _B3, _B4, _B5, _B6 = _B[0], _B[2], _B[3], _B[4], _B[5]
_E1, _E3, _E4, _E5, _E6, _E7 = _E[0], _E[2], _E[3], _E[4], _E[5], _E[6]

# consts vector layout passed to the kernel
K_K, K_G, K_R, K_WX, K_WY, K_WZ, K_DECAY, K_HC, K_HP, K_YP, K_TMAX, K_RTOL, K_ATOL = range(13)
NCONSTS = 13

_c_apex_t = COL["apex_t"]
_c_apex_x = COL["apex_x"]
_c_apex_y = COL["apex_y"]
_c_apex_z = COL["apex_z"]
_c_n_steps = COL["n_steps"]
_c_net_h = COL["net_h"]
_c_net_status = COL["net_status"]
_c_net_t = COL["net_t"]
_c_net_y = COL["net_y"]
_c_net_z = COL["net_z"]
_c_status = COL["status"]
_iLAND_T = COL["land_t"]
_iNET_T = COL["net_t"]
_iAPEX_T = COL["apex_t"]

_FASTMATH = {"nsz", "arcp", "contract", "afn", "reassoc"}


@nb.njit(cache=True, error_model="numpy", fastmath=_FASTMATH, inline="always")
def _dense_comp(theta, c, y0, K, h, P):
    s = 0.0
    for k in range(7):
        q = theta * (P[k, 0] + theta * (P[k, 1] + theta * (P[k, 2] + theta * P[k, 3])))
        s += K[k, c] * q
    return y0[c] + h * s


@nb.njit(cache=True, error_model="numpy", fastmath=_FASTMATH)
def _dense_full(theta, y0, K, h, P, out):
    for c in range(9):
        out[c] = _dense_comp(theta, c, y0, K, h, P)


@nb.njit(cache=True, error_model="numpy", fastmath=_FASTMATH)
def _root(c, target, y0, K, h, P, f0, f1, lo=0.0):
    """theta in [lo, 1] where the interpolant's component c equals target.

    The component is a quartic in theta, y0[c] + q0 th + q1 th^2 + q2 th^3 +
    q3 th^4 (its coefficients formed once); safeguarded Newton on it (bracket
    [lo, 1] with f(lo) = f0, f(1) = f1, f0 * f1 <= 0; bisection when a Newton
    step leaves the bracket); stops when the step is below 1e-15 of the
    interval or the residual below 1e-14.
    """
    a, fa = lo, f0
    b = 1.0
    if fa == 0.0:
        return lo
    if f1 == 0.0:
        return 1.0
    q0 = 0.0
    q1 = 0.0
    q2 = 0.0
    q3 = 0.0
    for k in range(7):
        kc = h * K[k, c]
        q0 += kc * P[k, 0]
        q1 += kc * P[k, 1]
        q2 += kc * P[k, 2]
        q3 += kc * P[k, 3]
    y0c = y0[c] - target
    x = lo + (1.0 - lo) * f0 / (f0 - f1)  # secant first guess
    for _ in range(60):
        fx = y0c + x * (q0 + x * (q1 + x * (q2 + x * q3)))
        dfx = q0 + x * (2.0 * q1 + x * (3.0 * q2 + x * 4.0 * q3))
        if abs(fx) < 1e-14:
            return x
        if (fx > 0.0) == (fa > 0.0):
            a, fa = x, fx
        else:
            b = x
        xn = x - fx / dfx if dfx != 0.0 else 0.5 * (a + b)
        if not (a < xn < b):
            xn = 0.5 * (a + b)
        if abs(xn - x) < 1e-15:
            return xn
        x = xn
    return x


#: first step [s]: of 0.05, 0.1 and 0.2 s, 0.1 s needs the fewest evaluations on mixed shots
#: (rejections included; benchmarks/_shots.py), 4 % fewer than 0.05 s
_H0 = 0.1
#: the step that reaches the ground is aimed to end this factor beyond the predicted contact
_AIM = 1.03


@nb.njit(cache=True, error_model="numpy", fastmath=_FASTMATH, inline="always")
def _aim_at_ground(y, f, r, h):
    """Step size: ``h``, or shortened so that the step ends just past the predicted ground contact.

    The contact is then located near the step's end, where the interpolant
    (4th order, as accurate as the error *estimate*, ~ tol x |y|) meets the
    5th-order solution, instead of mid-step: at the same tolerance this halves
    the mean landing error and removes the worst cases (short flights whose
    last step is long), at no cost in steps (docs/flight.md).  The prediction
    solves z + v_z tau + a_z tau^2 / 2 = r with the current acceleration.
    """
    zz = y[2] - r
    vz = y[5]
    az = f[5]
    tau = -1.0
    if az < 0.0:
        disc = vz * vz - 2.0 * az * zz
        if disc >= 0.0:
            tau = (-vz - math.sqrt(disc)) / az
    elif vz < 0.0:
        tau = -zz / vz
    if tau > 0.0 and _AIM * tau < h:
        return _AIM * tau
    return h


@nb.njit(cache=True, error_model="numpy", fastmath=_FASTMATH)
def integrate_one(y_init, aero, aero_p, consts, row, work):
    """Integrate one trajectory from ``y_init`` (9,) and fill the event ``row`` (NCOLS,).

    ``aero`` is the aero kernel as a first-class function or its inline tag
    (see the batch kernels below); ``work`` is a (12, 9) scratch array (reused
    across trajectories of a chunk).
    """
    k = consts[K_K]
    g = consts[K_G]
    r = consts[K_R]
    wx = consts[K_WX]
    wy = consts[K_WY]
    wz = consts[K_WZ]
    decay = consts[K_DECAY]
    t_max = consts[K_TMAX]
    rtol = consts[K_RTOL]
    atol = consts[K_ATOL]
    P = _P
    for i in range(NCOLS):
        row[i] = np.nan
    row[_c_net_status] = NET_NONE
    K = work[0:7]
    y = work[7]
    ytmp = work[8]
    ynew = work[9]
    yev = work[10]
    fcur = work[11]
    for c in range(9):
        y[c] = y_init[c]
    ok = True
    for i in range(9):
        if not math.isfinite(y[i]):
            ok = False
    if not ok or y[2] < r:
        row[_c_status] = STATUS_BAD_START
        row[_c_n_steps] = 0
        return
    derivative(y, fcur, aero, aero_p, k, g, r, wx, wy, wz, decay)
    side = -1.0 if y[0] < 0.0 else (1.0 if y[0] > 0.0 else -math.copysign(1.0, y[3]))
    net_done = False
    apex_done = False
    if y[5] <= 0.0:
        apex_done = True
        row[_iAPEX_T] = 0.0
        row[_c_apex_x] = y[0]
        row[_c_apex_y] = y[1]
        row[_c_apex_z] = y[2]
    t = 0.0
    h = _H0
    nsteps = 0
    landed = False
    while t < t_max and nsteps < 100000:
        h = _aim_at_ground(y, fcur, r, h)
        if t + h > t_max:
            h = t_max - t
        for c in range(9):
            K[0, c] = fcur[c]
        # stages, unrolled (Dormand-Prince tableau constants below)
        for c in range(9):
            ytmp[c] = y[c] + h * (_A21 * K[0, c])
        derivative(ytmp, K[1], aero, aero_p, k, g, r, wx, wy, wz, decay)
        for c in range(9):
            ytmp[c] = y[c] + h * (_A31 * K[0, c] + _A32 * K[1, c])
        derivative(ytmp, K[2], aero, aero_p, k, g, r, wx, wy, wz, decay)
        for c in range(9):
            ytmp[c] = y[c] + h * (_A41 * K[0, c] + _A42 * K[1, c] + _A43 * K[2, c])
        derivative(ytmp, K[3], aero, aero_p, k, g, r, wx, wy, wz, decay)
        for c in range(9):
            ytmp[c] = y[c] + h * (_A51 * K[0, c] + _A52 * K[1, c] + _A53 * K[2, c] + _A54 * K[3, c])
        derivative(ytmp, K[4], aero, aero_p, k, g, r, wx, wy, wz, decay)
        for c in range(9):
            ytmp[c] = y[c] + h * (_A61 * K[0, c] + _A62 * K[1, c] + _A63 * K[2, c] + _A64 * K[3, c] + _A65 * K[4, c])
        derivative(ytmp, K[5], aero, aero_p, k, g, r, wx, wy, wz, decay)
        for c in range(9):
            ynew[c] = y[c] + h * (_B1 * K[0, c] + _B3 * K[2, c] + _B4 * K[3, c] + _B5 * K[4, c] + _B6 * K[5, c])
        derivative(ynew, K[6], aero, aero_p, k, g, r, wx, wy, wz, decay)
        errsum = 0.0
        for c in range(9):
            acc = _E1 * K[0, c] + _E3 * K[2, c] + _E4 * K[3, c] + _E5 * K[4, c] + _E6 * K[5, c] + _E7 * K[6, c]
            sc = atol + rtol * max(abs(y[c]), abs(ynew[c]))
            e = h * acc / sc
            errsum += e * e
        err = math.sqrt(errsum / 9.0)
        if not math.isfinite(err):
            h *= 0.2
            continue
        if err > 1.0:
            h *= max(0.2, 0.9 * err**-0.2)
            continue
        nsteps += 1
        # ---- events within [t, t + h]
        th_land = 2.0
        if ynew[2] - r <= 0.0:
            if y[2] - r > 0.0:
                th_land = _root(2, r, y, K, h, P, y[2] - r, ynew[2] - r)
            elif nsteps == 1 and y[5] > 0.0 and ynew[5] <= 0.0:
                # started on the ground (z = r) going up and hopped within the first
                # step: the contact is the root after the hop's apex
                ta = _root(5, 0.0, y, K, h, P, y[5], ynew[5])
                th_land = _root(2, r, y, K, h, P, _dense_comp(ta, 2, y, K, h, P) - r, ynew[2] - r, ta)
            elif nsteps == 1:
                th_land = 0.0  # started on the ground, not going up
        if not net_done and side * y[0] > 0.0 and side * ynew[0] <= 0.0:
            th = _root(0, 0.0, y, K, h, P, y[0], ynew[0])
            if th <= th_land:
                net_done = True
                ny = _dense_comp(th, 1, y, K, h, P)
                nz = _dense_comp(th, 2, y, K, h, P)
                hn = net_height_linear(ny, consts[K_HC], consts[K_HP], consts[K_YP])
                row[_iNET_T] = t + th * h
                row[_c_net_y] = ny
                row[_c_net_z] = nz
                row[_c_net_h] = hn
                row[_c_net_status] = NET_HIT if nz - hn - r < 0.0 else NET_OVER
        if not apex_done and y[5] > 0.0 and ynew[5] <= 0.0:
            th = _root(5, 0.0, y, K, h, P, y[5], ynew[5])
            if th <= th_land:
                apex_done = True
                row[_iAPEX_T] = t + th * h
                row[_c_apex_x] = _dense_comp(th, 0, y, K, h, P)
                row[_c_apex_y] = _dense_comp(th, 1, y, K, h, P)
                row[_c_apex_z] = _dense_comp(th, 2, y, K, h, P)
        if th_land <= 1.0:
            _dense_full(th_land, y, K, h, P, yev)
            row[_iLAND_T] = t + th_land * h
            for c in range(9):
                row[_iLAND_T + 1 + c] = yev[c]
            landed = True
            break
        t += h
        for c in range(9):
            y[c] = ynew[c]
            fcur[c] = K[6, c]
        fac = 10.0 if err == 0.0 else min(10.0, max(0.2, 0.9 * err**-0.2))
        h *= fac
    row[_c_n_steps] = nsteps
    row[_c_status] = STATUS_OK if landed else STATUS_NO_LANDING


# ---------------------------------------------------------------- batch kernels
# ``aero`` is either the model's inline tag (tennislab's own models: Numba
# compiles one specialised, cached kernel per model with the C_D/C_L formula
# inlined, ~1.3x faster for Stepanek's formula) or a first-class function
# (any other kernel: one compiled kernel serves them all; see
# :func:`tennislab.core.aero.aero_coefficients`).
@nb.njit(cache=True, error_model="numpy", fastmath=_FASTMATH, parallel=True)
def batch_kernel(states, aero, aero_p, consts, out):
    """Integrate every row of ``states`` (N, 9) and fill the event table ``out`` (N, NCOLS)."""
    n = states.shape[0]
    nchunks = (n + 255) // 256
    for ci in nb.prange(nchunks):
        work = np.empty((12, 9))
        for i in range(ci * n // nchunks, (ci + 1) * n // nchunks):
            integrate_one(states[i], aero, aero_p, consts, out[i], work)


@nb.njit(cache=True, error_model="numpy", fastmath=_FASTMATH)
def serial_kernel(states, aero, aero_p, consts, out):
    """As :func:`batch_kernel`, on one thread (for callers that parallelise themselves)."""
    work = np.empty((12, 9))
    for i in range(states.shape[0]):
        integrate_one(states[i], aero, aero_p, consts, out[i], work)


_F = types.float64
BATCH_SIGNATURE = types.void(_F[:, ::1], AERO_FUNCTION_TYPE, _F[::1], _F[::1], _F[:, ::1])


@nb.njit(BATCH_SIGNATURE, cache=True, error_model="numpy", fastmath=_FASTMATH)
def batch_kernel_fp(states, aero, aero_p, consts, out):
    """:func:`batch_kernel` for an aero kernel passed as a first-class function."""
    batch_kernel(states, aero, aero_p, consts, out)


@nb.njit(BATCH_SIGNATURE, cache=True, error_model="numpy", fastmath=_FASTMATH)
def serial_kernel_fp(states, aero, aero_p, consts, out):
    """:func:`serial_kernel` for an aero kernel passed as a first-class function."""
    serial_kernel(states, aero, aero_p, consts, out)


@nb.njit(cache=True)
def rk4_step(y, h, aero, ap, k, g, r, wx, wy, wz, dec, work, out):
    """One classical Runge-Kutta 4 step of size ``h`` [s] (negative: backward) from ``y`` into ``out``.

    For fixed-step integrations whose results must vary smoothly with their
    inputs (the line-calling track fit, :mod:`tennislab.linecall.model`).
    Arguments after ``h`` are those of :func:`tennislab.core.dynamics.derivative`;
    ``work`` is a (5, 9) scratch array.
    """
    k1 = work[0]
    k2 = work[1]
    k3 = work[2]
    k4 = work[3]
    yt = work[4]
    derivative(y, k1, aero, ap, k, g, r, wx, wy, wz, dec)
    for i in range(9):
        yt[i] = y[i] + 0.5 * h * k1[i]
    derivative(yt, k2, aero, ap, k, g, r, wx, wy, wz, dec)
    for i in range(9):
        yt[i] = y[i] + 0.5 * h * k2[i]
    derivative(yt, k3, aero, ap, k, g, r, wx, wy, wz, dec)
    for i in range(9):
        yt[i] = y[i] + h * k3[i]
    derivative(yt, k4, aero, ap, k, g, r, wx, wy, wz, dec)
    for i in range(9):
        out[i] = y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
