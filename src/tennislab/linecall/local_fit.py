"""Placing the bounce where the model is right: local refits near the bounce, the window chosen by the data.

A flight model never follows a real flight exactly: over a whole flight its misfit grows with the
distance from where it is anchored (on real 50 Hz tracker output the whole-flight residual of the
best physics fit is mostly the tracker's own cubic representation of each flight, 0.5 mm for short
flights to several mm for long ones; docs/linecall.md).  Where the ball lands is decided by the
samples just before the bounce.  :func:`refine_bounce` therefore refits the bounce-parametrised
model of :mod:`tennislab.linecall.model` (the same equations of motion, core's integrator) to the
samples within a window W before the bounce (and, when the approach is not sampled close to the
bounce, the samples within W after the contact), for a sequence of growing windows
:data:`WINDOWS`, and takes the widest window whose bounce agrees with every narrower one within
their uncertainties: the intersection-of-confidence-intervals rule (Goldenshluger & Nemirovski
1997; Katkovnik 1999); a window whose fit drops more than :data:`MAX_WINDOW_REJECT` of its
samples also ends the widening (the model no longer follows it).  A smooth, dense track keeps a
short window (the model's bias dominates); a noisy one a long one (the noise dominates).  The
spin and the drag scale start from the whole-flight fit and stay near it (Gaussian priors
:data:`LOCAL_SPIN_PRIOR`,
:data:`LOCAL_DRAG_PRIOR`): a short window sees too little curvature to place them.

Outliers: the whole-flight fit's gross ones (beyond :data:`GROSS_SIGMA` noise sigmas and
:data:`GROSS_MIN`) stay out; in a window the rest are judged against the noise (never against
the far part of the flight's misfit), so the samples nearest the bounce are never dropped
because the rest of the flight does not fit.

References
----------
Goldenshluger, A. & Nemirovski, A. (1997). On spatially adaptive estimation of nonparametric
regression. Mathematical Methods of Statistics 6, 135-170.
Katkovnik, V. (1999). A new method for varying adaptive bandwidth selection. IEEE Transactions on
Signal Processing 47(9), 2567-2571.
Wald, A. & Wolfowitz, J. (1940). On a test whether two samples are from the same population.
Annals of Mathematical Statistics 11(2), 147-162 (the runs test of :func:`runs_z`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import tennislab.linecall.model as M
from tennislab.linecall.fit import STEPS, Prior, TrackFit, lm_model

#: [s] windows before the bounce tried, narrowest first
WINDOWS = (0.08, 0.12, 0.18, 0.27, 0.4, 0.6, 0.9, 1.4)
#: two windows agree when their bounces differ by less than this many sigmas of the difference...
ICI_GAMMA = 3.0
ICI_FLOOR = 0.5e-3  #: [m] ...plus this (round-off of the fits, far below any line call's concern)
#: fewest samples before the bounce in a window
MIN_WINDOW_POINTS = 4
LOCAL_SPIN_PRIOR = 150.0  #: [rad/s] sigma of each spin component around the whole-flight fit's
LOCAL_DRAG_PRIOR = 0.1  #: sigma of the drag scale around the whole-flight fit's
NOISE_MIN = 2e-4  #: [m] smallest per-axis noise a window's weights assume (1 mm rounding alone: 0.29 mm)
MAX_WINDOW_REJECT = 0.25  #: a window whose fit drops more than this share of its samples ends the widening
GROSS_SIGMA = 10.0  #: a whole-flight outlier further than this many noise sigmas from its fit...
GROSS_MIN = 0.02  #: [m] ...and than this is kept out of every window
OUTLIER_SIGMA = 4.0  #: a sample further than this many noise sigmas (3-D) from the local fit is dropped...
OUTLIER_FLOOR = 3e-3  #: [m] ...and further than this (a short window's own model error stays below ~1 mm)


@dataclass(frozen=True)
class LocalFit:
    """The bounce placed by :func:`refine_bounce` (SI units).

    ``p``: the full parameter vector (:mod:`tennislab.linecall.model`) of the chosen window;
    ``bounce_cov``: 2x2 covariance of (x_b, y_b) [m^2] from that fit (scaled by its chi^2 per degree
    of freedom when above 1); ``window``: its
    span before the bounce [s]; ``rows``: the track rows it used; ``residual``: their 3-D residuals
    [m]; ``rms`` [m]; ``spread``: the largest distance between its bounce and a narrower window's
    [m]; ``tried``: (window [s], x, y, sigma [m], n) of every window fitted; ``runs_z``: the most
    negative runs-test z of the residual signs over the three axes (systematic residuals: < -3).
    """

    p: np.ndarray
    bounce_cov: np.ndarray
    window: float
    rows: np.ndarray
    residual: np.ndarray
    rms: float
    spread: float
    tried: tuple
    runs_z: float
    n_outliers: int

    @property
    def sigma(self) -> float:
        """1-sigma of the bounce point along its worst direction [m]."""
        ev = np.linalg.eigvalsh(self.bounce_cov) if np.all(np.isfinite(self.bounce_cov)) else [np.nan]
        return float(math.sqrt(max(float(np.max(ev)), 0.0)))


def runs_z(signs: np.ndarray) -> float:
    """Wald-Wolfowitz runs test z of a sequence of residual signs (0 for fewer than 6 or one sign):
    far below 0 means fewer sign changes than chance, i.e. a systematic misfit."""
    s = np.asarray(signs) > 0
    n1 = int(np.count_nonzero(s))
    n2 = s.size - n1
    if s.size < 6 or n1 == 0 or n2 == 0:
        return 0.0
    runs = 1 + int(np.count_nonzero(s[1:] != s[:-1]))
    n = n1 + n2
    mu = 2.0 * n1 * n2 / n + 1.0
    var = 2.0 * n1 * n2 * (2.0 * n1 * n2 - n) / (n * n * (n - 1.0))
    return float((runs - mu) / math.sqrt(var)) if var > 0 else 0.0


def _window_fit(fit: TrackFit, t, xyz, consts, rows: np.ndarray, post: bool, noise: float):
    """One local fit over ``rows`` (pre-bounce, plus post-bounce when ``post``); returns (p, cov of the
    free parameters, residual norms, used rows, n outliers) or None when it fails."""
    params = fit.params
    kern, ap = M.kernel_arg(params), params.aero.params
    p = fit.p.copy()
    tt, xx = t[rows], xyz[rows]
    n = tt.size
    tb, tc = p[M.P_TB], fit.mark_params.contact_time
    seg = np.where(tt < tb, M.SEG_PRE, np.where(tt > tb + tc, M.SEG_POST if post else M.SEG_OFF, M.SEG_OFF))
    seg = seg.astype(np.int64)
    free_list = [M.P_XB, M.P_YB, M.P_TB, *M.indices(M.P_VIN), *M.indices(M.P_WIN), M.P_DRAG]
    if post:
        free_list += M.indices(M.P_VOUT)
    free = np.array(free_list, dtype=np.int64)
    table = {k: (float(p[k]), LOCAL_SPIN_PRIOR) for k in M.indices(M.P_WIN)}
    table[M.P_DRAG] = (float(p[M.P_DRAG]), LOCAL_DRAG_PRIOR)
    prior = Prior.build(free_list, table)
    w = np.full(n, 1.0 / max(noise, NOISE_MIN))
    q = p.copy()
    x, _, _, _ = lm_model(p, free, tt, xx, w, seg, kern, ap, consts, prior, robust=True)
    if not np.all(np.isfinite(x)):
        return None
    q[free] = x
    x, _, _, _ = lm_model(q, free, tt, xx, w, seg, kern, ap, consts, prior, robust=False)  # the plain cost
    if not np.all(np.isfinite(x)):
        return None
    q[free] = x
    pos = np.full((n, 3), np.nan)
    M.model_positions(q, tt, seg, kern, ap, consts, pos, True, post)
    r = np.linalg.norm(pos - xx, axis=1)
    bad = (seg != M.SEG_OFF) & (r > max(OUTLIER_SIGMA * math.sqrt(3.0) * noise, OUTLIER_FLOOR))
    n_out = int(np.count_nonzero(bad))
    if n_out and np.count_nonzero((seg == M.SEG_PRE) & ~bad) >= MIN_WINDOW_POINTS:
        seg = np.where(bad, M.SEG_OFF, seg).astype(np.int64)
        q[free] = x
        x, _, _, _ = lm_model(q, free, tt, xx, w, seg, kern, ap, consts, prior, robust=False)
        if not np.all(np.isfinite(x)):
            return None
        q[free] = x
        M.model_positions(q, tt, seg, kern, ap, consts, pos, True, post)
        r = np.linalg.norm(pos - xx, axis=1)
    else:
        n_out = 0
    res = np.empty(3 * n)
    M.residuals(q, tt, xx, w, seg, kern, ap, consts, res, np.empty((n, 3)))
    J = np.empty((3 * n, free.size))
    M.jacobian(q, free, STEPS, tt, xx, w, seg, kern, ap, consts, res, J)
    A = J.T @ J
    for j, sj in zip(prior.index, prior.sigma):
        A[j, j] += 1.0 / sj**2
    used = seg != M.SEG_OFF
    dof = max(3 * int(np.count_nonzero(used)) - (free.size - prior.index.size), 1)
    chi2 = float(np.sum(res**2)) / dof
    state = np.array([j for j, f in enumerate(free_list) if f not in table])  # not the spin, not the drag
    try:
        cov = np.linalg.inv(A)
        cond = np.linalg.inv(A[np.ix_(state, state)])[:2, :2]  # the bounce given the aero: the noise alone
    except np.linalg.LinAlgError:
        return None
    return q, cov, cond, max(1.0, chi2), np.where(used, r, np.nan), rows[used], n_out


def refine_bounce(fit: TrackFit, t, xyz, noise: float, *, post: bool = False) -> LocalFit | None:
    """The bounce of ``fit`` (the whole-flight fit) placed by local refits (see the module docstring).

    t, xyz: the samples ``fit`` was fitted to [s, m]; noise: their per-axis noise [m]; post: also fit
    the samples after the contact (when the approach is not sampled close to the bounce).  None when
    no window has :data:`MIN_WINDOW_POINTS` samples before the bounce.
    """
    t = np.ascontiguousarray(t, dtype=np.float64)
    xyz = np.ascontiguousarray(xyz, dtype=np.float64)
    consts = M.make_consts(fit.params, fit.surface, fit.mark_params.contact_time, 16e-3)
    noise = max(float(noise), NOISE_MIN) if np.isfinite(noise) else 1e-3
    tb, tc = float(fit.p[M.P_TB]), fit.mark_params.contact_time
    tried = []
    chosen = None
    prev: list[tuple[np.ndarray, np.ndarray]] = []
    n_pre_last = -1
    # the whole-flight fit's gross outliers stay out (its others are judged afresh in each window)
    ok = np.ones(t.size, dtype=bool)
    if fit.outlier.size == t.size:
        gross = fit.outlier & (np.nan_to_num(fit.residual, nan=np.inf) > max(GROSS_SIGMA * noise, GROSS_MIN))
        ok &= ~gross
    for win in WINDOWS:
        pre = np.nonzero((t >= tb - win) & (t < tb) & ok)[0]
        if pre.size < MIN_WINDOW_POINTS or pre.size == n_pre_last:
            continue
        n_pre_last = pre.size
        rows = pre
        if post:
            rows = np.concatenate([pre, np.nonzero((t > tb + tc) & (t <= tb + tc + win) & ok)[0]])
        got = _window_fit(fit, t, xyz, consts, rows, post, noise)
        if got is None:
            continue
        q, cov, cond, infl, r, used_rows, n_out = got
        b = q[M.P_XY].copy()
        bc = cov[:2, :2]
        # the windows are compared on the noise alone (given the aero): a bias, of the aero or of the
        # model, shows up as disagreement between windows instead of hiding in a wide interval
        sig = math.sqrt(max(float(np.max(np.linalg.eigvalsh(cond))), 0.0)) if np.all(np.isfinite(cond)) else math.inf
        tried.append((win, float(b[0]), float(b[1]), sig, int(used_rows.size)))
        # nested windows share samples: the difference of two estimates has variance ~ s2^2 - sig^2
        agrees = all(
            np.linalg.norm(b - b2) <= ICI_GAMMA * math.sqrt(abs(s2 * s2 - sig * sig)) + ICI_FLOOR for b2, s2 in prev
        )
        rejecting = n_out > MAX_WINDOW_REJECT * rows.size  # the model no longer follows this window
        if prev and (not agrees or rejecting):
            break
        spread = max((float(np.linalg.norm(b - pb)) for pb, _ in prev), default=0.0)
        prev.append((b, sig))  # type: ignore[arg-type]
        rr = r[np.isfinite(r)]
        zs = _runs(q, fit, t[used_rows], xyz[used_rows], consts, post)
        chosen = LocalFit(
            p=q,
            bounce_cov=bc * infl,
            window=win,
            rows=used_rows,
            residual=rr,
            rms=float(math.sqrt(np.mean(rr**2))) if rr.size else float("nan"),
            spread=spread,
            tried=(),
            runs_z=zs,
            n_outliers=n_out,
        )
    if chosen is None:
        return None
    return LocalFit(**{**chosen.__dict__, "tried": tuple(tried)})


def _runs(q, fit: TrackFit, tt, xx, consts, post: bool) -> float:
    """Most negative runs-test z over the axes of the signed residuals of ``q`` at (tt, xx)."""
    tb, tc = q[M.P_TB], fit.mark_params.contact_time
    seg = np.where(tt < tb, M.SEG_PRE, np.where(tt > tb + tc, M.SEG_POST if post else M.SEG_OFF, M.SEG_OFF))
    pos = np.full((tt.size, 3), np.nan)
    M.model_positions(
        q, tt, seg.astype(np.int64), M.kernel_arg(fit.params), fit.params.aero.params, consts, pos, True, post
    )
    d = pos - xx
    ok = np.all(np.isfinite(d), axis=1)
    return min((runs_z(d[ok, c]) for c in range(3)), default=0.0)
