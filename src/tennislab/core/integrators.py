"""Compiled batch integrator: Dormand-Prince 5(4) with dense output and events.

One trajectory per initial state, integrated in parallel (``numba.prange``)
with the adaptive Dormand & Prince (1980) 5(4) pair (J. Comput. Appl. Math.
6:19), its free 4th-order continuous extension (Shampine 1986, Math. Comp.
46:135; the coefficients SciPy's RK45 uses) for locating events, and the
standard step-size controller (Hairer, Norsett & Wanner, Solving ODEs I,
section II.4).  Events are found by safeguarded Newton iteration on the
interpolant, to ~1e-14 in the step fraction, never at a step end.  The right-hand side is
:func:`tennislab.core.dynamics.derivative`, the same one the SciPy path uses.

References
----------
.. [1] Dormand & Prince (1980), J. Comput. Appl. Math. 6:19
.. [2] Shampine (1986), Math. Comp. 46:135
.. [3] Hairer, Norsett & Wanner (1993), Solving Ordinary Differential Equations I, 2nd ed., sec. II.1 and II.4
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba as nb
import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from tennislab.core._jit import JIT
from tennislab.core._net import net_blocks, net_height_linear
from tennislab.core.aero import _CAP_BLEND, AERO_FUNCTION_TYPE, CAP_ZONE, CAP_ZONE_ERR, cap_distance
from tennislab.core.dynamics import derivative
from tennislab.core.events import (
    ALWAYS,
    COL,
    EV_AIM,
    EV_COL0,
    EV_COMPONENT,
    EV_DIRECTION,
    EV_MARGIN,
    EV_RADII,
    EV_STATUS,
    EV_STOP,
    EV_TARGET,
    EV_TCOL,
    IF_NET,
    MAX_EVENTS,
    NCOLS,
    NET_HIT,
    NET_NONE,
    NET_OVER,
    STATUS_BAD_START,
    STATUS_FAILED,
    STATUS_NET,
    STATUS_NO_LANDING,
    STATUS_OUT_OF_RANGE,
    TOWARD,
)


class KernelConsts(NamedTuple):
    """The constants of the compiled flight kernel, by name (built by
    :meth:`tennislab.core.flight.FlightParams.consts`; all float64, SI)."""

    k: float  #: 1/2 rho A / m [1/m]
    gravity: float  #: [m/s^2]
    radius: float  #: ball radius [m]
    wind_x: float  #: wind velocity [m/s]
    wind_y: float
    wind_z: float
    spin_decay: float  #: [1/s]
    net_center_height: float  #: [m]
    net_post_height: float  #: [m]
    net_y_post: float  #: lateral position of the posts [m]
    t_max: float  #: longest flight [s]
    rtol: float  #: relative tolerance of the step control
    atol: float  #: absolute tolerance of the step control
    max_speed: float  #: launch speeds above this are refused (status STATUS_OUT_OF_RANGE) [m/s]
    max_spin: float  #: launch spins above this are refused (status STATUS_OUT_OF_RANGE) [rad/s]
    max_position: float  #: launches with |x|, |y| or z above this are refused (STATUS_OUT_OF_RANGE) [m]
    max_steps: float  #: most step attempts (accepted and rejected) per flight (then STATUS_FAILED)


NCONSTS = len(KernelConsts._fields)
#: Numba type of :class:`KernelConsts`
CONSTS_TYPE = types.NamedUniTuple(types.float64, NCONSTS, KernelConsts)

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

_c_net_t = COL["net_t"]
_c_net_y = COL["net_y"]
_c_net_z = COL["net_z"]
_c_net_h = COL["net_h"]
_c_net_status = COL["net_status"]
_c_hit_t = COL["net_hit_t"]
_c_hit_y = COL["net_hit_y"]
_c_hit_z = COL["net_hit_z"]
_c_n_steps = COL["n_steps"]
_c_status = COL["status"]


@nb.njit(**JIT, inline="always")
def _weight(theta, P, k):
    """Stage ``k``'s weight in the interpolant at step fraction ``theta`` (the same for every component)."""
    return theta * (P[k, 0] + theta * (P[k, 1] + theta * (P[k, 2] + theta * P[k, 3])))


