"""The line-call workflows: one shot's track (:func:`call_track`), a state (:func:`call_state`) and
camera detections (:func:`call_detections`), each returning a :class:`TrackCall`.

:func:`call_track` is the pipeline of ``tennislab call --track`` and of every shot of
``tennislab call --rally`` (:mod:`tennislab.linecall.rally`):

1. the net check (:func:`tennislab.linecall.net.check_net`): a ball stopped by the net is called
   ``net``; after a net cord only the flight after the net is fitted; a serve that touched the tape
   and lands in its box is a ``let``;
2. the first bounce in the data (:func:`tennislab.linecall.detect.find_bounces`): the fit splits
   there and ends before the second; later bounces are reported (``bounces``), not called;
3. the robust fit through the bounce (:func:`tennislab.linecall.fit.fit_track`), the ball mark
   (:func:`tennislab.core.mark.ball_mark`) and the decision against the target or line with its
   probability (:func:`tennislab.linecall.decide.call_mark`);
4. the quality gate: a fit that diverged (non-finite parameters or covariance, an incoming speed far
   from the data's or beyond :data:`MAX_SPEED`), a model misfit (residual RMS above
   :data:`MISFIT_SIGMA` times the track's noise and above :data:`MISFIT_MIN`), more than a quarter of
   the points rejected, a bounce extrapolated beyond :data:`MAX_EXTRAPOLATION`, or ``p_in`` within
   :data:`REVIEW_P` is answered ``review`` with the reasons (``review_reasons``), never a confident
   call; ``provisional_call`` keeps what the numbers say.

The track's noise, for the misfit test, is the given sigma or the model-free estimate from third
differences (:func:`tennislab.linecall.detect.noise_from_differences`), never below
:data:`tennislab.linecall.fit.NOISE_FLOOR`.

Spin (``spin``): the fitted spin vector at the bounce in the launch vocabulary of
:mod:`tennislab.core.launch` relative to the incoming velocity d: topspin (about h = unit(z x d),
horizontal; < 0 backspin), sidespin (about u = d x h; > 0 curves the ball to its left) and spin along
the path (about d), each with its 1-sigma from the fit's covariance, in rpm; the tracker's signed
rpm (negative = backspin) is compared with the topspin component.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace

import numpy as np

import tennislab.linecall.local_fit as local_fit
import tennislab.linecall.model as M
from tennislab.core.bounce import bounce
from tennislab.core.flight import DEFAULT_NET, FlightParams, fly_dense, with_net
from tennislab.core.mark import MarkParams, ball_mark
from tennislab.core.surfaces import get_surface
from tennislab.errors import InputError, check_range, check_vector
from tennislab.linecall.answer import (
    OWN_SIDE,
    BounceEstimate,
    TrackCall,
    fit_entry,
    no_fit,
    review_call,
    spin_components,
)
from tennislab.linecall.cameras import cameras_from_records, triangulate_detections
from tennislab.linecall.closed_form import closed_form_from_physics
from tennislab.linecall.decide import N_SAMPLES, call_mark
from tennislab.linecall.detect import (
    bounce_estimate,
    find_bounces,
    noise_from_differences,
    off_grid,
    travel_direction,
)
from tennislab.linecall.fit import (
    AUTO_GAP,
    MAX_REJECT_FRACTION,
    MODEL_SIGMA,
    NOISE_FLOOR,
    WHOLE_FLIGHT,
    TrackFit,
    fit_track,
)
from tennislab.linecall.local_fit import LocalFit, refine_bounce
from tennislab.linecall.net import NetCheck, check_net

MAX_SPEED = 80.0  #: [m/s] fastest credible incoming speed at a bounce (fastest serves: 73 m/s off the racket)
SPEED_TOL = (0.35, 6.0)  #: a fitted incoming speed further than rel x |v| + abs [m/s] from the data's has diverged
MISFIT_SIGMA = 5.0  #: residual RMS per axis above this many noise sigmas is a model misfit...
MISFIT_MIN = 0.02  #: [m] ...and above this 3-D RMS
MAX_EXTRAPOLATION = 0.15  #: [s] a bounce further than this after the last sample before it is a guess
REVIEW_P = (0.05, 0.95)  #: p_in strictly between these: ``review``
LOCAL_MISFIT_MIN = 5e-3  #: [m] a local residual (3-D RMS) below this is never a misfit
RUNS_Z = -3.0  #: runs-test z below which the residual signs near the bounce are systematic
#: physical ranges of the fitted aero scales (C_D and C_L of real balls lie within a factor ~2 of any
#: published model's; a scale outside says the fit absorbed something that is not aerodynamics)
DRAG_SCALE_RANGE = (0.4, 2.5)
LIFT_SCALE_RANGE = (0.0, 3.0)
MIN_TRACK_POINTS = 4  #: fewest samples of a track called
SECOND_BOUNCE_GAP = 0.02  #: [s] the fit ends this long before the second bounce's lowest sample


def _check_track(t, xyz, sigma):
    try:
        t = np.asarray(t, dtype=float).reshape(-1)
        xyz = np.asarray(xyz, dtype=float).reshape(-1, 3)
    except (TypeError, ValueError):
        raise InputError("track: times must be (N,) and positions (N, 3) numbers") from None
    if t.size != xyz.shape[0]:
        raise InputError(f"track: {t.size} times but {xyz.shape[0]} positions")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(xyz))):
        raise InputError("track: times and positions must be finite")
    if t.size > 1 and np.any(np.diff(t) <= 0):
        raise InputError("track: times must be strictly increasing")
    if sigma is not None:
        sig = np.broadcast_to(np.asarray(sigma, dtype=float), t.shape).copy()
        if not np.all((sig > 0) & (sig <= 1.0)):
            bad = float(sig[~((sig > 0) & (sig <= 1.0))][0])
            raise InputError(f"sigma: {bad:g} m is outside the allowed range (0, 1] m")
        sigma = sig
    return t, xyz, sigma


def quality_reasons(fit: TrackFit, t, noise: float, local: LocalFit | None = None) -> list[str]:
    """Why a fit must not give a confident call (empty: none).

    ``fit`` is the whole-flight fit, ``local`` the refit that placed the bounce
    (:func:`~tennislab.linecall.local_fit.refine_bounce`).  A model cannot follow a long real flight
    exactly, and its departure grows with the flight time (real 50 Hz tracker output, set 1: 2 mm
    median under 0.5 s, 7 mm at 1.1-1.5 s, 15 mm beyond; a 2.4 s lob stored as one cubic leaves 70
    mm), so the whole flight is judged only for what no bounce estimate survives: a diverged fit,
    aero scales outside :data:`DRAG_SCALE_RANGE` / :data:`LIFT_SCALE_RANGE`, most points rejected,
    a residual above :data:`MISFIT_SIGMA` noise sigmas and :data:`MISFIT_MIN` x max(1, (T / 1 s)^4)
    (T: the flight time fitted; a glued or broken track, not a long flight); the samples
    near the bounce must be followed to within the noise: a local residual above
    :data:`MISFIT_SIGMA` sigmas and :data:`LOCAL_MISFIT_MIN`, or residual signs in long runs
    (runs test z below :data:`RUNS_Z`, with a residual above twice the noise), is a misfit."""
    reasons = []
    p = fit.p
    if not (np.all(np.isfinite(p)) and np.all(np.isfinite(fit.cov)) and np.isfinite(fit.rms)):
        return ["fit diverged: non-finite parameters, covariance or residuals"]
    v = float(np.linalg.norm(p[M.P_VIN]))
    v0 = float(np.linalg.norm(fit.p_start[M.P_VIN]))
    if v > MAX_SPEED or abs(v - v0) > SPEED_TOL[0] * v0 + SPEED_TOL[1]:
        reasons.append(f"fit diverged: incoming speed {v:.1f} m/s where the data say {v0:.1f} m/s")
    pre_t = t[fit.segment == M.SEG_PRE]
    if local is not None:
        near = t[local.rows][t[local.rows] < fit.t_bounce]
        pre_t = near if not pre_t.size else np.concatenate([near, pre_t[pre_t < near.min()]]) if near.size else pre_t
    if pre_t.size and fit.t_bounce - pre_t.max() > MAX_EXTRAPOLATION:
        reasons.append(f"bounce extrapolated {fit.t_bounce - pre_t.max():.2f} s beyond the last sample before it")
    if pre_t.size and fit.t_bounce < pre_t.min():
        reasons.append("fit diverged: the bounce lies before the track")
    ref = max(noise, NOISE_FLOOR) if np.isfinite(noise) else max(fit.noise, NOISE_FLOOR)
    span = fit.t_bounce - float(pre_t.min()) if pre_t.size else 0.0
    lim = max(MISFIT_SIGMA * math.sqrt(3.0) * ref, MISFIT_MIN * max(1.0, span**4))
    if fit.rms > lim:
        reasons.append(f"model misfit: residual rms {fit.rms * 1e3:.1f} mm against a noise of {ref * 1e3:.1f} mm")
    for name, val, (lo, hi) in (
        ("drag", fit.drag_scale, DRAG_SCALE_RANGE),
        ("lift", fit.lift_scale, LIFT_SCALE_RANGE),
    ):
        if not lo <= val <= hi:
            reasons.append(f"model misfit: non-physical {name} scale {val:.2f} (physical: {lo:g} to {hi:g})")
    if fit.rejection_capped:
        reasons.append("most points rejected: more than a quarter of the points look like outliers")
    if local is not None:
        lref = max(noise, local_fit.NOISE_MIN) if np.isfinite(noise) else ref
        llim = max(MISFIT_SIGMA * math.sqrt(3.0) * lref, LOCAL_MISFIT_MIN)
        if local.rms > llim:
            reasons.append(
                f"model misfit near the bounce: residual rms {local.rms * 1e3:.1f} mm over the last "
                f"{local.window:.2f} s against a noise of {lref * 1e3:.1f} mm"
            )
        elif local.runs_z < RUNS_Z and local.rms > 2.0 * math.sqrt(3.0) * lref:
            reasons.append(
                f"systematic residuals near the bounce: runs test z = {local.runs_z:.1f} "
                f"over the last {local.window:.2f} s"
            )
        if local.n_outliers > MAX_REJECT_FRACTION * max(local.rows.size + local.n_outliers, 1):
            reasons.append("most points rejected near the bounce: more than a quarter look like outliers")
    return reasons


def _crosses_net(t, xyz, direction: float) -> bool | None:
    """Whether the samples ever reach the far side of the net plane (None: no samples)."""
    if t.size == 0:
        return None
    return bool(np.any(xyz[:, 0] * direction > 0.0)) and bool(np.any(xyz[:, 0] * direction < 0.0))


def _local_params(p_whole: np.ndarray, p_local: np.ndarray) -> np.ndarray:
    """The whole-flight parameters with the bounce (point, time, velocity in) of the local fit; the
    spin and the aero scales stay the whole flight's (a short window hardly sees them)."""
    p = p_whole.copy()
    for k in (M.P_XB, M.P_YB, M.P_TB, *M.indices(M.P_VIN)):
        p[k] = p_local[k]
    return p


