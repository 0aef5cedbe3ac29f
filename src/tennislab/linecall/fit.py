"""Robust fits of the physical flight model to a 3-D ball track: through the bounce, and free flight.

**Bounce fit** (:func:`fit_track`).  Unknowns (see :mod:`tennislab.linecall.model`): the
first-contact point and time (x_b, y_b, t_b), the velocity and the full spin vector arriving there
(topspin, sidespin and spin along the path: three free components), the velocity leaving the ground
(when there are points after the bounce), and the aerodynamic scales: the drag scale s_D (C_D ->
s_D C_D) and the lift scale s_L (C_L -> s_L C_L), each ``"fixed"`` (1), ``"prior"`` (free with a
Gaussian prior around 1) or ``"free"``.  The bounce point is found jointly from both segments: they
share (x_b, y_b, t_b), and the post-bounce flight starts where the contact model puts it: the centre
travels during the contact (T_c = 4.5 ms) by the closed form of
:func:`~tennislab.core.mark.contact_displacement`, and the spin out follows from the fitted velocities
by the impulse relation of the bounce model.  With ``contact_prior`` > 0 [s] the travel gets a free
offset (prior sigma contact_prior x horizontal speed, i.e. an uncertain T_c) and the spin out a free
offset (prior sigma 150 rad/s).

Defaults and why: the drag scale is free with a prior sigma of :data:`DRAG_PRIOR` (real balls' C_D
differs from any published model by 5-15 %: issue 13 found an effective C_D of 0.60-0.61 on real
serves against Stepanek's ~0.55-0.66); a long, dense track then sets it from the data, a short one
leans on the prior and its uncertainty widens the bounce's.  The lift scale is fixed by default: with
the spin vector free it is degenerate with the spin rate (C_L rises with the spin), so it is only
worth freeing when the spin is known independently.

Procedure:

1. Split the track at its first bounce (``t_hint``, from :func:`tennislab.linecall.track.find_bounces`,
   or the lowest point); quadratic fits of each segment give the starting values.
2. Levenberg-Marquardt (:func:`levenberg_marquardt`) on residuals weighted by 1/sigma, with a robust
   soft-L1 loss on each point's 3-D residual in the first round, a compiled forward-difference
   Jacobian and compiled normal equations (no multi-threaded BLAS call).  Weak priors: sigma
   :data:`SPIN_PRIOR` on each spin component (the spin along the velocity is seen only through the
   turning of the velocity), the aero-scale priors above.
3. Outlier rejection that cannot cascade and never mistakes a smooth misfit for outliers: at most
   :data:`MAX_ROUNDS` rounds; each round rejects, from *all* usable points afresh, those whose 3-D
   residual, less its running median (:func:`_detrend`: what no smooth misfit explains), exceeds
   :data:`OUTLIER_SIGMA` times a scale (1.4826 MAD of every usable point's detrended residual
   components, the rejected ones included), never below :data:`NOISE_FLOOR` (or the given sigma); at most
   :data:`MAX_REJECT_FRACTION` of the points (the worst) are rejected.  Removing points therefore
   never shrinks the scale they are judged by (before: each round re-estimated the noise from the
   survivors and rejected at 4 sigma again, 32 points -> 13 -> 6 -> 3).
4. Covariance (J^T J)^-1 (priors included) scaled by max(1, chi^2 per dof), and, when the noise is
   estimated, by (1 + 4/dof) for the uncertainty of that estimate (short tracks get wider errors);
   the bounce point's gets the model floor :data:`MODEL_SIGMA` added in quadrature.

The free-flight fit of the net check (:mod:`tennislab.linecall.free_flight`) uses the same solver.

References
----------
.. [1] More, J. J. (1978). The Levenberg-Marquardt algorithm: implementation and theory. Numerical
    Analysis, Lecture Notes in Mathematics 630, 105-116.
.. [2] Triggs, B., McLauchlan, P., Hartley, R. & Fitzgibbon, A. (2000). Bundle adjustment - a modern
    synthesis. Vision Algorithms: Theory and Practice, LNCS 1883, section 6.8 (robust reweighting).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

import tennislab.linecall.model as M
from tennislab.core.bounce import bounce_kernel
from tennislab.core.flight import FlightParams
from tennislab.core.mark import MarkParams
from tennislab.core.surfaces import get_surface
from tennislab.errors import InputError
from tennislab.linecall._lm import lm_bounce
from tennislab.linecall.detect import find_bounces

SPIN_PRIOR = 500.0  #: [rad/s] sigma of the weak zero-mean prior on each spin component
DRAG_PRIOR = 0.15  #: sigma of the prior on the drag scale s_D around 1 (default ``drag="prior"``)
LIFT_PRIOR = 0.3  #: sigma of the prior on the lift scale s_L around 1 (``lift="prior"``)
CONTACT_PRIOR = 0.3e-3  #: [s] suggested sigma of T_c (4-5 ms, Brody [S]: uniform -> 0.29 ms)
SPIN_OUT_PRIOR = 150.0  #: [rad/s] sigma of the offset of the spin out from the bounce model
MIN_CONTACT_SIGMA = 1e-3  #: [m] floor of the contact-travel prior (slow balls)
OUTLIER_SIGMA = 4.0  #: normalised 3-D residual above which a point is an outlier
NOISE_FLOOR = 1.5e-3  #: [m] smallest per-axis scale outliers are judged against
MAX_REJECT_FRACTION = 0.25  #: largest fraction of the usable points rejected as outliers
MAX_ROUNDS = 3  #: fit / reject rounds
#: [m] per-axis model error added to the bounce covariance: the error of the fit itself when the truth
#: flies with another aero model (cross2014 C_D 0.6, C_L 0.6 S; noise-free, 40 shots, 50 and 340 Hz:
#: median 0.5 mm, p90 1.7-2.4 mm, RMS 1.3 mm in 2-D); without it a smooth track's sigma shrinks to
#: 0.1 mm and understates the error fivefold.  A lower bound for real balls.
MODEL_SIGMA = 1.0e-3
MIN_PRE_POINTS = 3  #: fewest points before the bounce (fewer than 6: the spin leans on its prior)
MIN_POST_POINTS = 3  #: fewest points after the bounce to fit the outgoing velocity
AERO_MODES = ("fixed", "prior", "free")
POST_MODES = ("auto", "joint", "loose", "off")
AUTO_GAP = 0.05  #: [s] ``post="auto"``: the approach alone places the bounce when it is sampled this close to it
POST_DRAG_PRIOR = 0.2  #: sigma of the prior on the post-bounce drag ratio (``post="loose"``)
STEPS = np.array(
    [1e-6, 1e-6, 1e-7, 1e-6, 1e-6, 1e-6, 1e-3, 1e-3, 1e-3, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-3, 1e-3, 1e-3]
    + [1e-6, 1e-6]
)
FREE_STEPS = np.array([1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-3, 1e-3, 1e-3, 1e-6, 1e-6])
ROBUST_SCALE = 2.0  #: soft-L1 scale of the first round [sigma]
COST_TOL = 1e-3  #: stop when an iteration lowers the cost (chi^2) by less than this
MAX_ITER = 60  #: Levenberg-Marquardt iterations per round
#: [s] default (before, after) window of the fit around the bounce: the whole flight from the hit,
#: 0.3 s after (the spin and the drag scale are seen over the whole flight; where the ball lands is
#: then placed by the local refits of :mod:`tennislab.linecall.local_fit`)
WHOLE_FLIGHT = (30.0, 0.3)
STAGE_WINDOW = 0.6  #: [s] a fit over a longer window starts from a fit of this long before the bounce


@dataclass(frozen=True)
class TrackFit:
    """Result of :func:`fit_track` (SI units).

    ``p`` is the full parameter vector (see :mod:`model`), ``cov`` the covariance of
    the free parameters ``free`` (indices into p); ``bounce_cov`` the 2x2
    covariance of (x_b, y_b) [m^2].  ``segment`` labels each point (0 before the
    bounce, 1 after, -1 unused: in the contact, outside the window or an outlier); ``outlier`` marks
    rejected points; ``residual`` the 3-D residual of each point [m].  ``p_start`` is the starting
    guess (from quadratic fits of the data); ``noise`` the per-axis scale outliers were judged
    against [m]; ``rejection_capped`` says that more points than :data:`MAX_REJECT_FRACTION` looked
    like outliers; ``converged`` that the last round ended on a small step or gain.
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
    p_start: np.ndarray = field(default_factory=lambda: np.zeros(M.NPARAM), repr=False)
    noise: float = float("nan")
    rejection_capped: bool = False
    converged: bool = True
    n_pre: int = 0
    n_post: int = 0
    vout_source: str = "joint"  #: v_out from the joint fit, a fit of the samples after the bounce, or the bounce model

    @property
    def bounce_xy(self) -> np.ndarray:
        return self.p[M.P_XY].copy()

    @property
    def t_bounce(self) -> float:
        return float(self.p[M.P_TB])

    @property
    def velocity_in(self) -> np.ndarray:
        return self.p[M.P_VIN].copy()

    @property
    def spin_in(self) -> np.ndarray:
        return self.p[M.P_WIN].copy()

    @property
    def velocity_out(self) -> np.ndarray:
        return self.p[M.P_VOUT].copy()

    @property
    def contact_offset(self) -> np.ndarray:
        """Fitted offset of the ball's travel during the contact from the contact model [m]."""
        return self.p[M.P_DXY].copy()

    @property
    def drag_scale(self) -> float:
        return float(self.p[M.P_DRAG])

    @property
    def lift_scale(self) -> float:
        return float(self.p[M.P_LIFT])

    def param_sigma(self, index: int) -> float:
        """1-sigma of parameter ``index`` (0 when it was not free)."""
        hit = np.nonzero(self.free == index)[0]
        if hit.size == 0:
            return 0.0
        v = self.cov[hit[0], hit[0]]
        return float(math.sqrt(v)) if np.isfinite(v) and v >= 0 else float("nan")

    def param_cov(self, indices) -> np.ndarray:
        """Covariance block of the parameters ``indices`` (zero rows for fixed ones)."""
        idx = list(indices)
        out = np.zeros((len(idx), len(idx)))
        pos = {int(f): k for k, f in enumerate(self.free)}
        for a, i in enumerate(idx):
            for b, j in enumerate(idx):
                if i in pos and j in pos:
                    out[a, b] = self.cov[pos[i], pos[j]]
        return out

    @property
    def sigma_bounce(self) -> float:
        """1-sigma bounce-point uncertainty along its worst direction [m]."""
        if not np.all(np.isfinite(self.bounce_cov)):
            return float("nan")
        ev = np.linalg.eigvalsh(self.bounce_cov)
        return float(math.sqrt(max(ev.max(), 0.0)))

    def positions(self, t) -> np.ndarray:
        """Model positions at times t (pre-bounce before t_b, post-bounce after the contact)."""
        t = np.asarray(t, dtype=float)
        tb, tc = self.p[M.P_TB], self.mark_params.contact_time
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


