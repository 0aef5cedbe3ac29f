"""Robust fit of the physical flight model to a 3-D ball track, through the bounce.

Unknowns (see :mod:`tennislab.linecall.model`): the first-contact point and time
(x_b, y_b, t_b), the velocity and spin arriving there, the velocity leaving
the ground (when there are points after the bounce) and optionally a drag
scale.  The bounce point is found jointly from both segments: they share
(x_b, y_b, t_b), and the post-bounce flight starts where the contact model puts
it: the centre travels during the contact (T_c = 4.5 ms) by the closed form of
:func:`~tennislab.core.mark.contact_displacement`, and the spin out follows
from the fitted velocities by the impulse relation of the bounce model, so the
surface enters only through mu, and only for a ball that grips (a fitted
bounce that slid throughout uses the mu its velocities imply).  With
``contact_prior`` > 0 [s] the travel gets a free offset (prior sigma
contact_prior x horizontal speed, i.e. an uncertain T_c) and the spin out a
free offset (prior sigma 150 rad/s): robust to a wrong contact model, at the
cost of most of the post-bounce information (docs/linecall.md).

Procedure:

1. Split the track at its lowest point (running median of z); quadratic fits
   of each segment give the starting values (bounce where the pre-bounce
   quadratic reaches z = r).
2. Levenberg-Marquardt (:func:`_levenberg_marquardt`) on residuals weighted
   by 1/sigma, with the robust soft-L1 loss on each point's 3-D residual and a
   compiled forward-difference Jacobian; the normal equations are accumulated
   by a compiled loop (no multi-threaded BLAS call, which on a busy machine
   cost 10x the fit itself).  A weak prior (sigma 500 rad/s) on each spin
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

from tennislab.core.bounce import bounce
from tennislab.core.flight import FlightParams
from tennislab.core.mark import MarkParams
from tennislab.core.surfaces import get_surface
from tennislab.errors import InputError
from tennislab.linecall import model as M

SPIN_PRIOR = 500.0  #: [rad/s] sigma of the weak zero-mean prior on each spin component
CONTACT_PRIOR = 0.3e-3  #: [s] suggested sigma of T_c (4-5 ms, Brody [S]: uniform -> 0.29 ms)
SPIN_OUT_PRIOR = 150.0  #: [rad/s] sigma of the offset of the spin out from the bounce model
#: zero-mean Gaussian priors (sigma) on parameters, by parameter index
PRIOR_SIGMA = {6: SPIN_PRIOR, 7: SPIN_PRIOR, 8: SPIN_PRIOR, 15: SPIN_OUT_PRIOR, 16: SPIN_OUT_PRIOR, 17: SPIN_OUT_PRIOR}
MIN_CONTACT_SIGMA = 1e-3  #: [m] floor of the contact-travel prior (slow balls)
OUTLIER_SIGMA = 4.0  #: normalised 3-D residual above which a point is an outlier
MIN_PRE_POINTS = 6  #: fewest points before the bounce
MIN_POST_POINTS = 4  #: fewest points after the bounce to fit the outgoing velocity
STEPS = np.array(
    [1e-6, 1e-6, 1e-7, 1e-6, 1e-6, 1e-6, 1e-3, 1e-3, 1e-3, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-3, 1e-3, 1e-3]
)


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
    def contact_offset(self) -> np.ndarray:
        """Fitted offset of the ball's travel during the contact from the contact model [m]."""
        return self.p[13:15].copy()

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
    """Starting parameters (NPARAM,) and whether there are usable post-bounce points."""
    r = params.ball.radius
    z = _running_median(xyz[:, 2])
    i_min = int(np.argmin(z))
    n = t.size
    if i_min < MIN_PRE_POINTS - 1:
        raise InputError(
            f"track: no bounce in range: only {i_min + 1} point(s) before the lowest point "
            f"(need {MIN_PRE_POINTS} before the bounce)"
        )
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
        raise InputError(
            f"track: no bounce in range: the ball would land {tau:.2f} s after the last point before its lowest point"
        )
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


ROBUST_SCALE = 2.0  #: soft-L1 scale of the first round [sigma]
COST_TOL = 1e-3  #: stop when an iteration lowers the cost (chi^2) by less than this