@nb.njit(**JIT, inline="always")
def _dense_weights(theta, P):
    """The seven stage weights of the interpolant at ``theta``: formed once for every component an
    event records (:func:`_record`)."""
    return (
        _weight(theta, P, 0),
        _weight(theta, P, 1),
        _weight(theta, P, 2),
        _weight(theta, P, 3),
        _weight(theta, P, 4),
        _weight(theta, P, 5),
        _weight(theta, P, 6),
    )


@nb.njit(**JIT, inline="always")
def _dense_at(q, c, y0, K, h):
    """Component ``c`` of the interpolant with the stage weights ``q`` (:func:`_dense_weights`)."""
    s = 0.0
    for k in range(7):
        s += K[k, c] * q[k]
    return y0[c] + h * s


@nb.njit(**JIT, inline="always")
def _dense_comp(theta, c, y0, K, h, P):
    """Component ``c`` of the interpolant at step fraction ``theta``."""
    return _dense_at(_dense_weights(theta, P), c, y0, K, h)


@nb.njit(**JIT)
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


#: the rows of an event work array ``evw`` (6, MAX_EVENTS), one column per event: its target value,
#: direction, done flag, step fraction of its crossing, armed flag (on its target at the start, moving
#: away) and the step it crossed in.  The kernels index it in place: a view of a row costs two atomic
#: reference counts, paid per event and step.
W_TARGET, W_DIRECTION, W_DONE, W_THETA, W_ARMED, W_WHEN = range(6)
#: a start this close to an event's target [m] is *on* it: a ball launched 1e-17 m above the ground
#: and rising would otherwise find its "landing" in the round-off of the interpolant at t = 0
_ON_TARGET = 1e-12
#: first step [s]: of 0.05, 0.1 and 0.2 s, 0.1 s needs the fewest evaluations on mixed shots
#: (rejections included; benchmarks/_shots.py), 4 % fewer than 0.05 s
_H0 = 0.1
#: the step that reaches the ground is aimed to end this factor beyond the predicted contact
_AIM = 1.03


@nb.njit(**JIT, inline="always")
def _aim_at(y, f, c, target, h):
    """Step size: ``h``, or shortened so that the step ends just past the predicted crossing.

    For the event that ends most flights (the ground): the contact is then
    located near the step's end, where the interpolant (4th order, as accurate
    as the error *estimate*, ~ tol x |y|) meets the 5th-order solution, instead
    of mid-step: at the same tolerance this halves the mean landing error and
    removes the worst cases (short flights whose last step is long), at no cost
    in steps (docs/flight.md).  The prediction solves
    q + v tau + a tau^2 / 2 = target for the falling position component q = y[c]
    with the current velocity v = f[c] and acceleration a = f[c + 3].
    """
    return aim_step(y[c] - target, f[c], f[c + 3], h)


@nb.njit(**JIT, inline="always")
def aim_step(zz, vz, az, h):
    """:func:`_aim_at` from the distance ``zz`` to the target, the velocity ``vz`` and the
    acceleration ``az`` of the component."""
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


@nb.njit(**JIT)
def _root_after_start(c, target, d, y0, K, h, P, f1):
    """theta of the crossing (direction ``d``) of a component that starts *on* its target moving
    away from it and comes back within the step (a low hop from the ground): the root after the
    interpolant's excursion, found by sampling for a point on the near side of the target and
    root-finding from there; 0 if no such point (the excursion is below the sampling)."""
    best = 0.0
    th_best = 0.0
    for i in range(1, 16):
        th = i / 16.0
        v = -d * (_dense_comp(th, c, y0, K, h, P) - target)
        if v > best:
            best = v
            th_best = th
    if best <= 0.0:
        return 0.0
    return _root(c, target, y0, K, h, P, _dense_comp(th_best, c, y0, K, h, P) - target, f1, th_best)