def _options(window, contact_sigma):
    w = check_vector("window", window, 2)
    if not (0 < w[0] <= 100 and 0 <= w[1] <= 100):
        raise InputError(f"window: ({w[0]:g}, {w[1]:g}) s is outside the allowed range (0, 100] x [0, 100] s")
    cs = check_range("contact_sigma", contact_sigma, 0.0, 10.0, "ms")
    return w, cs


def call_track(
    t,
    xyz,
    sigma=None,
    *,
    params: FlightParams | None = None,
    surface="hard",
    line: str | None = None,
    target: str | None = None,
    drag: str = "prior",
    lift: str = "prior",
    fit_drag: bool = False,
    contact_sigma: float = 0.0,
    window=WHOLE_FLIGHT,
    post: str = "auto",
    serve: bool = False,
    net_check: bool = True,
    strict: bool = True,
    tracker_spin_rpm: float | None = None,
    mark_params: MarkParams = MarkParams(),
    n_samples: int = N_SAMPLES,
) -> TrackCall:
    """Call one shot from its 3-D track (see the module docstring).

    t [s] (N,), xyz [m] (N, 3) ball-centre positions in the court frame, sigma [m] per-axis noise
    (scalar, (N,) or None: estimated); params: flight physics (:meth:`FlightParams.from_options`);
    surface: court surface name; line / target: what to call against (default: the singles court of
    the half the ball lands in); drag, lift, fit_drag: the aero scales of the fit
    (:func:`~tennislab.linecall.fit.fit_track`); contact_sigma [ms]: prior sigma of the contact time
    (0: trust the contact model); window (before, after) [s] around the bounce; serve: a serve (a net
    cord landing in the target is a ``let``); net_check: look for net contact; strict: raise
    :class:`InputError` on a track that cannot be fitted (``False``: answer ``review`` with the reason,
    as for a rally's shots); tracker_spin_rpm: the tracker's signed spin, for comparison.
    """
    t0_clock = time.perf_counter()
    params = params or FlightParams()
    surf = get_surface(surface)
    t, xyz, sigma = _check_track(t, xyz, sigma)
    w, cs = _options(window, contact_sigma)
    t_ref = float(t[0]) if t.size else 0.0
    t = t - t_ref  # times relative to the first sample inside (absolute clocks lose precision)
    if t.size < MIN_TRACK_POINTS:
        msg = f"track: too few points ({t.size}); need at least {MIN_TRACK_POINTS}"
        if strict:
            raise InputError(msg)
        return review_call([msg], params, surf, n_points=int(t.size), track=(t, xyz), time_offset=t_ref)
    n_all = t.size
    drop = off_grid(t)
    if np.any(drop) and np.count_nonzero(~drop) >= MIN_TRACK_POINTS:
        t, xyz = t[~drop], xyz[~drop]
        sigma = None if sigma is None else sigma[~drop]
    noise = float(np.median(sigma)) if sigma is not None else noise_from_differences(t, xyz)
    direction = travel_direction(t, xyz)
    net: NetCheck | None = check_net(t, xyz, params, direction) if net_check else None
    net_d = None if net is None else net.to_dict(t_ref)
    extra_reasons: list[str] = []
    if net is not None and net.contact and not net.crossed:
        return TrackCall(
            method="track-fit",
            call="net",
            surface=surf.name,
            physics=params.to_dict(),
            fit=no_fit(n_all),
            net=net_d,
            track=(t, xyz),
            time_offset=t_ref,
        )
    sel = np.arange(t.size)
    if net is not None and net.contact and net.resume >= 0:
        sel = sel[net.resume :]
    ts, xs = t[sel], xyz[sel]
    bidx = find_bounces(ts, xs)
    later: list[dict] = []
    t_hint = None
    if bidx:
        t_hint = float(ts[bidx[0]])
        if len(bidx) > 1:
            for i in bidx[1:]:
                tb, xb, yb = bounce_estimate(ts, xs, i, params.ball.radius)
                later.append({"t": tb + t_ref, "x": xb, "y": yb})
            cut = ts < ts[bidx[1]] - SECOND_BOUNCE_GAP
            cut &= np.arange(ts.size) <= bidx[1] - 2
            sel = sel[cut]
            ts, xs = t[sel], xyz[sel]
    sig_sel = None if sigma is None else sigma[sel]
    try:
        kw = dict(
            drag=drag,
            lift=lift,
            fit_drag=fit_drag,
            contact_prior=cs / 1000.0,
            post=post,
            t_hint=t_hint,
            mark_params=mark_params,
        )
        fit = fit_track(ts, xs, sig_sel, params, surf, window=tuple(w), **kw)
    except InputError as exc:
        if strict:
            raise
        return review_call([str(exc)], params, surf, net=net_d, n_points=int(n_all), track=(t, xyz), time_offset=t_ref)
    reasons = quality_reasons(fit, ts, noise) + extra_reasons
    mark = None
    decision = None
    loc = None
    if not any(r.startswith("fit diverged") for r in reasons):
        pre_t = ts[ts < fit.t_bounce]  # every sample, the whole fit's outliers too: the window judges them afresh
        near = pre_t.size >= 6 and fit.t_bounce - pre_t.max() <= AUTO_GAP
        loc = refine_bounce(fit, ts, xs, noise, post=fit.has_post and not near)
        if loc is not None:
            reasons = quality_reasons(fit, ts, noise, loc) + extra_reasons
    if loc is not None:
        fit = replace(
            fit,
            p=_local_params(fit.p, loc.p),
            bounce_cov=loc.bounce_cov + MODEL_SIGMA**2 * np.eye(2),
        )
    if not any(r.startswith("fit diverged") for r in reasons) and np.all(np.isfinite(fit.velocity_out)):
        mark = ball_mark(fit.bounce_xy, fit.velocity_in, fit.velocity_out, fit.spin_in, surf, params.ball, mark_params)
        decision = call_mark(
            mark, court=params.court, target=target, line=line, bounce_cov=fit.bounce_cov, n_samples=n_samples
        )
    elif not reasons:
        reasons.append("fit diverged: no outgoing velocity")
    provisional = None if decision is None else decision["call"]
    if decision is not None and REVIEW_P[0] < decision["p_in"] < REVIEW_P[1]:
        reasons.append(f"too close to call: p_in = {decision['p_in']:.2f}")
    call = "review" if reasons else str(provisional)
    notes: tuple[str, ...] = ()
    if not reasons and serve and net is not None and net.contact and provisional == "in":
        call = "let"
    if fit.bounce_xy[0] * direction < 0.0 and _crosses_net(ts, xs, direction) is False:
        # the first contact is on the side the ball comes from: out whatever its mark touches
        call, provisional, reasons, notes = "out", "out", [], (OWN_SIDE,)
        decision = {**(decision or {}), "call": "out", "p_in": 0.0}
    elapsed = time.perf_counter() - t0_clock
    spin = spin_components(fit.spin_in, fit.velocity_in, fit.param_cov([6, 7, 8]), tracker_spin_rpm)
    return TrackCall(
        method="track-fit",
        call=call,
        provisional_call=provisional,
        review_reasons=tuple(reasons),
        notes=notes,
        decision=decision,
        bounce=BounceEstimate.from_fit(fit, t_ref),
        mark=None if mark is None else mark.to_dict(),
        fit=fit_entry(fit, n_all, elapsed, noise, loc),
        spin=spin,
        net=net_d,
        later_bounces=tuple(later),
        surface=surf.name,
        physics=params.to_dict(),
        fit_result=fit,
        mark_result=mark,
        track=(ts, xs),
        time_offset=t_ref,
    )