def _robust_poly(t, y, deg=2, rounds: int = 3, floor: float = 0.0):
    """Least-squares polynomial with up to ``rounds`` rounds of 5-MAD outlier removal (degree lowered
    to fit the points); each round judges every point afresh against the fit of the previous one,
    never closer than ``floor`` [m] (a smooth track's own departure from a polynomial is no outlier).
    The first fit leaves out the points far from a 5-sample running median: two gross outliers among
    30 points could otherwise tilt it so far that the rounds keep the outliers and drop the track."""
    deg = min(deg, t.size - 1)
    c = np.polyfit(t, y, deg)
    if t.size >= 7:
        d = y - _running_median(y)
        s = 1.4826 * np.median(np.abs(d - np.median(d)))
        start = np.abs(d) <= max(5 * s, floor, 1e-6)
        if start.sum() > deg + 2 and not start.all():
            c = np.polyfit(t[start], y[start], deg)
    for _ in range(rounds):
        r = y - np.polyval(c, t)
        mad = 1.4826 * np.median(np.abs(r - np.median(r))) + 1e-9
        keep = np.abs(r) < max(5 * mad, floor) + 1e-6
        if keep.sum() <= deg + 2 or keep.all():
            break
        c = np.polyfit(t[keep], y[keep], deg)
    return c