@nb.njit(**JIT, inline="always")
def _stops_at(ev, e, y_, z_, c):
    """Whether event ``e`` ends the flight when it happens with the ball centre at lateral
    position ``y_`` and height ``z_`` (only ``IF_NET`` events look at them)."""
    stop = ev[e, EV_STOP]
    if stop == ALWAYS:
        return True
    if stop == IF_NET:
        zz = z_ - ev[e, EV_MARGIN] * c.radius
        return net_blocks(y_, zz, c.net_center_height, c.net_post_height, c.net_y_post)
    return False


@nb.njit(**JIT)
def _record(ev, e, t, theta, y0, K, h, P, row):
    """Write event ``e``'s time and recorded components at step fraction ``theta`` into ``row``."""
    row[int(ev[e, EV_TCOL])] = t + theta * h
    q = _dense_weights(theta, P)
    for i in range(9):
        col = int(ev[e, EV_COL0 + i])
        if col >= 0:
            row[col] = _dense_at(q, i, y0, K, h)


@nb.njit(**JIT)
def _finish_row(row, c, status, nsteps):
    """Status, step count and the derived net columns (height, result; a net contact's place)."""
    if status == STATUS_NET:
        row[_c_net_t] = row[_c_hit_t]
        row[_c_net_y] = row[_c_hit_y]
        row[_c_net_z] = row[_c_hit_z]
    if math.isnan(row[_c_net_t]):
        row[_c_net_status] = NET_NONE
    else:
        hn = net_height_linear(row[_c_net_y], c.net_center_height, c.net_post_height, c.net_y_post)
        row[_c_net_h] = hn
        row[_c_net_status] = NET_HIT if row[_c_net_z] - hn - c.radius < 0.0 else NET_OVER
    row[_c_n_steps] = nsteps
    row[_c_status] = status


@nb.njit(**JIT)
def _aim_event(ev):
    """Index of the first event that steps are aimed at (``EV_AIM``), or -1."""
    for e in range(ev.shape[0]):
        if ev[e, EV_AIM] != 0.0:
            return e
    return -1


@nb.njit(**JIT)
def start_flight(y, fcur, aero, aero_p, c, ev, row, evw):
    """Check the launch ``y`` (9,), fill ``fcur`` with its slope and set up the events of ``evw``;
    ``True`` if the flight is to be integrated, ``False`` if it ends at the start (``row`` finished:
    a bad or out-of-range start, or a ball on the ground not going up).  Shared by the per-shot and
    the lockstep kernel."""
    r = c.radius
    for i in range(NCOLS):
        row[i] = np.nan
    for i in range(9):
        if not math.isfinite(y[i]):
            _finish_row(row, c, STATUS_BAD_START, 0)
            return False
    speed = math.sqrt(y[3] * y[3] + y[4] * y[4] + y[5] * y[5])
    spin = math.sqrt(y[6] * y[6] + y[7] * y[7] + y[8] * y[8])
    lim = c.max_position
    if speed > c.max_speed or spin > c.max_spin or abs(y[0]) > lim or abs(y[1]) > lim or y[2] > lim:
        _finish_row(row, c, STATUS_OUT_OF_RANGE, 0)
        return False
    derivative(y, fcur, aero, aero_p, c.k, c.k, c.gravity, r, c.wind_x, c.wind_y, c.wind_z, c.spin_decay)
    side = -1.0 if y[0] < 0.0 else (1.0 if y[0] > 0.0 else -math.copysign(1.0, y[3]))
    # ---- the events at the start (events.py: past -> at the start; on the target moving away -> armed)
    stop_e = -1
    for e in range(ev.shape[0]):
        toward = ev[e, EV_DIRECTION] == TOWARD
        evw[W_DIRECTION, e] = -side if toward else ev[e, EV_DIRECTION]
        evw[W_TARGET, e] = ev[e, EV_TARGET] + ev[e, EV_RADII] * r * (side if toward else 1.0)
        evw[W_DONE, e] = 0.0
        evw[W_ARMED, e] = 0.0
        evw[W_WHEN, e] = -1.0
        ci = int(ev[e, EV_COMPONENT])
        f0 = y[ci] - evw[W_TARGET, e]
        if abs(f0) <= _ON_TARGET and evw[W_DIRECTION, e] * f0 <= 0.0 and evw[W_DIRECTION, e] * fcur[ci] < 0.0:
            evw[W_ARMED, e] = 1.0  # on its target (to round-off) and moving away: the crossing after the start
            continue
        if evw[W_DIRECTION, e] * f0 < 0.0:
            continue
        evw[W_DONE, e] = 1.0
        if _stops_at(ev, e, y[1], y[2], c):
            if evw[W_DIRECTION, e] * f0 > 0.0:  # beyond an event that ends the flight: below the ground, inside the net
                _finish_row(row, c, STATUS_BAD_START, 0)
                return False
            if stop_e < 0:
                stop_e = e
        elif ev[e, EV_STOP] != IF_NET:
            _record_state(ev, e, 0.0, y, row)
    if stop_e >= 0:
        _record_state(ev, stop_e, 0.0, y, row)
        _finish_row(row, c, int(ev[stop_e, EV_STATUS]), 0)
        return False
    return True


