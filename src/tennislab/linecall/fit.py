"""Robust fit of the physical flight model to a 3-D ball track, through the bounce.

Unknowns (see :mod:`tennislab.linecall.model`): the first-contact point and time
(x_b, y_b, t_b), the velocity and spin arriving there, the velocity leaving
the ground (when there are points after the bounce) and optionally a drag
scale.  The bounce point is found jointly from both segments: they share
(x_b, y_b, t_b), the post-bounce flight starting where the contact model puts
it.  Spin out is the bounce model's (surface), not fitted.

Procedure:

1. Split the track at its lowest point (running median of z); quadratic fits
   of each segment give the starting values (bounce where the pre-bounce
   quadratic reaches z = r).
2. ``scipy.optimize.least_squares`` (trust-region reflective) on residuals
   weighted by 1/sigma, with the robust soft-L1 loss, and a compiled
   forward-difference Jacobian.  A weak prior (sigma 500 rad/s) on each spin
   component keeps the spin along the velocity (unobservable but for the
   spin dependence of C_D) from wandering.
3. Iterative outlier rejection: points whose 3-D normalised residual exceeds
   4 are dropped, segments are reassigned from the fitted t_b (points inside
   the contact are not used), and the fit is repeated with the plain
   least-squares loss until nothing changes (at most 5 rounds).
4. Covariance (J^T J)^-1 scaled by max(1, chi^2 per dof); without a sigma
   column the noise is estimated from the residuals (1.4826 MAD).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from tennislab.core.bounce import bounce
from tennislab.core.flight import FlightParams
from tennislab.core.mark import MarkParams
from tennislab.core.surfaces import get_surface
from tennislab.errors import InputError
from tennislab.linecall import model as M

SPIN_PRIOR = 500.0          #: [rad/s] sigma of the weak zero-mean prior on each spin component
OUTLIER_SIGMA = 4.0         #: normalised 3-D residual above which a point is an outlier
MIN_PRE_POINTS = 6          #: fewest points before the bounce
MIN_POST_POINTS = 4         #: fewest points after the bounce to fit the outgoing velocity
STEPS = np.array([1e-6, 1e-6, 1e-7, 1e-6, 1e-6, 1e-6, 1e-3, 1e-3, 1e-3, 1e-6, 1e-6, 1e-6, 1e-6])


@dataclass(frozen=True)
class TrackFit:
    """Result of :func:`fit_track` (SI units).

    ``p`` is the full parameter vector (see :mod:`model`), ``cov`` the covariance of
    the free parameters ``free`` (indices into p); ``bounce_cov`` the 2x2
    covariance of (x_b, y_b) [m^2].  ``segment`` labels each point (0 before the
    bounce, 1 after, -1 unused: in the contact or an outlier); ``outlier`` marks
    rejected points; ``residual`` the 3-D residual of each point [m].
    """

    p: np.ndarray
    free: np.ndarray
    cov: np.ndarray
    bounce_cov: np.ndarray
    sigma: np.ndarray
    segment: np.ndarray
    outlier: np.ndarray
    residual: np.ndarray
    rms: float
    chi2_dof: float
    has_post: bool
    spin_out: np.ndarray
    n_iter: int
    params: FlightParams = field(repr=False)
    surface: object = field(repr=False)
    mark_params: MarkParams = field(repr=False)

    @property
    def bounce_xy(self) -> np.ndarray:
        return self.p[0:2].copy()

    @property
    def t_bounce(self) -> float:
        return float(self.p[2])

    @property
    def velocity_in(self) -> np.ndarray:
        return self.p[3:6].copy()

    @property
    def spin_in(self) -> np.ndarray:
        return self.p[6:9].copy()

    @property
    def velocity_out(self) -> np.ndarray:
        return self.p[9:12].copy()

    @property
    def drag_scale(self) -> float:
        return float(self.p[12])

    @property
    def sigma_bounce(self) -> float:
        """1-sigma bounce-point uncertainty along its worst direction [m]."""
        ev = np.linalg.eigvalsh(self.bounce_cov)
        return float(math.sqrt(max(ev.max(), 0.0)))

    def positions(self, t) -> np.ndarray:
        """Model positions at times t (pre-bounce before t_b, post-bounce after the contact)."""
        t = np.asarray(t, dtype=float)
        tb, tc = self.p[2], self.mark_params.contact_time
        seg = np.where(t < tb, M.SEG_PRE, np.where(t > tb + tc, M.SEG_POST, M.SEG_OFF))
        if not self.has_post:
            seg = np.where(seg == M.SEG_POST, M.SEG_OFF, seg)
        return M.positions(self.p, t, seg, self.params, self.surface, tc)


def _running_median(z, w=5):
    n = z.size
    if n < w:
        return z.copy()
    pad = np.pad(z, (w // 2, w // 2), mode="edge")
    return np.median(np.lib.stride_tricks.sliding_window_view(pad, w), axis=1)


def _robust_poly(t, y, deg=2):
    """Least-squares polynomial with one round of 5-MAD outlier removal."""
    c = np.polyfit(t, y, deg)
    r = y - np.polyval(c, t)
    mad = 1.4826 * np.median(np.abs(r - np.median(r))) + 1e-9
    keep = np.abs(r) < 5 * mad + 1e-6
    if keep.sum() > deg + 2 and not keep.all():
        c = np.polyfit(t[keep], y[keep], deg)
    return c


def initial_guess(t, xyz, params: FlightParams, surface, contact_time: float):
    """Starting parameters (13,) and whether there are usable post-bounce points."""
    r = params.ball.radius
    z = _running_median(xyz[:, 2])
    i_min = int(np.argmin(z))
    n = t.size
    if i_min < MIN_PRE_POINTS - 1:
        raise InputError(f"track: no bounce in range: only {i_min + 1} point(s) before the lowest point "
                         f"(need {MIN_PRE_POINTS} before the bounce)")
    pre = np.arange(0, i_min + 1)
    post = np.arange(i_min + 1, n)
    # the last pre points describe the approach best; a quadratic over <= 0.25 s
    sel = pre[t[pre] >= t[pre[-1]] - 0.25]
    if sel.size < MIN_PRE_POINTS:
        sel = pre[-MIN_PRE_POINTS:]
    t0 = t[sel[-1]]
    cz = _robust_poly(t[sel] - t0, xyz[sel, 2])
    cx = _robust_poly(t[sel] - t0, xyz[sel, 0])
    cy = _robust_poly(t[sel] - t0, xyz[sel, 1])
    roots = np.roots(cz - np.array([0, 0, r]))
    roots = np.real(roots[np.abs(np.imag(roots)) < 1e-9])
    dz = np.polyder(cz)
    cand = [x for x in roots if np.polyval(dz, x) < 0 and x > -0.05]
    if not cand:
        raise InputError("track: no bounce in range: the ball does not come down to the ground")
    tau = min(cand)
    horizon = max(0.5, 0.5 * (t[-1] - t[0]))
    if tau > horizon + (t[-1] - t0):
        raise InputError(f"track: no bounce in range: the ball would land {tau:.2f} s after the last point "
                         f"before its lowest point")
    p = np.zeros(M.NPARAM)
    p[0] = np.polyval(cx, tau)
    p[1] = np.polyval(cy, tau)
    p[2] = t0 + tau
    p[3] = np.polyval(np.polyder(cx), tau)
    p[4] = np.polyval(np.polyder(cy), tau)
    p[5] = np.polyval(dz, tau)
    p[12] = 1.0
    post = post[t[post] > p[2] + contact_time]
    has_post = post.size >= MIN_POST_POINTS
    if has_post:
        selp = post[t[post] <= t[post[0]] + 0.25]
        if selp.size < MIN_POST_POINTS:
            selp = post[:MIN_POST_POINTS]
        deg = 2 if selp.size >= 6 else 1
        tt = p[2] + contact_time
        for c in range(3):
            cc = _robust_poly(t[selp] - tt, xyz[selp, c], deg)
            p[9 + c] = np.polyval(np.polyder(cc), 0.0)
        if p[11] <= 0:
            has_post = False
    if not has_post:
        p[9:12] = bounce(p[3:6], p[6:9], surface, params.ball).velocity_out
    return p, has_post


def _segments(t, tb, tc, has_post, outlier):
    seg = np.where(t < tb, M.SEG_PRE, np.where(t > tb + tc, M.SEG_POST, M.SEG_OFF))
    if not has_post:
        seg = np.where(seg == M.SEG_POST, M.SEG_OFF, seg)
    seg = np.where(outlier, M.SEG_OFF, seg)
    return seg.astype(np.int64)


def _solve(fun, jac, x0, loss):
    return least_squares(fun, x0, jac=jac, method="trf", loss=loss, f_scale=2.0, x_scale="jac",
                         xtol=1e-9, ftol=1e-9, gtol=1e-9, max_nfev=100)


def fit_track(t, xyz, sigma=None, params: FlightParams | None = None, surface="hard", *,
              fit_drag: bool = False, mark_params: MarkParams = MarkParams(), step: float = 4e-3,
              max_rounds: int = 5, window: tuple | None = (0.6, 0.3)) -> TrackFit:
    """Fit the flight model to a track (see the module docstring).

    t : (N,) strictly increasing times [s]; xyz : (N, 3) ball-centre positions [m];
    sigma : (N,) per-point 1-sigma 3-D noise per axis [m] or None (estimated);
    params : :class:`FlightParams`; surface : bounce surface (spin out, contact
    displacement); fit_drag : also fit a drag scale; window : (before, after) [s]
    around the first bounce estimate: only points in it are fitted (None: all).
    Points outside the window get segment -1 and residual NaN.
    """
    params = params or FlightParams()
    s = get_surface(surface)
    t = np.ascontiguousarray(t, dtype=np.float64)
    xyz = np.ascontiguousarray(xyz, dtype=np.float64)
    n = t.size
    tc = mark_params.contact_time
    p, has_post = initial_guess(t, xyz, params, s, tc)
    n_all = n
    rows = np.arange(n)
    if window is not None:
        keep = (t >= p[2] - window[0]) & (t <= p[2] + window[1])
        if np.count_nonzero(keep & (t < p[2])) >= MIN_PRE_POINTS:
            t, xyz, rows = t[keep], xyz[keep], rows[keep]
            if sigma is not None:
                sigma = np.asarray(sigma, dtype=np.float64)[keep]
            if has_post and np.count_nonzero(t > p[2] + tc) < MIN_POST_POINTS:  # pragma: no cover
                has_post = False
        n = t.size
    est_sigma = sigma is None
    sig = np.full(n, 3e-3) if est_sigma else np.asarray(sigma, dtype=np.float64)
    consts = M.make_consts(params, s, tc, step)
    kern, ap = params.aero.kernel, params.aero.params
    outlier = np.zeros(n, dtype=bool)
    free_list = list(range(9)) + ([9, 10, 11] if has_post else []) + ([12] if fit_drag else [])
    free = np.array(free_list, dtype=np.int64)
    spin_cols = [j for j, f in enumerate(free_list) if 6 <= f <= 8]
    pos = np.empty((n, 3))
    res = np.empty(3 * n)
    seg = _segments(t, p[2], tc, has_post, outlier)
    n_iter = 0
    state = {"seg": seg, "w": 1.0 / sig}

    def fun(x):
        q = p.copy()
        q[free] = x
        M.residuals(q, t, xyz, state["w"], state["seg"], kern, ap, consts, res, pos)
        prior = q[6:9] / SPIN_PRIOR
        return np.concatenate([res, prior])

    def jac(x):
        q = p.copy()
        q[free] = x
        base = np.empty(3 * n)
        M.residuals(q, t, xyz, state["w"], state["seg"], kern, ap, consts, base, pos)
        J = np.empty((3 * n, free.size))
        M.jacobian(q, free, STEPS, t, xyz, state["w"], state["seg"], kern, ap, consts, base, J)
        Jp = np.zeros((3, free.size))
        for i, c in enumerate(spin_cols):
            Jp[i, c] = 1.0 / SPIN_PRIOR
        return np.vstack([J, Jp])

    loss = "soft_l1"
    sol = None
    for rnd in range(max_rounds):
        sol = _solve(fun, jac, p[free], loss)
        n_iter += sol.nfev
        if rnd == 0 and spin_cols:
            # The spin component along the velocity is seen only through the turning of the
            # velocity: its sign can hide in a second minimum.  Restart with it reflected.
            q = p.copy()
            q[free] = sol.x
            vh = q[3:6] / np.linalg.norm(q[3:6])
            q[6:9] -= 2.0 * np.dot(q[6:9], vh) * vh
            alt = _solve(fun, jac, q[free], loss)
            n_iter += alt.nfev
            if alt.cost < sol.cost:
                sol = alt
        p[free] = sol.x
        nat = _segments(t, p[2], tc, has_post, np.zeros(n, dtype=bool))
        pos_all = np.full((n, 3), np.nan)
        M.model_positions(p, t, nat, kern, ap, consts, pos_all, True, True)
        r3 = pos_all - xyz
        usable = nat != M.SEG_OFF
        used = usable & ~outlier
        if est_sigma and used.any():
            comp = r3[used].ravel()
            s_est = 1.4826 * np.median(np.abs(comp - np.median(comp)))
            sig = np.full(n, max(s_est, 1e-5))
            state["w"] = 1.0 / sig
        norm = np.where(usable, np.linalg.norm(np.nan_to_num(r3), axis=1) / sig, 0.0)
        new_out = usable & (norm > OUTLIER_SIGMA)
        new_seg = _segments(t, p[2], tc, has_post, new_out)
        if loss == "linear" and np.array_equal(new_seg, state["seg"]):
            break
        outlier = new_out
        state["seg"] = new_seg
        loss = "linear"
    if np.count_nonzero(state["seg"] == M.SEG_PRE) < MIN_PRE_POINTS:
        raise InputError(f"track: too few usable points before the bounce (need {MIN_PRE_POINTS})")
    # final residuals and covariance
    M.residuals(p, t, xyz, state["w"], state["seg"], kern, ap, consts, res, pos)
    J = jac(p[free])
    used = state["seg"] != M.SEG_OFF
    nres = 3 * np.count_nonzero(used)
    dof = max(nres - free.size, 1)
    chi2 = float(np.sum(res ** 2)) / dof
    try:
        cov = np.linalg.pinv(J.T @ J) * max(1.0, chi2)
    except np.linalg.LinAlgError:  # pragma: no cover
        cov = np.full((free.size, free.size), np.nan)
    nat = _segments(t, p[2], tc, has_post, np.zeros(n, dtype=bool))
    pos_all = np.full((n, 3), np.nan)
    M.model_positions(p, t, nat, kern, ap, consts, pos_all, True, True)
    r3 = np.linalg.norm(pos_all - xyz, axis=1)
    rms = float(math.sqrt(np.mean(r3[used] ** 2))) if used.any() else float("nan")
    # bounce-point covariance, including t_b's correlation (the point is at fixed t_b)
    bc = cov[:2, :2].copy()
    spin_out = bounce(p[3:6], p[6:9], s, params.ball).spin_out
    seg_all = np.full(n_all, M.SEG_OFF, dtype=np.int64)
    seg_all[rows] = state["seg"]
    out_all = np.zeros(n_all, dtype=bool)
    out_all[rows] = outlier
    r3_all = np.full(n_all, np.nan)
    r3_all[rows] = r3
    sig_all = np.full(n_all, np.nan)
    sig_all[rows] = sig
    return TrackFit(p.copy(), free, cov, bc, sig_all, seg_all, out_all, r3_all, rms, chi2,
                    has_post, spin_out, n_iter, params, s, mark_params)