def _bounce_out(vin, win, surface, params: FlightParams) -> np.ndarray:
    """Outgoing velocity of the bounce model; a rising or non-finite incoming velocity gives NaN."""
    if not (np.all(np.isfinite(vin)) and np.all(np.isfinite(win)) and vin[2] < 0):
        return np.full(3, np.nan)
    vout = np.empty(3)
    wout = np.empty(3)
    b = params.ball
    bounce_kernel(
        np.ascontiguousarray(vin, dtype=np.float64),
        np.ascontiguousarray(win, dtype=np.float64),
        b.radius,
        b.inertia_factor,
        surface.e,
        surface.mu,
        surface.e_x,
        vout,
        wout,
    )
    return vout


def _descents(cz: np.ndarray, r: float) -> list[float]:
    """Times (after -0.05 s) at which the polynomial height ``cz`` comes down through z = ``r``."""
    roots = np.roots(cz - np.array([0, 0, r]))
    roots = np.real(roots[np.abs(np.imag(roots)) < 1e-9])
    dz = np.polyder(cz)
    return [float(x) for x in roots if np.polyval(dz, x) < 0 and x > -0.05]


def initial_guess(t, xyz, params: FlightParams, surface, contact_time: float, t_hint: float | None = None):
    """Starting parameters (NPARAM,) and whether there are usable post-bounce points.

    ``t_hint`` [s]: time of the first bounce found in the data (the split point); default the first
    bounce :func:`~tennislab.linecall.detect.find_bounces` finds, else the lowest point of the running
    median of z (a track that ends before its bounce).
    """
    r = params.ball.radius
    n = t.size
    if t_hint is None:
        found = find_bounces(t, xyz)
        t_hint = float(t[found[0]]) if found else None
    if t_hint is not None and np.isfinite(t_hint):
        i_min = int(np.argmin(np.abs(t - t_hint)))
        if t[i_min] > t_hint and i_min > 0:
            i_min -= 1
    else:
        z = _running_median(xyz[:, 2])
        i_min = int(np.argmin(z))
    if i_min < MIN_PRE_POINTS - 1:
        raise InputError(
            f"track: no bounce in range: only {i_min + 1} point(s) before the lowest point "
            f"(need {MIN_PRE_POINTS} before the bounce)"
        )
    pre = np.arange(0, i_min + 1)
    post = np.arange(i_min + 1, n)
    # the last pre points describe the approach best; a quadratic over <= 0.25 s
    sel = pre[t[pre] >= t[pre[-1]] - 0.25]
    if sel.size < 6:
        sel = pre[-6:]
    t0 = t[sel[-1]]
    cz = _robust_poly(t[sel] - t0, xyz[sel, 2])
    cx = _robust_poly(t[sel] - t0, xyz[sel, 0])
    cy = _robust_poly(t[sel] - t0, xyz[sel, 1])
    if cz.size < 3:  # two points: a straight line; add gravity
        cz = np.array([-4.9, cz[0], cz[1]])
    cand = _descents(cz, r)
    if not cand and sel.size >= 2:
        # outliers among few points can bend the free quadratic upward: fall back to a straight line
        # in z + g t^2 / 2, the curvature fixed by gravity (drag and lift only nudge it near the bounce)
        half_g = 0.5 * params.atmosphere.gravity
        lin = _robust_poly(t[sel] - t0, xyz[sel, 2] + half_g * (t[sel] - t0) ** 2, deg=1)
        cz = np.array([-half_g, lin[-2] if lin.size > 1 else 0.0, lin[-1]])
        cand = _descents(cz, r)
    dz = np.polyder(cz)
    if not cand:
        raise InputError("track: no bounce in range: the ball does not come down to the ground")
    tau = min(cand)
    horizon = max(0.5, 0.5 * (t[-1] - t[0]))
    if tau > horizon + (t[-1] - t0):
        raise InputError(
            f"track: no bounce in range: the ball would land {tau:.2f} s after the last point before its lowest point"
        )
    p = M.default_params()
    p[M.P_XB] = np.polyval(cx, tau)
    p[M.P_YB] = np.polyval(cy, tau)
    p[M.P_TB] = t0 + tau
    p[M.P_VIN] = [np.polyval(np.polyder(cx), tau), np.polyval(np.polyder(cy), tau), np.polyval(dz, tau)]
    post = post[t[post] > p[M.P_TB] + contact_time]
    has_post = post.size >= MIN_POST_POINTS
    if has_post:
        selp = post[t[post] <= t[post[0]] + 0.25]
        if selp.size < MIN_POST_POINTS:
            selp = post[:MIN_POST_POINTS]
        deg = 2 if selp.size >= 6 else 1
        tt = p[M.P_TB] + contact_time
        for c in range(3):
            cc = _robust_poly(t[selp] - tt, xyz[selp, c], deg)
            p[M.indices(M.P_VOUT)[c]] = np.polyval(np.polyder(cc), 0.0)
        if p[M.P_VOUT][2] <= 0:
            has_post = False
    if not has_post:
        p[M.P_VOUT] = _bounce_out(p[M.P_VIN], p[M.P_WIN], surface, params)
    return p, has_post