@nb.njit(**JIT)
def step_events(ev, c, evw, t, h, y, ynew, K, nsteps, row):
    """The events within the accepted step [t, t + h] from ``y`` to ``ynew`` (stages ``K`` (7, 9)):
    every crossing first, then the earliest that ends the flight; the crossings up to it recorded
    in ``row``.  Returns the event that ends the flight, or -1."""
    P = _P
    n_ev = ev.shape[0]
    th_stop = 2.0
    stop_e = -1
    ncross = 0
    for e in range(n_ev):
        if evw[W_DONE, e] != 0.0:
            continue
        ci = int(ev[e, EV_COMPONENT])
        d = evw[W_DIRECTION, e]
        f1 = ynew[ci] - evw[W_TARGET, e]
        if d * f1 < 0.0:
            continue
        f0 = y[ci] - evw[W_TARGET, e]
        if evw[W_ARMED, e] != 0.0:
            th = _root_after_start(ci, evw[W_TARGET, e], d, y, K, h, P, f1)
        elif d * f0 < 0.0:
            th = _root(ci, evw[W_TARGET, e], y, K, h, P, f0, f1)
        else:
            continue
        evw[W_THETA, e] = th
        evw[W_WHEN, e] = nsteps
        ncross += 1
        if ev[e, EV_STOP] == ALWAYS:
            stops = True
        elif ev[e, EV_STOP] == IF_NET:
            stops = _stops_at(ev, e, _dense_comp(th, 1, y, K, h, P), _dense_comp(th, 2, y, K, h, P), c)
        else:
            stops = False
        if stops and th < th_stop:
            th_stop = th
            stop_e = e
    if ncross > 0:
        for e in range(n_ev):
            if evw[W_WHEN, e] == nsteps and evw[W_DONE, e] == 0.0 and evw[W_THETA, e] <= th_stop:
                evw[W_DONE, e] = 1.0
                if ev[e, EV_STOP] != IF_NET or e == stop_e:
                    _record(ev, e, t, evw[W_THETA, e], y, K, h, P, row)
    return stop_e


@nb.njit(**JIT, inline="always")
def cap_gap(aero, ap, c, vx, vy, vz, wx, wy, wz):
    """c_l S - cap [-] at velocity/spin (v, w) in the wind of ``c``: where a capped lift's blend zone is
    (:func:`~tennislab.core.aero.cap_distance`; -inf for a model without a cap)."""
    return cap_gap_at_spin(aero, ap, c, vx, vy, vz, math.sqrt(wx * wx + wy * wy + wz * wz))


@nb.njit(**JIT, inline="always")
def cap_gap_at_spin(aero, ap, c, vx, vy, vz, w):
    """:func:`cap_gap` with the spin rate ``w`` [rad/s] given (the lockstep kernel's lanes keep it)."""
    ux = vx - c.wind_x
    uy = vy - c.wind_y
    uz = vz - c.wind_z
    return cap_distance(aero, math.sqrt(ux * ux + uy * uy + uz * uz), w, c.radius, ap)


