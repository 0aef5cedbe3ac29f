"""The compiled track models: ball-centre positions at given times.

**Bounce model** (the line-calling fit). Parameter vector (:data:`NPARAM` = 19), all SI, addressed by
the named indices and slices below (``P_XB`` ... ``P_LIFT``):

    0-2   x_b, y_b, t_b      first-contact point (ball centre at z = r) and time     P_XB, P_YB, P_TB
    3-5   v_in               velocity at contact                                      P_VIN
    6-8   w_in               spin at contact                                          P_WIN
    9-11  v_out              velocity leaving the ground (time t_b + T_c)             P_VOUT
    12    drag scale s_D     multiplies C_D (1 = the aero model as given)             P_DRAG
    13-14 contact offset     added to the modelled travel of the centre during the contact   P_DXY
    15-17 spin-out offset    added to the outgoing spin implied by the impulse        P_DWOUT
    18    lift scale s_L     multiplies C_L (1 = the aero model as given)             P_LIFT
    19    post drag ratio    the drag scale after the bounce is s_D times this        P_DRAG_POST

The flight after the bounce gets a drag scale of its own (s_D x ratio): the ball leaves the ground
with a spin and speed the aero model may describe less well than the approach's (a C_D(S) of the
wrong shape), and a shared scale would let the post-bounce points bend the approach.

Before the bounce the flight is integrated *backward* from (x_b, y_b, r, v_in,
w_in) at t_b, after it forward from (x_b + d, y_b + d', r, v_out, w_out) at
t_b + T_c, where w_out follows from v_in, w_in and v_out by the impulse relation
of the bounce model and (d, d') is the centre's travel during the contact
(:func:`contact_displacement`).
Parametrising by the bounce itself makes its covariance a block of the fit's.

**Free-flight model** (the net check): :data:`NFREE` = 11 parameters, position (3), velocity (3) and
spin (3) at a reference time t0, then the drag and lift scales (``F_POS``, ``F_VEL``, ``F_SPIN``,
``F_DRAG``, ``F_LIFT``); integrated backward and forward from t0.

Equations of motion and integration: core's, nothing of this module's own.  The right-hand side
is :func:`tennislab.core.dynamics.derivative` (seed 000 eqs 1-2, seed 002 eqs 1, 3) with the drag
and lift coefficients of the aero model multiplied by separate scales, C_D -> s_D C_D and
C_L -> s_L C_L (the fit's handles on an aero model that is not exactly the ball's); the
integration is :func:`tennislab.core.integrators.sweep_positions` (classical RK4 with a fixed
step, 16 ms in the fit, so that the residuals are smooth functions of the parameters; cubic
Hermite positions between steps; tests/linecall/test_linecall.py checks against
:func:`tennislab.core.flight.fly_dense`).

References
----------
.. [1] Grosen, Kousted & Treichel (2021), 2-dimensional tennis serves show similar successful mechanical
    parameter across physiological differences, Aalborg University (seed 000), eqs 1-2 (drag, lift)
.. [2] Wojcicki, Pucilowski & Kulesza (2010), Acta Mechanica et Automatica (seed 002), eqs 1, 3
.. [3] Hairer, Norsett & Wanner (1993), Solving Ordinary Differential Equations I, 2nd ed., sec. II.1 (RK4)
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from tennislab.core.aero import inline_tag
from tennislab.core.integrators import sweep_positions
from tennislab.core.mark import contact_displacement

NPARAM = 20
P_XB, P_YB, P_TB = 0, 1, 2
P_XY = slice(0, 2)
P_VIN = slice(3, 6)
P_WIN = slice(6, 9)
P_VOUT = slice(9, 12)
P_DRAG = 12
P_DXY = slice(13, 15)
P_DWOUT = slice(15, 18)
P_LIFT = 18
P_DRAG_POST = 19


def indices(sl: slice) -> list[int]:
    """The parameter indices of a named slice (``indices(P_WIN) == [6, 7, 8]``)."""
    return list(range(sl.start, sl.stop))


#: parameters that move the pre-bounce segment (the rest act after the bounce only)
PRE_DEPENDENT = (P_XB, P_YB, P_TB, *indices(P_VIN), *indices(P_WIN), P_DRAG, P_LIFT)

NFREE = 11
F_POS = slice(0, 3)
F_VEL = slice(3, 6)
F_SPIN = slice(6, 9)
F_DRAG = 9
F_LIFT = 10
F_STATE = slice(0, 9)

# consts layout
C_K, C_G, C_R, C_WX, C_WY, C_WZ, C_DECAY, C_ALPHA, C_E, C_MU, C_EX, C_TC, C_H = range(13)
NCONST = 13

SEG_PRE, SEG_POST, SEG_OFF = 0, 1, -1


def kernel_arg(params):
    """The aero model of ``params`` as the compiled functions below take it: its inline tag for
    tennislab's own models (a caller specialised on the model, formula inlined, cheap to pass
    from Python), else the kernel as a first-class function
    (:func:`tennislab.core.aero.inline_tag`)."""
    tag = inline_tag(params.aero.kernel)
    return params.aero.kernel if tag is None else tag


@nb.njit(cache=True)
def _sweep(y0, t0, t, idx, n, direction, aero, ap, consts, dscale, lscale, out):
    """:func:`tennislab.core.integrators.sweep_positions` with the model's constants, the step
    ``consts[C_H]`` in ``direction`` (+1/-1) and the drag and lift scales applied to k."""
    k = consts[C_K]
    sweep_positions(
        y0,
        t0,
        t,
        idx,
        n,
        consts[C_H] * direction,
        aero,
        ap,
        k * dscale,
        k * lscale,
        consts[C_G],
        consts[C_R],
        consts[C_WX],
        consts[C_WY],
        consts[C_WZ],
        consts[C_DECAY],
        out,
    )


@nb.njit(cache=True)
def post_start(p, consts, y0):
    """State leaving the ground (9,) and its time, from the parameters.

    The outgoing spin follows from the fitted velocities by the rigid-ball impulse relation
    of :mod:`tennislab.core.bounce` (dw = (P_y, -P_x, 0)/(alpha r), P = v_t,out - v_t,in),
    whatever the friction law; the travel during the contact uses the data's
    P_n = v_z,out - v_z,in, and the surface's mu only to time a grip (when the fitted
    velocities say the ball slid throughout, the mu they imply, |P|/P_n).
    """
    r = consts[C_R]
    alpha = consts[C_ALPHA]
    px = p[9] - p[3]
    py = p[10] - p[4]
    vz_in = p[5]
    e_data = p[11] / -vz_in if vz_in < 0.0 else consts[C_E]
    # did the ball slide throughout?  Then the friction acted over the whole contact whatever
    # the surface's mu: use the mu the data imply, |P| / P_n.
    uix = p[3] - r * p[7]
    uiy = p[4] + r * p[6]
    k = 1.0 + 1.0 / alpha
    uox = uix + k * px
    uoy = uiy + k * py
    mu = consts[C_MU]
    pn = (1.0 + e_data) * abs(vz_in)
    if uox * uix + uoy * uiy > 0.05 * (uix * uix + uiy * uiy) and pn > 0.0:
        mu = math.sqrt(px * px + py * py) / pn
    d = np.empty(2)
    contact_displacement(p[3], p[4], p[9], p[10], vz_in, mu, e_data, consts[C_TC], d)
    y0[0] = p[0] + d[0] + p[13]
    y0[1] = p[1] + d[1] + p[14]
    y0[2] = r
    for i in range(3):
        y0[3 + i] = p[9 + i]
    y0[6] = p[6] + py / (alpha * r) + p[15]
    y0[7] = p[7] - px / (alpha * r) + p[16]
    y0[8] = p[8] + p[17]
    return p[2] + consts[C_TC]


@nb.njit(cache=True)
def model_positions(p, t, seg, aero, ap, consts, out, do_pre, do_post):
    """Positions (N, 3) at times t for segment labels seg (0 pre, 1 post, -1 none)."""
    n = t.shape[0]
    npre = 0
    npost = 0
    for i in range(n):
        if seg[i] == SEG_PRE:
            npre += 1
        elif seg[i] == SEG_POST:
            npost += 1
    y0 = np.empty(9)
    if do_pre and npre > 0:
        idx = np.empty(npre, dtype=np.int64)
        j = 0
        for i in range(n - 1, -1, -1):
            if seg[i] == SEG_PRE:
                idx[j] = i
                j += 1
        y0[0] = p[0]
        y0[1] = p[1]
        y0[2] = consts[C_R]
        for i in range(6):
            y0[3 + i] = p[3 + i]
        _sweep(y0, p[2], t, idx, npre, -1.0, aero, ap, consts, p[P_DRAG], p[P_LIFT], out)
    if do_post and npost > 0:
        idx = np.empty(npost, dtype=np.int64)
        j = 0
        for i in range(n):
            if seg[i] == SEG_POST:
                idx[j] = i
                j += 1
        t0 = post_start(p, consts, y0)
        _sweep(y0, t0, t, idx, npost, 1.0, aero, ap, consts, p[P_DRAG] * p[P_DRAG_POST], p[P_LIFT], out)


@nb.njit(cache=True)
def residuals(p, t, xyz, w, seg, aero, ap, consts, res, pos):
    """Weighted residuals (3N,) = w (model - data); zero for seg == -1."""
    model_positions(p, t, seg, aero, ap, consts, pos, True, True)
    n = t.shape[0]
    for i in range(n):
        for c in range(3):
            if seg[i] == SEG_OFF:
                res[3 * i + c] = 0.0
            else:
                res[3 * i + c] = w[i] * (pos[i, c] - xyz[i, c])


@nb.njit(cache=True)
def jacobian(p, free, steps, t, xyz, w, seg, aero, ap, consts, base, jac):
    """Forward-difference Jacobian (3N, len(free)) of :func:`residuals` around ``base``."""
    n = t.shape[0]
    pos = np.empty((n, 3))
    res = np.empty(3 * n)
    for jj in range(free.shape[0]):
        j = free[jj]
        q = p.copy()
        q[j] += steps[j]
        pre_dep = j < 9 or j == P_DRAG or j == P_LIFT  # PRE_DEPENDENT (a tuple test is not compiled)
        if not pre_dep:
            # v_out and the contact offsets do not move the pre-bounce segment: reuse the base residuals
            model_positions(q, t, seg, aero, ap, consts, pos, False, True)
        else:
            model_positions(q, t, seg, aero, ap, consts, pos, True, True)
        for i in range(n):
            for c in range(3):
                if seg[i] == SEG_OFF:
                    res[3 * i + c] = 0.0
                elif seg[i] == SEG_PRE and not pre_dep:
                    res[3 * i + c] = base[3 * i + c]
                else:
                    res[3 * i + c] = w[i] * (pos[i, c] - xyz[i, c])
        for m in range(3 * n):
            jac[m, jj] = (res[m] - base[m]) / steps[j]


@nb.njit(cache=True)
def free_positions(q, t0, t, aero, ap, consts, out):
    """Free-flight positions (N, 3) at sorted times t from the state q[0:9] at t0 and scales q[9:11]."""
    n = t.shape[0]
    nb_ = 0
    for i in range(n):
        if t[i] < t0:
            nb_ += 1
    y0 = q[0:9].copy()
    if nb_ > 0:
        idx = np.empty(nb_, dtype=np.int64)
        for j in range(nb_):
            idx[j] = nb_ - 1 - j
        _sweep(y0, t0, t, idx, nb_, -1.0, aero, ap, consts, q[F_DRAG], q[F_LIFT], out)
    if n - nb_ > 0:
        idx = np.empty(n - nb_, dtype=np.int64)
        for j in range(n - nb_):
            idx[j] = nb_ + j
        _sweep(y0, t0, t, idx, n - nb_, 1.0, aero, ap, consts, q[F_DRAG], q[F_LIFT], out)


@nb.njit(cache=True)
def free_residuals(q, t0, t, xyz, w, aero, ap, consts, res, pos):
    """Weighted residuals (3N,) of the free-flight model."""
    free_positions(q, t0, t, aero, ap, consts, pos)
    for i in range(t.shape[0]):
        for c in range(3):
            res[3 * i + c] = w[i] * (pos[i, c] - xyz[i, c])


@nb.njit(cache=True)
def free_jacobian(q, free, steps, t0, t, xyz, w, aero, ap, consts, base, jac):
    """Forward-difference Jacobian (3N, len(free)) of :func:`free_residuals` around ``base``."""
    n = t.shape[0]
    pos = np.empty((n, 3))
    res = np.empty(3 * n)
    for jj in range(free.shape[0]):
        j = free[jj]
        qq = q.copy()
        qq[j] += steps[j]
        free_residuals(qq, t0, t, xyz, w, aero, ap, consts, res, pos)
        for m in range(3 * n):
            jac[m, jj] = (res[m] - base[m]) / steps[j]


def make_consts(params, surface, contact_time: float, step: float = 2e-3) -> np.ndarray:
    """The constant vector of the model from :class:`FlightParams`, a surface and the contact time."""
    w = params.atmosphere.wind
    return np.array(
        [
            params.k,
            params.atmosphere.gravity,
            params.ball.radius,
            w[0],
            w[1],
            w[2],
            params.spin_decay,
            params.ball.inertia_factor,
            surface.e,
            surface.mu,
            surface.e_x,
            contact_time,
            step,
        ],
        dtype=np.float64,
    )


def default_params() -> np.ndarray:
    """A parameter vector (NPARAM,) of zeros with the aero scales and the post-bounce drag ratio at 1."""
    p = np.zeros(NPARAM)
    p[P_DRAG] = 1.0
    p[P_LIFT] = 1.0
    p[P_DRAG_POST] = 1.0
    return p


def positions(p, t, seg, params, surface, contact_time: float, step: float = 2e-3) -> np.ndarray:
    """Python wrapper: model positions (N, 3) for parameters p (NPARAM,) at times t with labels seg."""
    t = np.ascontiguousarray(t, dtype=np.float64)
    p = np.ascontiguousarray(p, dtype=np.float64)
    if p.shape != (NPARAM,):
        raise ValueError(f"positions: p must have {NPARAM} entries, got shape {p.shape}")
    out = np.full((t.size, 3), np.nan)
    model_positions(
        p,
        t,
        np.ascontiguousarray(seg, dtype=np.int64),
        kernel_arg(params),
        params.aero.params,
        make_consts(params, surface, contact_time, step),
        out,
        True,
        True,
    )
    return out


@nb.njit(cache=True)
def normal_equations(jac, res, wpt, A, g):
    """A = sum_i w_i J_i^T J_i and g = sum_i w_i J_i^T r_i over points i (rows 3i..3i+2).

    Written out (no BLAS) so that a call does not wake a multi-threaded BLAS.
    """
    npar = jac.shape[1]
    for a in range(npar):
        g[a] = 0.0
        for b in range(npar):
            A[a, b] = 0.0
    for m in range(jac.shape[0]):
        w = wpt[m // 3]
        if w == 0.0:
            continue
        rm = res[m]
        for a in range(npar):
            ja = w * jac[m, a]
            if ja == 0.0:
                continue
            g[a] += ja * rm
            for b in range(a, npar):
                A[a, b] += ja * jac[m, b]
    for a in range(npar):
        for b in range(a):
            A[a, b] = A[b, a]