POST_SPAN = 0.25  #: [s] samples after the bounce used for the outgoing velocity when the approach alone is fitted


def _post_velocity(tau: np.ndarray, xyz: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Velocity at tau = 0 (the ball leaving the ground) from robust quadratics (lines for < 6 samples)
    of the samples after the bounce, and the samples they reject.  Drag bends the path by about
    k C_D v^2 ~ 10 m/s^2 at 20 m/s, which a quadratic over 0.25 s absorbs to ~0.1 m/s."""
    deg = 2 if tau.size >= 6 else 1
    v = np.empty(3)
    bad = np.zeros(tau.size, dtype=bool)
    for c in range(3):
        cc = _robust_poly(tau, xyz[:, c], deg, floor=5 * NOISE_FLOOR)
        v[c] = np.polyval(np.polyder(cc), 0.0)
        r = xyz[:, c] - np.polyval(cc, tau)
        mad = 1.4826 * np.median(np.abs(r - np.median(r))) + 1e-9
        bad |= np.abs(r) > max(5.0 * mad, 5 * NOISE_FLOOR)
    return v, bad


def _segments(t, tb, tc, has_post, outlier):
    seg = np.where(t < tb, M.SEG_PRE, np.where(t > tb + tc, M.SEG_POST, M.SEG_OFF))
    if not has_post:
        seg = np.where(seg == M.SEG_POST, M.SEG_OFF, seg)
    seg = np.where(outlier, M.SEG_OFF, seg)
    return seg.astype(np.int64)


@dataclass(frozen=True)
class Prior:
    """Gaussian priors on free parameters: positions in the free vector, means and sigmas."""

    index: np.ndarray
    mean: np.ndarray
    sigma: np.ndarray

    @classmethod
    def build(cls, free_list: list[int], table: dict[int, tuple[float, float]]) -> Prior:
        rows = [(j, *table[f]) for j, f in enumerate(free_list) if f in table]
        return cls(
            np.array([r[0] for r in rows], dtype=np.int64),
            np.array([r[1] for r in rows], dtype=float),
            np.array([r[2] for r in rows], dtype=float),
        )


def levenberg_marquardt(
    x0,
    n: int,
    resid: Callable[[np.ndarray, np.ndarray, np.ndarray], None],
    jac: Callable[[np.ndarray, np.ndarray, np.ndarray], None],
    prior: Prior,
    robust: bool,
    max_iter: int = MAX_ITER,
):
    """Minimise the (robust) cost from x0.  Returns (x, cost, model evaluations, converged).

    ``resid(x, res, pos)`` fills the weighted residuals (3n,); ``jac(x, res, J)`` the Jacobian around
    them.  Levenberg-Marquardt with Marquardt's diagonal scaling (More 1978) on the normal equations
    (accumulated by a compiled loop), soft-L1 loss by iteratively reweighting each point by
    rho'(z) = 1/sqrt(1 + z), z = |r_i|^2 / f^2 (Triggs et al. 2000, sec. 6.8) when ``robust``.
    Bounded: at most ``max_iter`` iterations of at most 12 damping trials each.
    """
    x = np.array(x0, dtype=float)
    npar = x.size
    res = np.empty(3 * n)
    pos = np.empty((n, 3))
    J = np.empty((3 * n, npar))
    A = np.empty((npar, npar))
    g = np.empty(npar)

    def cost_of(xv):
        resid(xv, res, pos)
        r2 = (res.reshape(-1, 3) ** 2).sum(axis=1)
        if robust:
            c = float(np.sum(2.0 * ROBUST_SCALE**2 * (np.sqrt(1.0 + r2 / ROBUST_SCALE**2) - 1.0)))
        else:
            c = float(np.sum(r2))
        return c + float(np.sum(((xv[prior.index] - prior.mean) / prior.sigma) ** 2)), r2

    cost, r2 = cost_of(x)
    nev = 1
    lam = 1e-3
    converged = False
    for _ in range(max_iter):
        if not np.isfinite(cost):
            break
        jac(x, res, J)
        nev += npar
        wpt = 1.0 / np.sqrt(1.0 + r2 / ROBUST_SCALE**2) if robust else np.ones(n)
        M.normal_equations(J, res, wpt, A, g)
        for j, mu, sj in zip(prior.index, prior.mean, prior.sigma):
            A[j, j] += 1.0 / sj**2
            g[j] += (x[j] - mu) / sj**2
        if not (np.all(np.isfinite(A)) and np.all(np.isfinite(g))):
            break
        d = np.maximum(np.diag(A).copy(), 1e-30)
        improved = False
        cn, r2n, xn = cost, r2, x
        step: np.ndarray = np.zeros(npar)
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
            converged = True  # no step lowers the cost: a minimum (or a dead end the caller judges)
            break
        gain = cost - cn
        small = np.all(np.abs(step) <= 1e-10 + 1e-9 * np.abs(x))
        x, cost, r2 = xn, cn, r2n
        lam = max(lam / 10.0, 1e-12)
        if gain < COST_TOL or small:  # cost is chi^2: a gain of 1e-3 moves parameters by ~0.03 sigma
            converged = True
            break
    return x, cost, nev, converged


def lm_model(p, free, t, xyz, w, seg, kern, ap, consts, prior: Prior, robust: bool, max_iter: int = MAX_ITER):
    """:func:`levenberg_marquardt` on the bounce model of :mod:`tennislab.linecall.model`, compiled
    (:func:`tennislab.linecall._lm.lm_bounce`), starting from ``p[free]``.  Returns (x, cost, model
    evaluations, converged)."""
    x, cost, nev, conv = lm_bounce(
        np.ascontiguousarray(p, dtype=np.float64), free, STEPS, t, xyz, np.ascontiguousarray(w, dtype=np.float64),
        seg, kern, ap, consts, prior.index, prior.mean, prior.sigma, bool(robust), ROBUST_SCALE, int(max_iter),
        COST_TOL,
    )  # fmt: skip
    return x, float(cost), int(nev), bool(conv)


def _check_mode(name: str, mode: str) -> str:
    if mode not in AERO_MODES:
        raise InputError(f"{name}: unknown mode {mode!r}; allowed: {', '.join(AERO_MODES)}")
    return mode


def _robust_scale(r3: np.ndarray) -> float:
    """1.4826 MAD of the residual components (per axis) [m]."""
    comp = r3.ravel()
    comp = comp[np.isfinite(comp)]
    if comp.size == 0:
        return float("nan")
    return float(1.4826 * np.median(np.abs(comp - np.median(comp))))


def _detrend(r3: np.ndarray, seg: np.ndarray) -> np.ndarray:
    """The residuals less their running median (5 samples, per axis, within each segment): what is
    left is what no smooth misfit explains.  A model that cannot follow a long flight leaves a
    smooth, systematic residual of several mm; judged against it (or against its spread) the
    samples where it is largest, near the ends and the bounce, would be rejected as outliers."""
    out = np.full_like(r3, np.nan)
    for lab in (M.SEG_PRE, M.SEG_POST):
        idx = np.nonzero(seg == lab)[0]
        if idx.size == 0:
            continue
        for c in range(3):
            col = r3[idx, c]
            out[idx, c] = col - _running_median_inside(col)
    return out


def _running_median_inside(z: np.ndarray, w: int = 5) -> np.ndarray:
    """Running median over ``w`` samples that stays inside the sequence: at its ends the window is
    the first or last ``w`` samples (padding the ends with their own value would make an outlier
    at the end its own median, and the end of the approach is where the bounce is)."""
    n = z.size
    if n < w:
        return np.full(n, np.median(z)) if n else z.copy()
    win = np.lib.stride_tricks.sliding_window_view(z, w)
    med = np.median(win, axis=1)
    start = np.clip(np.arange(n) - w // 2, 0, n - w)
    return med[start]


def _reject(norm: np.ndarray, usable: np.ndarray) -> tuple[np.ndarray, bool]:
    """Outliers among ``usable`` points: normalised residual above :data:`OUTLIER_SIGMA`, the worst
    :data:`MAX_REJECT_FRACTION` at most.  Returns (mask, capped)."""
    out = usable & (norm > OUTLIER_SIGMA)
    cap = int(MAX_REJECT_FRACTION * np.count_nonzero(usable))
    if np.count_nonzero(out) <= cap:
        return out, False
    order = np.argsort(-np.where(out, norm, -np.inf))
    keep = np.zeros_like(out)
    keep[order[:cap]] = True
    return keep & out, True


def fit_track(
    t,
    xyz,
    sigma=None,
    params: FlightParams | None = None,
    surface="hard",
    *,
    drag: str = "prior",
    lift: str = "prior",
    fit_drag: bool = False,
    mark_params: MarkParams = MarkParams(),
    step: float = 16e-3,
    max_rounds: int = MAX_ROUNDS,
    window: tuple | None = WHOLE_FLIGHT,
    contact_prior: float = 0.0,
    t_hint: float | None = None,
    spin_prior: float = SPIN_PRIOR,
    post: str = "auto",
    start: np.ndarray | None = None,
) -> TrackFit:
    """Fit the flight model through the bounce to a track (see the module docstring).

    t : (N,) strictly increasing times [s]; xyz : (N, 3) ball-centre positions [m];
    sigma : (N,) per-point 1-sigma noise per axis [m] or None (estimated);
    params : :class:`FlightParams`; surface : bounce surface (spin out, contact
    displacement); drag, lift : ``"fixed"`` (scale 1), ``"prior"`` (free around 1 with sigma
    :data:`DRAG_PRIOR` / :data:`LIFT_PRIOR`) or ``"free"``; fit_drag : shorthand for
    ``drag="free"``; contact_prior : sigma [s] of the contact time, which sets the prior of the
    offset of the contact travel from the contact model (0: trust the contact model);
    window : (before, after) [s] around the first bounce estimate: only points in it are fitted
    (None: all); t_hint : time of the first bounce seen in the data [s] (the split point);
    spin_prior : sigma [rad/s] of the zero-mean prior on each spin component; start: a parameter
    vector (NPARAM,) to start from (a fit over a shorter window) instead of the quadratic guess.
    Points outside the window get segment -1 and residual NaN.
    """
    params = params or FlightParams()
    drag = "free" if fit_drag else _check_mode("drag", drag)
    lift = _check_mode("lift", lift)
    if post not in POST_MODES:
        raise InputError(f"post: unknown mode {post!r}; allowed: {', '.join(POST_MODES)}")
    s = get_surface(surface)
    t = np.ascontiguousarray(t, dtype=np.float64)
    xyz = np.ascontiguousarray(xyz, dtype=np.float64)
    n = t.size
    tc = mark_params.contact_time
    p, has_post = initial_guess(t, xyz, params, s, tc, t_hint)
    if start is None and window is not None and window[0] > STAGE_WINDOW and p[M.P_TB] - t[0] > STAGE_WINDOW:
        # a long flight: fit its end first and start the whole flight from there (a start guessed
        # from the last 0.25 s and flown back over a second can miss the flight's shape)
        start = fit_track(
            t, xyz, sigma, params, surface, drag=drag, lift=lift, fit_drag=fit_drag, mark_params=mark_params,
            step=step, max_rounds=max_rounds, window=(STAGE_WINDOW, window[1]), contact_prior=contact_prior,
            t_hint=t_hint, spin_prior=spin_prior, post=post,
        ).p  # fmt: skip
    if start is not None and np.all(np.isfinite(start)):
        p = np.array(start, dtype=float)
        has_post = has_post and p[M.P_VOUT][2] > 0
        if not has_post:
            p[M.P_VOUT] = _bounce_out(p[M.P_VIN], p[M.P_WIN], s, params)
    post_points = has_post
    if post == "auto":
        pre_t = t[t < p[M.P_TB]]
        near = pre_t.size >= 6 and p[M.P_TB] - pre_t.max() <= AUTO_GAP
        post = "off" if near else "joint"
    if post == "off" and has_post:
        has_post = False
        p[M.P_VOUT] = _bounce_out(p[M.P_VIN], p[M.P_WIN], s, params)
    loose = has_post and post == "loose"
    p_start = p.copy()
    n_all = n
    rows = np.arange(n)
    if window is not None:
        keep = (t >= p[M.P_TB] - window[0]) & (t <= p[M.P_TB] + window[1])
        if np.count_nonzero(keep & (t < p[M.P_TB])) >= MIN_PRE_POINTS:
            t, xyz, rows = t[keep], xyz[keep], rows[keep]
            if sigma is not None:
                sigma = np.asarray(sigma, dtype=np.float64)[keep]
            if has_post and np.count_nonzero(t > p[M.P_TB] + tc) < MIN_POST_POINTS:
                has_post = False
                p[M.P_VOUT] = _bounce_out(p[M.P_VIN], p[M.P_WIN], s, params)
        n = t.size
    est_sigma = sigma is None
    given = None if est_sigma else np.asarray(sigma, dtype=np.float64)
    sig = np.full(n, 3e-3) if given is None else given.copy()
    consts = M.make_consts(params, s, tc, step)
    kern, ap = M.kernel_arg(params), params.aero.params
    outlier = np.zeros(n, dtype=bool)
    free_list = (
        [M.P_XB, M.P_YB, M.P_TB, *M.indices(M.P_VIN), *M.indices(M.P_WIN)]
        + (M.indices(M.P_VOUT) if has_post else [])
        + ([M.P_DRAG] if drag != "fixed" else [])
        + ([M.P_LIFT] if lift != "fixed" else [])
        + (M.indices(M.P_DXY) + M.indices(M.P_DWOUT) if has_post and (contact_prior > 0 or loose) else [])
        + ([M.P_DRAG_POST] if loose and drag != "fixed" else [])
    )
    free = np.array(free_list, dtype=np.int64)
    table: dict[int, tuple[float, float]] = {k: (0.0, spin_prior) for k in M.indices(M.P_WIN)}
    if drag == "prior":
        table[M.P_DRAG] = (1.0, DRAG_PRIOR)
    if lift == "prior":
        table[M.P_LIFT] = (1.0, LIFT_PRIOR)
    if has_post and (contact_prior > 0 or loose):  # travel = T_c x mean horizontal speed: sigma scales with it
        vmean = 0.5 * (np.hypot(*p[M.P_VIN][:2]) + np.hypot(*p[M.P_VOUT][:2]))
        ts = max(float(contact_prior if contact_prior > 0 else CONTACT_PRIOR) * vmean, MIN_CONTACT_SIGMA)
        table.update({k: (0.0, ts) for k in M.indices(M.P_DXY)})
        table.update({k: (0.0, SPIN_OUT_PRIOR) for k in M.indices(M.P_DWOUT)})
    if loose:
        table[M.P_DRAG_POST] = (1.0, POST_DRAG_PRIOR)
    prior = Prior.build(free_list, table)
    spin_idx = np.array([j for j, f in enumerate(free_list) if f in M.indices(M.P_WIN)], dtype=np.int64)
    pos = np.empty((n, 3))

    def solve(x0, seg, w, robust):
        q = p.copy()
        q[free] = x0
        return lm_model(q, free, t, xyz, w, seg, kern, ap, consts, prior, robust)

    seg = _segments(t, p[M.P_TB], tc, has_post, outlier)
    w = 1.0 / sig
    n_iter = 0
    noise = float("nan")
    capped = False
    converged = False
    r3 = np.full((n, 3), np.nan)
    for rnd in range(max(1, min(int(max_rounds), MAX_ROUNDS))):
        robust = rnd == 0
        x, cost, nev, converged = solve(p[free], seg, w, robust)
        n_iter += nev
        if rnd == 0 and spin_idx.size and np.all(np.isfinite(x)):
            q = p.copy()
            q[free] = x
            vn = np.linalg.norm(q[M.P_VIN])
            if vn > 0 and abs(np.dot(q[M.P_WIN], q[M.P_VIN])) / vn > 10.0:
                # The spin component along the velocity is seen only through the turning of the
                # velocity: its sign can hide in a second minimum.  Restart with it reflected.
                vh = q[M.P_VIN] / vn
                q[M.P_WIN] -= 2.0 * np.dot(q[M.P_WIN], vh) * vh
                x2, cost2, nev2, conv2 = solve(q[free], seg, w, robust)
                n_iter += nev2
                if cost2 < cost:
                    x, cost, converged = x2, cost2, conv2
        p[free] = x
        nat = _segments(t, p[M.P_TB], tc, has_post, np.zeros(n, dtype=bool))
        pos_all = np.full((n, 3), np.nan)
        M.model_positions(p, t, nat, kern, ap, consts, pos_all, True, True)
        r3 = pos_all - xyz
        usable = nat != M.SEG_OFF
        d3 = _detrend(r3, nat)
        scale = _robust_scale(d3[usable]) if usable.any() else float("nan")
        if not np.isfinite(scale):
            break
        floor = NOISE_FLOOR if given is None else max(NOISE_FLOOR, float(np.median(given)))
        noise = max(scale, floor)
        if est_sigma:
            sig = np.full(n, max(scale, 1e-4))
            w = 1.0 / sig
        judge = noise if est_sigma else np.maximum(sig, noise)
        # an outlier is far from the model *and* from the smooth part of the misfit (a model that
        # cannot follow a long flight leaves a smooth residual; a bad sample stands out of it)
        raw = np.linalg.norm(np.nan_to_num(r3, nan=1e3), axis=1) / np.maximum(judge, _robust_scale(r3[usable]))
        det = np.linalg.norm(np.nan_to_num(d3, nan=1e3), axis=1) / judge
        norm = np.where(usable, np.minimum(raw, det), 0.0)
        new_out, capped = _reject(norm, usable)
        new_seg = _segments(t, p[M.P_TB], tc, has_post, new_out)
        if rnd > 0 and np.array_equal(new_seg, seg):
            break
        outlier = new_out
        seg = new_seg
    n_pre = int(np.count_nonzero(seg == M.SEG_PRE))
    n_post = int(np.count_nonzero(seg == M.SEG_POST))
    if n_pre < MIN_PRE_POINTS:
        raise InputError(f"track: too few usable points before the bounce (need {MIN_PRE_POINTS})")
    # final residuals and covariance
    res = np.empty(3 * n)
    M.residuals(p, t, xyz, w, seg, kern, ap, consts, res, pos)
    J = np.empty((3 * n, free.size))
    M.jacobian(p, free, STEPS, t, xyz, w, seg, kern, ap, consts, res, J)
    A = np.empty((free.size, free.size))
    g = np.empty(free.size)
    M.normal_equations(J, res, np.ones(n), A, g)
    for j, sj in zip(prior.index, prior.sigma):
        A[j, j] += 1.0 / sj**2
    used = seg != M.SEG_OFF
    nres = 3 * int(np.count_nonzero(used))
    dof = max(nres - int(free.size - prior.index.size), 1)
    chi2 = float(np.sum(res**2)) / dof
    infl = max(1.0, chi2) * ((1.0 + 4.0 / dof) if est_sigma else 1.0)
    if np.all(np.isfinite(A)):
        try:
            cov = np.linalg.inv(A) * infl
        except np.linalg.LinAlgError:
            cov = np.linalg.pinv(A) * infl
    else:
        cov = np.full((free.size, free.size), np.nan)
    r3n = np.linalg.norm(r3, axis=1)
    rms = float(math.sqrt(np.mean(r3n[used] ** 2))) if used.any() else float("nan")
    # bounce-point covariance (marginal over every other parameter, t_b included) plus the model floor
    bc = cov[:2, :2].copy() + MODEL_SIGMA**2 * np.eye(2)
    vout_source = "joint" if has_post else "bounce-model"
    if not has_post:  # no data after the bounce used: a flight fitted to them, or the bounce model
        p[M.P_VOUT] = _bounce_out(p[M.P_VIN], p[M.P_WIN], s, params)
        if post_points and np.all(np.isfinite(p)):
            t_out = float(p[M.P_TB] + tc)
            later = np.nonzero((t > t_out + 0.002) & (t <= t_out + POST_SPAN))[0]
            if later.size >= MIN_POST_POINTS:
                v_out, bad = _post_velocity(t[later] - t_out, xyz[later])
                few_bad = np.count_nonzero(bad) <= MAX_REJECT_FRACTION * later.size
                if np.all(np.isfinite(v_out)) and v_out[2] > 0 and few_bad:
                    p[M.P_VOUT] = v_out
                    vout_source = "post-fit"
                    seg[later[~bad]] = M.SEG_POST
                    outlier[later[bad]] = True
                    has_post = True
                    n_post = int(np.count_nonzero(seg == M.SEG_POST))
    y_out = np.empty(9)
    M.post_start(p, consts, y_out)
    spin_out = y_out[6:9].copy()
    seg_all = np.full(n_all, M.SEG_OFF, dtype=np.int64)
    seg_all[rows] = seg
    out_all = np.zeros(n_all, dtype=bool)
    out_all[rows] = outlier
    r3_all = np.full(n_all, np.nan)
    r3_all[rows] = r3n
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
        p_start,
        noise,
        capped,
        converged,
        n_pre,
        n_post,
        vout_source,
    )