@nb.njit(**JIT, inline="always")
def cap_zone_scale(d0, d1):
    """The factor of a step's error from the :func:`cap_gap` ``d0`` at its start and ``d1`` at its end:
    :data:`~tennislab.core.aero.CAP_ZONE_ERR` if the step starts or ends in the capped lift's blend zone
    or crosses the cap, else 1 (branch-free, so that the lockstep kernel evaluates it in SIMD lanes)."""
    zone = CAP_ZONE * _CAP_BLEND
    near = (abs(d0) < zone) | (abs(d1) < zone) | (d0 * d1 < 0.0)
    return CAP_ZONE_ERR if near else 1.0


@nb.njit(**JIT, inline="always")
def cap_scale(aero, ap, c, vx0, vy0, vz0, wx0, wy0, wz0, vx1, vy1, vz1, wx1, wy1, wz1):
    """:func:`cap_zone_scale` of a step from velocity/spin 0 to 1 (the lockstep kernel keeps the start's
    :func:`cap_gap` from the step before instead: the same numbers)."""
    return cap_zone_scale(
        cap_gap(aero, ap, c, vx0, vy0, vz0, wx0, wy0, wz0), cap_gap(aero, ap, c, vx1, vy1, vz1, wx1, wy1, wz1)
    )


@intrinsic
def _float_bits(typingctx, x):
    """The bits of the float64 ``x`` as an int64 (a reinterpretation, no conversion)."""

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.IntType(64))

    return types.int64(types.float64), codegen


@intrinsic
def _bits_float(typingctx, i):
    """The float64 whose bits are the int64 ``i``."""

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.DoubleType())

    return types.float64(types.int64), codegen


#: the bits of 1.0; 1.2 times them less a fifth of x's bits approximate x^-1/5 to ~10 % (the exponent
#: field scales as log2: Blinn 1997, "Floating-point tricks", IEEE Comput. Graph. Appl. 17(4):80)
_ONE_BITS = 0x3FF0000000000000


@nb.njit(**JIT, inline="always")
def inv_fifth_root(x):
    """x^(-1/5) for a normal x in [1e-7, 1e5], to 3 ulp: a first guess from the bits of x, then five
    Newton steps on y^-5 = x (quadratic: 10 % -> 1e-16).  Branch-free, so that LLVM forms every lane's in
    SIMD, where the library's ``pow`` is a scalar call (~11 ns; this 1.7 ns, SIMD)."""
    y = _bits_float(np.int64(1.2 * _ONE_BITS - 0.2 * np.float64(_float_bits(x))))
    for _ in range(5):
        y2 = y * y
        y = y * (1.2 - 0.2 * x * (y2 * y2 * y))
    return y


#: errors below ``_ERR_LO`` give the largest factor (0.9 err^-1/5 >= 10 below 0.09^5 = 5.9e-6), above
#: ``_ERR_HI`` the smallest (<= 0.2 above 4.5^5 = 1845): :func:`step_factor` clamps to them
_ERR_LO = 5e-6
_ERR_HI = 2000.0


@nb.njit(**JIT, inline="always")
def step_factor(err):
    """The step-size factor after a step of scaled error ``err`` (Hairer et al. II.4: 0.9 err^-1/5,
    within [0.2, 10]; err^-1/5 by :func:`inv_fifth_root`), after an accepted step (err <= 1) and a
    rejected one alike (an error of 0 is clamped to ``_ERR_LO``: the largest factor).  Branch-free: the
    lockstep kernel forms every lane's in SIMD."""
    return min(10.0, max(0.2, 0.9 * inv_fifth_root(min(max(err, _ERR_LO), _ERR_HI))))