def _levenberg_marquardt(
    p, free, x0, t, xyz, w, seg, kern, ap, consts, prior_idx, prior_sig, robust: bool, max_iter: int = 60
):
    """Minimise the (robust) cost over p[free] from x0.  Returns (x, cost, model evaluations).

    Levenberg-Marquardt with Marquardt's diagonal scaling (More 1978) on the normal equations
    (accumulated by a compiled loop), soft-L1 loss by iteratively reweighting each point by
    rho'(z) = 1/sqrt(1 + z), z = |r_i|^2 / f^2 (Triggs et al. 2000, sec. 6.8) when ``robust``.
    """
    n = t.size
    npar = free.size
    res = np.empty(3 * n)
    pos = np.empty((n, 3))
    J = np.empty((3 * n, npar))
    A = np.empty((npar, npar))
    g = np.empty(npar)
    q = p.copy()

    def cost_of(x):
        q[free] = x
        M.residuals(q, t, xyz, w, seg, kern, ap, consts, res, pos)
        r2 = (res.reshape(-1, 3) ** 2).sum(axis=1)
        if robust:
            c = float(np.sum(2.0 * ROBUST_SCALE**2 * (np.sqrt(1.0 + r2 / ROBUST_SCALE**2) - 1.0)))
        else:
            c = float(np.sum(r2))
        return c + float(np.sum((x[prior_idx] / prior_sig) ** 2)), r2

    x = np.array(x0, dtype=float)
    cost, r2 = cost_of(x)
    nev = 1
    lam = 1e-3
    for _ in range(max_iter):
        q[free] = x
        M.jacobian(q, free, STEPS, t, xyz, w, seg, kern, ap, consts, res, J)
        nev += npar
        wpt = 1.0 / np.sqrt(1.0 + r2 / ROBUST_SCALE**2) if robust else np.ones(n)
        M.normal_equations(J, res, wpt, A, g)
        for j, sj in zip(prior_idx, prior_sig):
            A[j, j] += 1.0 / sj**2
            g[j] += x[j] / sj**2
        d = np.maximum(np.diag(A).copy(), 1e-30)
        improved = False
        for _ in range(12):
            try:
                step = -np.linalg.solve(A + lam * np.diag(d), g)
            except np.linalg.LinAlgError:
                lam *= 10.0
                continue
            xn = x + step
            cn, r2n = cost_of(xn)
            nev += 1
            if np.isfinite(cn) and cn < cost:
                improved = True
                break
            lam *= 10.0
        if not improved:
            cost_of(x)  # restore the residual buffer at x
            break
        gain = cost - cn
        small = np.all(np.abs(step) <= 1e-10 + 1e-9 * np.abs(x))
        x, cost, r2 = xn, cn, r2n
        lam = max(lam / 10.0, 1e-12)
        if gain < COST_TOL or small:  # cost is chi^2: a gain of 1e-3 moves parameters by ~0.03 sigma
            break
    return x, cost, nev


