"""Lockstep batch kernel: shots advanced together in blocks of :data:`LANES`, structure of arrays.

The same Dormand-Prince 5(4) pair, step-size control, first step, landing aim and
event table as the per-shot kernel :func:`tennislab.core.integrators.integrate_one`
(its reference), with every lane (one shot) keeping its own time, step size, error
and events.  The stages and the error norm are loops over the lanes of arrays laid
out as ``[component, lane]``, so that LLVM turns them into packed (SIMD) arithmetic:
one evaluation of the right-hand side serves :data:`LANES` shots.  Only the per-lane
decisions (accept or reject, the events of an accepted step, a finished flight) are
scalar; a lane whose flight ends takes the next shot of its block at once, so the
lanes stay busy until the block runs dry; then its flights still going move down to
its lowest lanes (:func:`_compact`), since a step computes the lanes up to the last
busy one.

Each lane does the per-shot kernel's arithmetic in the same order, so both give the
same landings to round-off (1e-9 m, tests/core/test_lockstep.py); the setup of a
flight and the handling of an accepted step's events are the per-shot kernel's own
functions (:func:`~tennislab.core.integrators.start_flight`,
:func:`~tennislab.core.integrators.step_events`).

References
----------
.. [1] Dormand & Prince (1980), J. Comput. Appl. Math. 6:19
.. [2] Hairer, Norsett & Wanner (1993), Solving Ordinary Differential Equations I, 2nd ed., sec. II.4
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from tennislab.core._jit import JIT
from tennislab.core.aero import _constant_kernel, _kernel_key, _linear_lift_kernel, _stepanek_kernel
from tennislab.core.dynamics import derivative_lanes, lane_spin_rate, spin_rate
from tennislab.core.events import EV_COMPONENT, EV_STATUS, MAX_EVENTS
from tennislab.core.integrators import (
    _A21,
    _A31,
    _A32,
    _A41,
    _A42,
    _A43,
    _A51,
    _A52,
    _A53,
    _A54,
    _A61,
    _A62,
    _A63,
    _A64,
    _A65,
    _B1,
    _B3,
    _B4,
    _B5,
    _B6,
    _E1,
    _E3,
    _E4,
    _E5,
    _E6,
    _E7,
    _H0,
    BATCH_SIGNATURE,
    STATUS_FAILED,
    STATUS_NO_LANDING,
    W_ARMED,
    W_DIRECTION,
    W_DONE,
    W_TARGET,
    _aim_event,
    _finish_row,
    aim_step,
    cap_gap,
    cap_gap_at_spin,
    cap_zone_scale,
    start_flight,
    step_events,
    step_factor,
)

#: shots advanced together.  64 lanes, not the 8 of one 512-bit register: LLVM vectorises each loop over
#: the lanes (8 per register, several registers in flight, since the stages' square roots and divisions are
#: latency-bound) only when the loop runs 64 times or more, after checking at run time that its arrays do not
#: overlap (read from the kernel's assembly); with 32 lanes every step ran in the scalar remainder.  A step
#: computes the lanes up to the last busy one only (a batch of a few shots pays for those, not for 64); with
#: no reassociation in the kernels (:data:`~tennislab.core._jit.FASTMATH`) a lane's arithmetic is the same in
#: the vector loop and in its remainder, so a shot's row does not depend on where it sits and chunking a
#: batch never changes a bit (docs/batch.md; tests/core/test_lockstep.py).  One thread, 2 x 10^4 mixed shots,
#: same-run A/B against 32 lanes: 1.55-1.61 against 1.87-1.94 us CPU per flight; batches of 1 and 20 shots
#: the same (51 and 104-111 us CPU against 49 and 95-101 us)
LANES = 64
#: shots per block (one thread's unit of work): the lanes idle only while a block drains
BLOCK = 512


def lockstep_suits(kernel) -> bool:
    """Whether the lockstep kernel is the faster for the aero ``kernel``: tennislab's smooth formulas
    (``constant``, ``stepanek1988``, the linear-lift models such as the default), which LLVM evaluates
    in SIMD lanes (2 threads, 5 x 10^4 mixed shots, quiet machine, one run: the default model 1.5x the
    per-shot kernel, ``stepanek1988`` 1.4x, ``launcher2015`` 1.8x, ``constant`` 1.3x; 20 shots 1.1-1.3x,
    the default 1.4x since a step computes the busy lanes only; 200 shots 1.9-3.1x).  Not a user's kernel
    (called through a pointer: no lane can share the call) nor the ``table`` and ``curves`` models (their
    cell search is a loop per lane: ``tennislab2026`` 0.98x), which keep the per-shot kernel."""
    return _kernel_key(kernel) in _SUITED


_SUITED = frozenset(_kernel_key(k) for k in (_constant_kernel, _stepanek_kernel, _linear_lift_kernel))


@nb.njit(**JIT, inline="always")
def _changing_rows(dec):
    """How many rows of a lane's state a step changes: all 9, or without spin decay (``dec`` 0) the 6 of
    position and velocity (the spin is the start's to the bit)."""
    return 6 if dec == 0.0 else 9


@nb.njit(**JIT)
def _stages(Y, K, YT, YN, h, errsum, ysum, err, fac, D0, D1, WN, aero, ap, c, n):
    """One Dormand-Prince step of size ``h[l]`` from ``Y`` (slopes ``K[0]``) in every lane: the stages
    ``K[1..6]``, the new state ``YN`` and, per lane, the sum of the new state, the
    :func:`~tennislab.core.integrators.cap_gap` ``D1`` of ``YN`` and the step's scaled error ``err`` (the
    RMS of the scaled errors, ``errsum`` their squares, times the error factor of a capped lift's blend zone
    from ``D1`` and ``D0``, that of ``Y``: ``cap_zone_scale``, the per-shot kernel's ``cap_scale``) with
    its step-size factor ``fac`` (:func:`~tennislab.core.integrators.step_factor`, SIMD).
    ``WN`` holds each lane's spin rate (:func:`~tennislab.core.dynamics.lane_spin_rate`)."""
    k = c.k
    g = c.gravity
    r = c.radius
    wx = c.wind_x
    wy = c.wind_y
    wz = c.wind_z
    dec = c.spin_decay
    # the right-hand side reads velocity and spin only: the stages' positions are not formed; without
    # spin decay the spin rows of every stage are Y's (slopes 0: the same to the bit), kept in YT, YN
    hi = _changing_rows(dec)
    if dec == 0.0:
        for i in range(6, 9):
            for la in range(n):
                YT[i, la] = Y[i, la]
                YN[i, la] = Y[i, la]
    for i in range(3, hi):
        for la in range(n):
            YT[i, la] = Y[i, la] + h[la] * (_A21 * K[0, i, la])
    derivative_lanes(YT, K[1], n, aero, ap, k, g, r, wx, wy, wz, dec, WN)
    for i in range(3, hi):
        for la in range(n):
            YT[i, la] = Y[i, la] + h[la] * (_A31 * K[0, i, la] + _A32 * K[1, i, la])
    derivative_lanes(YT, K[2], n, aero, ap, k, g, r, wx, wy, wz, dec, WN)
    for i in range(3, hi):
        for la in range(n):
            YT[i, la] = Y[i, la] + h[la] * (_A41 * K[0, i, la] + _A42 * K[1, i, la] + _A43 * K[2, i, la])
    derivative_lanes(YT, K[3], n, aero, ap, k, g, r, wx, wy, wz, dec, WN)
    for i in range(3, hi):
        for la in range(n):
            YT[i, la] = Y[i, la] + h[la] * (
                _A51 * K[0, i, la] + _A52 * K[1, i, la] + _A53 * K[2, i, la] + _A54 * K[3, i, la]
            )
    derivative_lanes(YT, K[4], n, aero, ap, k, g, r, wx, wy, wz, dec, WN)
    for i in range(3, hi):
        for la in range(n):
            YT[i, la] = Y[i, la] + h[la] * (
                _A61 * K[0, i, la] + _A62 * K[1, i, la] + _A63 * K[2, i, la] + _A64 * K[3, i, la] + _A65 * K[4, i, la]
            )
    derivative_lanes(YT, K[5], n, aero, ap, k, g, r, wx, wy, wz, dec, WN)
    for i in range(hi):
        for la in range(n):
            YN[i, la] = Y[i, la] + h[la] * (
                _B1 * K[0, i, la] + _B3 * K[2, i, la] + _B4 * K[3, i, la] + _B5 * K[4, i, la] + _B6 * K[5, i, la]
            )
    derivative_lanes(YN, K[6], n, aero, ap, k, g, r, wx, wy, wz, dec, WN)
    for la in range(n):
        errsum[la] = 0.0
        ysum[la] = 0.0
    for i in range(hi):  # without spin decay the spin's stages are 0: no error to add
        for la in range(n):
            acc = (
                _E1 * K[0, i, la]
                + _E3 * K[2, i, la]
                + _E4 * K[3, i, la]
                + _E5 * K[4, i, la]
                + _E6 * K[5, i, la]
                + _E7 * K[6, i, la]
            )
            sc = c.atol + c.rtol * max(abs(Y[i, la]), abs(YN[i, la]))
            e_i = h[la] * acc / sc
            errsum[la] += e_i * e_i
    for i in range(9):
        for la in range(n):
            ysum[la] += YN[i, la]
    for la in range(n):
        w = lane_spin_rate(YN, la, WN, dec)
        D1[la] = cap_gap_at_spin(aero, ap, c, YN[3, la], YN[4, la], YN[5, la], w)
        err[la] = math.sqrt(errsum[la] / 9.0) * cap_zone_scale(D0[la], D1[la])
        fac[la] = step_factor(err[la])


@nb.njit(**JIT)
def _crosses(ev, evw, YN, lane):
    """Whether an event still to come may have happened in the lane's step (``step_events`` then
    looks): the new state on or beyond its target.  ``evw`` is every lane's event work (LANES, 6,
    MAX_EVENTS), indexed in place: a view per lane and step would cost two atomic reference counts."""
    for e in range(ev.shape[0]):
        if (
            evw[lane, W_DONE, e] == 0.0
            and evw[lane, W_DIRECTION, e] * (YN[int(ev[e, EV_COMPONENT]), lane] - evw[lane, W_TARGET, e]) >= 0.0
        ):
            return True
    return False


@nb.njit(**JIT)
def _load(states, nxt, i1, lane, Y, F, D0, WN, t, h, shot, nst, att, aero, ap, c, ev, out, evw, y1, f1):
    """Give ``lane`` the next shot from ``nxt`` on that needs integrating (the others finish at their
    start), and its start's ``cap_gap`` in ``D0``; returns the next unused row.  A lane left without a
    shot idles at rest (``shot`` -1)."""
    while nxt < i1:
        i = nxt
        nxt += 1
        for j in range(9):
            y1[j] = states[i, j]
        if start_flight(y1, f1, aero, ap, c, ev, out[i], evw[lane]):
            for j in range(9):
                Y[j, lane] = y1[j]
                F[j, lane] = f1[j]
            D0[lane] = cap_gap(aero, ap, c, y1[3], y1[4], y1[5], y1[6], y1[7], y1[8])
            WN[lane] = spin_rate(Y, lane)
            t[lane] = 0.0
            h[lane] = _H0
            nst[lane] = 0
            att[lane] = 0
            shot[lane] = i
            return nxt
    _idle(lane, shot, Y, F, D0, WN, h)
    return nxt


@nb.njit(**JIT, inline="always")
def _idle(lane, shot, Y, F, D0, WN, h):
    """Leave ``lane`` without a shot (``shot`` -1), at rest."""
    shot[lane] = -1
    h[lane] = 0.0
    D0[lane] = 0.0
    WN[lane] = 0.0
    for j in range(9):
        Y[j, lane] = 0.0
        F[j, lane] = 0.0


#: Busy lanes at most of a drained block whose step computes 64 lanes, below which its flights move to the lowest
#: lanes (:func:`_compact`): the loops then run in their scalar remainder, ~3x the cost of a SIMD lane, over the
#: busy lanes alone
COMPACT_BELOW = LANES // 3


@nb.njit(**JIT)
def _compact(shot, Y, F, D0, WN, t, h, nst, att, evw):
    """Move the flights of a drained block into its lowest lanes, the idle ones above, when that shortens the
    lanes a step computes (to the last busy one): whenever a step computes fewer than :data:`LANES` lanes (the
    scalar remainder, whose cost is per lane), else once no more than :data:`COMPACT_BELOW` are busy.  A lane's
    arithmetic does not depend on where it sits: the same rows to the bit."""
    busy = 0
    top = 0
    for lane in range(LANES):
        if shot[lane] >= 0:
            busy += 1
            top = lane + 1
    if busy == top or (top == LANES and busy > COMPACT_BELOW):
        return
    dst = 0
    for src in range(top):
        if shot[src] < 0:
            continue
        while shot[dst] >= 0 and dst < src:
            dst += 1
        if dst >= src:
            continue
        for j in range(9):
            Y[j, dst] = Y[j, src]
            F[j, dst] = F[j, src]
        for a in range(evw.shape[1]):
            for e in range(evw.shape[2]):
                evw[dst, a, e] = evw[src, a, e]
        D0[dst], WN[dst], t[dst], h[dst] = D0[src], WN[src], t[src], h[src]
        nst[dst], att[dst], shot[dst] = nst[src], att[src], shot[src]
        _idle(src, shot, Y, F, D0, WN, h)


@nb.njit(**JIT)
def _block(states, i0, i1, aero, ap, c, ev, out):
    """Fly the rows ``i0`` to ``i1`` of ``states`` into ``out``, :data:`LANES` at a time."""
    Y = np.empty((9, LANES))
    K = np.zeros((7, 9, LANES))  # zeros: without spin decay the spin's slopes are never written
    F = K[0]  # the slopes at Y: the first stage of the next step
    acc = np.zeros(LANES, dtype=np.bool_)
    YT = np.empty((9, LANES))
    YN = np.empty((9, LANES))
    h = np.empty(LANES)
    t = np.zeros(LANES)
    errsum = np.empty(LANES)
    ysum = np.empty(LANES)
    errs = np.empty(LANES)
    facs = np.empty(LANES)  # each lane's step-size factor (step_factor of its error)
    D0 = np.empty(LANES)
    D1 = np.empty(LANES)
    WN = np.empty(LANES)  # each lane's |w| (spin_rate of its start: constant without spin decay)
    shot = np.empty(LANES, dtype=np.int64)
    nst = np.zeros(LANES, dtype=np.int64)
    att = np.zeros(LANES, dtype=np.int64)
    evw = np.empty((LANES, 6, MAX_EVENTS))
    y1 = np.empty(9)
    f1 = np.empty(9)
    yl = np.empty(9)
    ynl = np.empty(9)
    Kl = np.empty((7, 9))
    aim_e = _aim_event(ev)
    aim_c = int(ev[aim_e, EV_COMPONENT]) if aim_e >= 0 else 0
    nxt = i0
    for lane in range(LANES):
        nxt = _load(states, nxt, i1, lane, Y, F, D0, WN, t, h, shot, nst, att, aero, ap, c, ev, out, evw, y1, f1)
    while True:
        busy = 0
        top = 0
        for lane in range(LANES):  # before the step: the attempt limit, the aim at the ground, t_max
            while shot[lane] >= 0 and att[lane] >= c.max_steps:
                _finish_row(out[shot[lane]], c, STATUS_FAILED, nst[lane])
                nxt = _load(
                    states, nxt, i1, lane, Y, F, D0, WN, t, h, shot, nst, att, aero, ap, c, ev, out, evw, y1, f1
                )
            if shot[lane] < 0:
                continue
            busy += 1
            top = lane + 1
            att[lane] += 1
            if aim_e >= 0 and evw[lane, W_DONE, aim_e] == 0.0:
                h[lane] = aim_step(
                    Y[aim_c, lane] - evw[lane, W_TARGET, aim_e], F[aim_c, lane], F[aim_c + 3, lane], h[lane]
                )
            if t[lane] + h[lane] > c.t_max:
                h[lane] = c.t_max - t[lane]
        if busy == 0:
            return
        _stages(Y, K, YT, YN, h, errsum, ysum, errs, facs, D0, D1, WN, aero, ap, c, top)
        for lane in range(LANES):  # after the step, lane by lane
            if shot[lane] < 0:
                continue
            err = errs[lane]
            if not math.isfinite(err + ysum[lane]):  # a non-finite error or state: a rejection
                h[lane] *= 0.2
                continue
            if err > 1.0:
                h[lane] *= facs[lane]
                continue
            nst[lane] += 1
            stop_e = -1
            if _crosses(ev, evw, YN, lane):
                for j in range(9):
                    yl[j] = Y[j, lane]
                    ynl[j] = YN[j, lane]
                    for s in range(7):
                        Kl[s, j] = K[s, j, lane]
                stop_e = step_events(ev, c, evw[lane], t[lane], h[lane], yl, ynl, Kl, nst[lane], out[shot[lane]])
            if nst[lane] == 1:
                for e in range(ev.shape[0]):
                    evw[lane, W_ARMED, e] = 0.0
            if stop_e >= 0:
                _finish_row(out[shot[lane]], c, int(ev[stop_e, EV_STATUS]), nst[lane])
                nxt = _load(
                    states, nxt, i1, lane, Y, F, D0, WN, t, h, shot, nst, att, aero, ap, c, ev, out, evw, y1, f1
                )
                continue
            t[lane] += h[lane]
            if not t[lane] < c.t_max:
                _finish_row(out[shot[lane]], c, STATUS_NO_LANDING, nst[lane])
                nxt = _load(
                    states, nxt, i1, lane, Y, F, D0, WN, t, h, shot, nst, att, aero, ap, c, ev, out, evw, y1, f1
                )
                continue
            acc[lane] = True
            h[lane] *= facs[lane]
        for i in range(_changing_rows(c.spin_decay)):  # the lanes going on (SIMD, masked)
            for la in range(LANES):
                if acc[la]:
                    Y[i, la] = YN[i, la]
                    F[i, la] = K[6, i, la]
        for la in range(LANES):
            if acc[la]:
                D0[la] = D1[la]
            acc[la] = False
        if nxt >= i1:  # the block has run dry: its flights still going move down (a step computes up to the last)
            _compact(shot, Y, F, D0, WN, t, h, nst, att, evw)


@nb.njit(**JIT, parallel=True)
def lockstep_kernel(states, aero, aero_p, consts, events, out):
    """Integrate every row of ``states`` (N, 9) into the event table ``out`` (N, NCOLS), blocks of
    :data:`BLOCK` rows in parallel (``numba.prange``), each flown :data:`LANES` shots at a time."""
    n = states.shape[0]
    nblocks = (n + BLOCK - 1) // BLOCK
    if nblocks < 2 and n > 1:
        nblocks = 2  # both cores for a small batch
    for b in nb.prange(nblocks):
        _block(states, b * n // nblocks, (b + 1) * n // nblocks, aero, aero_p, consts, events, out)


@nb.njit(**JIT)
def lockstep_serial_kernel(states, aero, aero_p, consts, events, out):
    """As :func:`lockstep_kernel`, on one thread (for callers that parallelise themselves)."""
    _block(states, 0, states.shape[0], aero, aero_p, consts, events, out)


@nb.njit(BATCH_SIGNATURE, **JIT)
def lockstep_kernel_fp(states, aero, aero_p, consts, events, out):
    """:func:`lockstep_kernel` for an aero kernel passed as a first-class function."""
    lockstep_kernel(states, aero, aero_p, consts, events, out)


@nb.njit(BATCH_SIGNATURE, **JIT)
def lockstep_serial_kernel_fp(states, aero, aero_p, consts, events, out):
    """:func:`lockstep_serial_kernel` for an aero kernel passed as a first-class function."""
    lockstep_serial_kernel(states, aero, aero_p, consts, events, out)


__all__ = ["BLOCK", "LANES", "lockstep_kernel", "lockstep_serial_kernel", "lockstep_suits"]