@nb.njit(**JIT)
def integrate_one(y_init, aero, aero_p, c, ev, row, work, evw):
    """Integrate one trajectory from ``y_init`` (9,) and fill the event ``row`` (NCOLS,).

    ``aero`` is the aero kernel as a first-class function or its inline tag
    (see the batch kernels below); ``c`` the :class:`KernelConsts`; ``ev`` the
    event array (:func:`tennislab.core.events.event_array`); ``work`` a (12, 9)
    and ``evw`` a (6, MAX_EVENTS) scratch array (reused across trajectories).

    Bounded: at most ``c.max_steps`` step attempts, rejected ones included
    (then ``STATUS_FAILED``; a step whose error or new state is not finite is
    rejected and shrunk, so a state that cannot be made finite ends there).  A
    launch faster than ``c.max_speed``, spinning faster than ``c.max_spin`` or
    from beyond ``c.max_position`` is not integrated (``STATUS_OUT_OF_RANGE``).
    This is the reference of the lockstep kernel (:mod:`tennislab.core.lockstep`).
    """
    k = c.k
    g = c.gravity
    r = c.radius
    wx = c.wind_x
    wy = c.wind_y
    wz = c.wind_z
    decay = c.spin_decay
    t_max = c.t_max
    rtol = c.rtol
    atol = c.atol
    n_ev = ev.shape[0]
    tgt = evw[0]
    armed = evw[4]
    done = evw[2]
    K = work[0:7]
    y = work[7]
    ytmp = work[8]
    ynew = work[9]
    fcur = work[11]
    for i in range(9):
        y[i] = y_init[i]
    if not start_flight(y, fcur, aero, aero_p, c, ev, row, evw):
        return
    aim_e = _aim_event(ev)
    t = 0.0
    h = _H0
    nsteps = 0
    attempts = 0
    status = STATUS_NO_LANDING
    while t < t_max:
        if attempts >= c.max_steps:
            status = STATUS_FAILED
            break
        attempts += 1
        if aim_e >= 0 and done[aim_e] == 0.0:
            h = _aim_at(y, fcur, int(ev[aim_e, EV_COMPONENT]), tgt[aim_e], h)
        if t + h > t_max:
            h = t_max - t
        for i in range(9):
            K[0, i] = fcur[i]
        # stages, unrolled (Dormand-Prince tableau constants below)
        for i in range(9):
            ytmp[i] = y[i] + h * (_A21 * K[0, i])
        derivative(ytmp, K[1], aero, aero_p, k, k, g, r, wx, wy, wz, decay)
        for i in range(9):
            ytmp[i] = y[i] + h * (_A31 * K[0, i] + _A32 * K[1, i])
        derivative(ytmp, K[2], aero, aero_p, k, k, g, r, wx, wy, wz, decay)
        for i in range(9):
            ytmp[i] = y[i] + h * (_A41 * K[0, i] + _A42 * K[1, i] + _A43 * K[2, i])
        derivative(ytmp, K[3], aero, aero_p, k, k, g, r, wx, wy, wz, decay)
        for i in range(9):
            ytmp[i] = y[i] + h * (_A51 * K[0, i] + _A52 * K[1, i] + _A53 * K[2, i] + _A54 * K[3, i])
        derivative(ytmp, K[4], aero, aero_p, k, k, g, r, wx, wy, wz, decay)
        for i in range(9):
            ytmp[i] = y[i] + h * (_A61 * K[0, i] + _A62 * K[1, i] + _A63 * K[2, i] + _A64 * K[3, i] + _A65 * K[4, i])
        derivative(ytmp, K[5], aero, aero_p, k, k, g, r, wx, wy, wz, decay)
        for i in range(9):
            ynew[i] = y[i] + h * (_B1 * K[0, i] + _B3 * K[2, i] + _B4 * K[3, i] + _B5 * K[4, i] + _B6 * K[5, i])
        derivative(ynew, K[6], aero, aero_p, k, k, g, r, wx, wy, wz, decay)
        errsum = 0.0
        ysum = 0.0
        for i in range(9):
            acc = _E1 * K[0, i] + _E3 * K[2, i] + _E4 * K[3, i] + _E5 * K[4, i] + _E6 * K[5, i] + _E7 * K[6, i]
            sc = atol + rtol * max(abs(y[i]), abs(ynew[i]))
            e_i = h * acc / sc
            errsum += e_i * e_i
            ysum += ynew[i]
        err = math.sqrt(errsum / 9.0) * cap_scale(
            aero, aero_p, c, y[3], y[4], y[5], y[6], y[7], y[8], ynew[3], ynew[4], ynew[5], ynew[6], ynew[7], ynew[8]
        )
        if not math.isfinite(err + ysum):  # a non-finite error or state: a rejection, counted in attempts
            h *= 0.2
            continue
        if err > 1.0:
            h *= step_factor(err)
            continue
        nsteps += 1
        # ---- events within [t, t + h]: every crossing first, then the earliest that ends the flight
        stop_e = step_events(ev, c, evw, t, h, y, ynew, K, nsteps, row)
        if nsteps == 1:
            for e in range(n_ev):
                armed[e] = 0.0
        if stop_e >= 0:
            status = int(ev[stop_e, EV_STATUS])
            break
        t += h
        for i in range(9):
            y[i] = ynew[i]
            fcur[i] = K[6, i]
        h *= step_factor(err)
    _finish_row(row, c, status, nsteps)