def call_state(
    position,
    velocity,
    spin=(0.0, 0.0, 0.0),
    *,
    params: FlightParams | None = None,
    surface="hard",
    line: str | None = None,
    target: str | None = None,
    method: str = "numeric",
    net: str = DEFAULT_NET,
) -> TrackCall:
    """Call the landing of a ball flown from a state: numerically (``method="numeric"``) or by seed
    001's closed form (``"closed-form"``: its drop point with the numerical landing velocity).

    ``net``: ``obstacle`` (default, as :func:`tennislab.trajectory.fly`) calls a ball that meets the
    net ``net`` (no bounce); ``through`` lets it pass, as the seeds' models do."""
    params = with_net(params, net)
    surf = get_surface(surface)
    if method not in ("numeric", "closed-form"):
        raise InputError(f"method: unknown {method!r}; allowed: numeric, closed-form")
    position = check_vector("position", position)
    velocity = check_vector("velocity", velocity)
    spin = check_vector("spin", spin)
    tr = fly_dense(position, velocity, spin, params)
    dp = closed_form_from_physics(position, velocity, spin, params) if method == "closed-form" else None
    if tr.net_contact is not None:
        return _net_call(tr, params, surf, method)
    if tr.landing is None:
        raise InputError(f"flight: the ball does not land within t_max = {params.t_max:g} s (no bounce in range)")
    land = tr.landing
    extra: dict = {}
    if dp is not None:
        pos = np.array([dp.x, dp.y])
        t_land = dp.t
        extra["closed_form"] = dp.to_dict()
        extra["numeric"] = {"x": land.x, "y": land.y, "t": land.t}
        extra["closed_form_error_mm"] = float(np.hypot(dp.x - land.x, dp.y - land.y) * 1000)
    else:
        pos = land.position[:2]
        t_land = land.t
    b = bounce(land.velocity, land.spin, surf, params.ball)
    mark = ball_mark(pos, land.velocity, b.velocity_out, land.spin, surf, params.ball)
    decision = call_mark(mark, court=params.court, target=target, line=line)
    bnc = BounceEstimate(
        x=float(pos[0]),
        y=float(pos[1]),
        t=float(t_land),
        sigma_mm=0.0,
        velocity_in=land.velocity,
        spin_in=land.spin,
        velocity_out=b.velocity_out,
        spin_out=b.spin_out,
        mode=b.mode,
    )
    return TrackCall(
        method=method,
        call=decision["call"],
        surface=surf.name,
        physics=params.to_dict(),
        provisional_call=decision["call"],
        decision=decision,
        bounce=bnc,
        mark=mark.to_dict(),
        spin=spin_components(land.spin, land.velocity),
        extra=extra,
        mark_result=mark,
    )


def _net_call(tr, params: FlightParams, surf, method: str) -> TrackCall:
    """The call of a flown state that meets the net: ``net``, where it met it, no bounce."""
    c = tr.net_contact
    net = {
        "checked": True,
        "contact": True,
        "crossed": False,
        "t": c.t,
        "y": c.y,
        "z": c.z,
        "clearance_m": tr.net.clearance,
        "deviation_m": None,
        "note": f"flown into the net ({c.part})",
    }
    return TrackCall(
        method=method, call="net", surface=surf.name, physics=params.to_dict(), provisional_call="net", net=net
    )


def call_detections(cameras, detections: dict, **kwargs) -> TrackCall:
    """Triangulate 2-D detections from calibrated cameras and call the track (:func:`call_track`'s
    keyword arguments).  ``cameras``: :class:`~tennislab.linecall.cameras.Camera` objects or the plain
    camera records of :func:`tennislab.io.cameras.parse_cameras`."""
    cams = cameras_from_records(cameras)
    t, xyz, sig = triangulate_detections(cams, detections)
    res = call_track(t, xyz, sig, **kwargs)
    extra = dict(res.extra)
    extra["cameras"] = {"n_cameras": len(cams), "n_triangulated": int(t.size)}
    return replace(res, extra=extra)