def fit_track(
    t,
    xyz,
    sigma=None,
    params: FlightParams | None = None,
    surface="hard",
    *,
    fit_drag: bool = False,
    mark_params: MarkParams = MarkParams(),
    step: float = 8e-3,
    max_rounds: int = 5,
    window: tuple | None = (0.6, 0.3),
    contact_prior: float = 0.0,
) -> TrackFit:
    """Fit the flight model to a track (see the module docstring).

    t : (N,) strictly increasing times [s]; xyz : (N, 3) ball-centre positions [m];
    sigma : (N,) per-point 1-sigma 3-D noise per axis [m] or None (estimated);
    params : :class:`FlightParams`; surface : bounce surface (spin out, contact
    displacement); fit_drag : also fit a drag scale; contact_prior : sigma [s] of the
    contact time, which sets the prior of the offset of the contact travel from the
    contact model (sigma = contact_prior x mean horizontal speed, at least 1 mm; 0: trust
    the contact model and the bounce model's spin out exactly); window : (before, after) [s]
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
    free_list = (
        list(range(9))
        + ([9, 10, 11] if has_post else [])
        + ([12] if fit_drag else [])
        + (list(range(13, 18)) if has_post and contact_prior > 0 else [])
    )
    free = np.array(free_list, dtype=np.int64)
    pos = np.empty((n, 3))
    seg = _segments(t, p[2], tc, has_post, outlier)
    n_iter = 0
    w = 1.0 / sig
    spin_idx = np.array([j for j, f in enumerate(free_list) if 6 <= f <= 8], dtype=np.int64)
    prior_idx = np.array([j for j, f in enumerate(free_list) if f in PRIOR_SIGMA], dtype=np.int64)
    psig = dict(PRIOR_SIGMA)
    if contact_prior > 0:  # travel = T_c x mean horizontal speed: its sigma scales with the speed
        vmean = 0.5 * (np.hypot(p[3], p[4]) + np.hypot(p[9], p[10]))
        psig[13] = psig[14] = max(float(contact_prior) * vmean, MIN_CONTACT_SIGMA)
    prior_sig = np.array([psig[free_list[j]] for j in prior_idx])

    def solve(x0, seg, w, robust):
        return _levenberg_marquardt(p, free, x0, t, xyz, w, seg, kern, ap, consts, prior_idx, prior_sig, robust)

    robust = True
    for rnd in range(max_rounds):
        x, cost, nev = solve(p[free], seg, w, robust)
        n_iter += nev
        q = p.copy()
        q[free] = x
        along = abs(np.dot(q[6:9], q[3:6])) / np.linalg.norm(q[3:6])
        if rnd == 0 and spin_idx.size and along > 10.0:
            # The spin component along the velocity is seen only through the turning of the
            # velocity: its sign can hide in a second minimum.  Restart with it reflected.
            vh = q[3:6] / np.linalg.norm(q[3:6])
            q[6:9] -= 2.0 * np.dot(q[6:9], vh) * vh
            x2, cost2, nev2 = solve(q[free], seg, w, robust)
            n_iter += nev2
            if cost2 < cost:
                x, cost = x2, cost2
        p[free] = x
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
            w = 1.0 / sig
        norm = np.where(usable, np.linalg.norm(np.nan_to_num(r3), axis=1) / sig, 0.0)
        new_out = usable & (norm > OUTLIER_SIGMA)
        new_seg = _segments(t, p[2], tc, has_post, new_out)
        if not robust and np.array_equal(new_seg, seg):
            break
        outlier = new_out
        seg = new_seg
        robust = False
    state = {"seg": seg, "w": w}
    if np.count_nonzero(state["seg"] == M.SEG_PRE) < MIN_PRE_POINTS:
        raise InputError(f"track: too few usable points before the bounce (need {MIN_PRE_POINTS})")
    # final residuals and covariance
    res = np.empty(3 * n)
    M.residuals(p, t, xyz, state["w"], state["seg"], kern, ap, consts, res, pos)
    J = np.empty((3 * n, free.size))
    M.jacobian(p, free, STEPS, t, xyz, state["w"], state["seg"], kern, ap, consts, res, J)
    A = np.empty((free.size, free.size))
    g = np.empty(free.size)
    M.normal_equations(J, res, np.ones(n), A, g)
    for j, sj in zip(prior_idx, prior_sig):
        A[j, j] += 1.0 / sj**2
    used = state["seg"] != M.SEG_OFF
    nres = 3 * np.count_nonzero(used)
    dof = max(nres - free.size, 1)
    chi2 = float(np.sum(res**2)) / dof
    try:
        cov = np.linalg.inv(A) * max(1.0, chi2)
    except np.linalg.LinAlgError:
        cov = np.linalg.pinv(A) * max(1.0, chi2)
    nat = _segments(t, p[2], tc, has_post, np.zeros(n, dtype=bool))
    pos_all = np.full((n, 3), np.nan)
    M.model_positions(p, t, nat, kern, ap, consts, pos_all, True, True)
    r3 = np.linalg.norm(pos_all - xyz, axis=1)
    rms = float(math.sqrt(np.mean(r3[used] ** 2))) if used.any() else float("nan")
    # bounce-point covariance (marginal over every other parameter, t_b included)
    bc = cov[:2, :2].copy()
    if not has_post:  # no data after the bounce: the bounce model gives the outgoing velocity
        p[9:12] = bounce(p[3:6], p[6:9], s, params.ball).velocity_out
    y_out = np.empty(9)
    M.post_start(p, consts, y_out)
    spin_out = y_out[6:9].copy()
    seg_all = np.full(n_all, M.SEG_OFF, dtype=np.int64)
    seg_all[rows] = state["seg"]
    out_all = np.zeros(n_all, dtype=bool)
    out_all[rows] = outlier
    r3_all = np.full(n_all, np.nan)
    r3_all[rows] = r3
    sig_all = np.full(n_all, np.nan)
    sig_all[rows] = sig
    return TrackFit(
        p.copy(),
        free,
        cov,
        bc,
        sig_all,
        seg_all,
        out_all,
        r3_all,
        rms,
        chi2,
        has_post,
        spin_out,
        n_iter,
        params,
        s,
        mark_params,
    )