@nb.njit(**JIT)
def _record_state(ev, e, t, ystate, row):
    """Write event ``e``'s time ``t`` and recorded components of ``ystate`` into ``row``."""
    row[int(ev[e, EV_TCOL])] = t
    for i in range(9):
        col = int(ev[e, EV_COL0 + i])
        if col >= 0:
            row[col] = ystate[i]


# ---------------------------------------------------------------- batch kernels
# ``aero`` is either the model's inline tag (tennislab's own models: Numba
# compiles one specialised, cached kernel per model with the C_D/C_L formula
# inlined, ~2x faster for Stepanek's formula) or a first-class function
# (any other kernel: one compiled kernel serves them all; see
# :func:`tennislab.core.aero.aero_coefficients`).
@nb.njit(**JIT, parallel=True)
def batch_kernel(states, aero, aero_p, consts, events, out):
    """Integrate every row of ``states`` (N, 9) and fill the event table ``out`` (N, NCOLS)."""
    n = states.shape[0]
    nchunks = (n + 255) // 256
    for ci in nb.prange(nchunks):
        work = np.empty((12, 9))
        evw = np.empty((6, MAX_EVENTS))
        for i in range(ci * n // nchunks, (ci + 1) * n // nchunks):
            integrate_one(states[i], aero, aero_p, consts, events, out[i], work, evw)


@nb.njit(**JIT)
def serial_kernel(states, aero, aero_p, consts, events, out):
    """As :func:`batch_kernel`, on one thread (for callers that parallelise themselves)."""
    work = np.empty((12, 9))
    evw = np.empty((6, MAX_EVENTS))
    for i in range(states.shape[0]):
        integrate_one(states[i], aero, aero_p, consts, events, out[i], work, evw)


_F = types.float64
BATCH_SIGNATURE = types.void(_F[:, ::1], AERO_FUNCTION_TYPE, _F[::1], CONSTS_TYPE, _F[:, ::1], _F[:, ::1])


@nb.njit(BATCH_SIGNATURE, **JIT)
def batch_kernel_fp(states, aero, aero_p, consts, events, out):
    """:func:`batch_kernel` for an aero kernel passed as a first-class function."""
    batch_kernel(states, aero, aero_p, consts, events, out)


@nb.njit(BATCH_SIGNATURE, **JIT)
def serial_kernel_fp(states, aero, aero_p, consts, events, out):
    """:func:`serial_kernel` for an aero kernel passed as a first-class function."""
    serial_kernel(states, aero, aero_p, consts, events, out)


@nb.njit(**JIT)
def rk4_step(y, h, aero, ap, kd, kl, g, r, wx, wy, wz, dec, work, out):
    """One classical Runge-Kutta 4 step of size ``h`` [s] (negative: backward) from ``y`` into ``out``.

    The fixed-step member of the family, for integrations whose results must vary smoothly with
    their inputs.  Its one caller is :func:`sweep_positions`, which steps it for the line-calling
    track fit (:mod:`tennislab.linecall.model`) and for the track calibration's identification and
    family fit (:mod:`tennislab.calibrate._sweeps`).  Arguments after ``h`` are those of
    :func:`tennislab.core.dynamics.derivative`; ``work`` is a (5, 9) scratch array.

    References
    ----------
    Hairer, Norsett & Wanner, Solving Ordinary Differential Equations I (2nd ed., 1993),
    section II.1, the classical fourth-order method.
    """
    k1 = work[0]
    k2 = work[1]
    k3 = work[2]
    k4 = work[3]
    yt = work[4]
    derivative(y, k1, aero, ap, kd, kl, g, r, wx, wy, wz, dec)
    for i in range(9):
        yt[i] = y[i] + 0.5 * h * k1[i]
    derivative(yt, k2, aero, ap, kd, kl, g, r, wx, wy, wz, dec)
    for i in range(9):
        yt[i] = y[i] + 0.5 * h * k2[i]
    derivative(yt, k3, aero, ap, kd, kl, g, r, wx, wy, wz, dec)
    for i in range(9):
        yt[i] = y[i] + h * k3[i]
    derivative(yt, k4, aero, ap, kd, kl, g, r, wx, wy, wz, dec)
    for i in range(9):
        out[i] = y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])


#: steps allowed per :func:`sweep_positions` (bounds a sweep toward a far sample time: 40 s at 8 ms)
MAX_SWEEP_STEPS = 5000


@nb.njit(**JIT)
def sweep_positions(y0, t0, t, idx, n, h, aero, ap, kd, kl, g, r, wx, wy, wz, dec, out):
    """Positions at the times ``t[idx[0..n-1]]`` (ordered away from ``t0``) of the flight from
    state ``y0`` (9,) at ``t0``, by :func:`rk4_step` steps of fixed size ``h`` [s] (negative:
    backward) on a grid anchored at ``t0``; written into ``out[idx[j], 0:3]``.

    Between two steps the position is the cubic Hermite interpolant of the positions and
    velocities at the step's ends (error ~ h^4 |d^4x/dt^4| / 384: below 0.13 um for tennis
    flights at 16 ms).  Because the grid moves with ``t0`` and never depends on the data, the
    positions are smooth functions of ``y0``, ``t0`` and the constants (a least-squares fit can
    difference them); an adaptive step would make them jump where its step sequence changes.
    NaN beyond :data:`MAX_SWEEP_STEPS` steps or from a non-finite state.  ``kd``, ``kl``: the
    drag and lift constants of :func:`tennislab.core.dynamics.derivative` (k times the scales).
    """
    work = np.empty((5, 9))
    ya = y0.copy()
    yb = np.empty(9)
    ta = t0
    rk4_step(ya, h, aero, ap, kd, kl, g, r, wx, wy, wz, dec, work, yb)
    tb = t0 + h
    direction = 1.0 if h > 0.0 else -1.0
    steps = 1
    for j in range(n):
        ts = t[idx[j]]
        while (ts - tb) * direction > 0.0 and steps <= MAX_SWEEP_STEPS:
            for i in range(9):
                ya[i] = yb[i]
            ta = tb
            rk4_step(ya, h, aero, ap, kd, kl, g, r, wx, wy, wz, dec, work, yb)
            tb = ta + h
            steps += 1
        if steps > MAX_SWEEP_STEPS or not (math.isfinite(yb[0]) and math.isfinite(yb[1]) and math.isfinite(yb[2])):
            for c in range(3):
                out[idx[j], c] = np.nan
            continue
        s = (ts - ta) / h
        s2 = s * s
        s3 = s2 * s
        h00 = 2 * s3 - 3 * s2 + 1
        h10 = s3 - 2 * s2 + s
        h01 = -2 * s3 + 3 * s2
        h11 = s3 - s2
        for c in range(3):
            out[idx[j], c] = h00 * ya[c] + h10 * h * ya[c + 3] + h01 * yb[c] + h11 * h * yb[c + 3]
