"""Free-flight fit (no bounce): position, velocity and spin at a reference time, the drag scale with
its prior (:data:`tennislab.linecall.fit.DRAG_PRIOR`), the lift scale 1; the solver, priors and outlier
rules of :mod:`tennislab.linecall.fit`.  Used by the net check (:mod:`tennislab.linecall.net`) to fly
the ball's approach on to the net plane.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

import tennislab.linecall.model as M
from tennislab.core.flight import FlightParams
from tennislab.core.surfaces import get_surface
from tennislab.errors import InputError
from tennislab.linecall.fit import (
    DRAG_PRIOR,
    FREE_STEPS,
    NOISE_FLOOR,
    SPIN_PRIOR,
    Prior,
    _check_mode,
    _reject,
    _robust_poly,
    _robust_scale,
    levenberg_marquardt,
)


@dataclass(frozen=True)
class FreeFit:
    """Result of :func:`fit_free_flight`: state ``q`` (NFREE,) at ``t0``, covariance of the free
    parameters, per-point 3-D residuals [m], their RMS [m] and the per-axis noise scale [m]."""

    q: np.ndarray
    t0: float
    free: np.ndarray
    cov: np.ndarray
    residual: np.ndarray
    rms: float
    noise: float
    params: FlightParams = field(repr=False)
    consts: np.ndarray = field(repr=False)
    outlier: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool), repr=False)

    def positions(self, t) -> np.ndarray:
        """Positions (N, 3) at times t (any order)."""
        t = np.asarray(t, dtype=np.float64).ravel()
        order = np.argsort(t)
        out = np.full((t.size, 3), np.nan)
        buf = np.full((t.size, 3), np.nan)
        M.free_positions(
            self.q, self.t0, np.ascontiguousarray(t[order]), M.kernel_arg(self.params), self.params.aero.params,
            self.consts, buf,
        )  # fmt: skip
        out[order] = buf
        return out


def fit_free_flight(
    t, xyz, params: FlightParams | None = None, *, t0: float | None = None, step: float = 16e-3, drag: str = "prior"
) -> FreeFit:
    """Fit a free flight (no bounce, no contact) to points ``t`` (sorted), ``xyz`` (N >= 3).

    The state is taken at ``t0`` (default: the last point); spin free with the weak prior, drag scale
    as in :func:`fit_track`, lift scale 1; one robust round, one plain round after rejecting points
    beyond :data:`OUTLIER_SIGMA` (judged as in :func:`fit_track`).
    """
    params = params or FlightParams()
    drag = _check_mode("drag", drag)
    t = np.ascontiguousarray(t, dtype=np.float64)
    xyz = np.ascontiguousarray(xyz, dtype=np.float64)
    n = t.size
    if n < 3:
        raise InputError(f"track: a free flight needs at least 3 points, got {n}")
    t0 = float(t[-1] if t0 is None else t0)
    q = np.zeros(M.NFREE)
    for c in range(3):
        cc = _robust_poly(t - t0, xyz[:, c], 2 if n >= 4 else 1)
        q[c] = np.polyval(cc, 0.0)
        q[3 + c] = np.polyval(np.polyder(cc), 0.0)
    q[M.F_DRAG] = 1.0
    q[M.F_LIFT] = 1.0
    free_list = M.indices(M.F_STATE) + ([M.F_DRAG] if drag != "fixed" else [])
    free = np.array(free_list, dtype=np.int64)
    table = {k: (0.0, SPIN_PRIOR) for k in M.indices(M.F_SPIN)}
    if drag == "prior":
        table[M.F_DRAG] = (1.0, DRAG_PRIOR)
    prior = Prior.build(free_list, table)
    consts = M.make_consts(params, get_surface("hard"), 4.5e-3, step)
    kern, ap = M.kernel_arg(params), params.aero.params
    w = np.full(n, 1.0 / 3e-3)
    noise = float("nan")
    out = np.zeros(n, dtype=bool)

    def run(w, robust):
        qq = q.copy()

        def resid(xv, res, posb):
            qq[free] = xv
            M.free_residuals(qq, t0, t, xyz, w, kern, ap, consts, res, posb)

        def jac(xv, res, J):
            qq[free] = xv
            M.free_jacobian(qq, free, FREE_STEPS, t0, t, xyz, w, kern, ap, consts, res, J)

        return levenberg_marquardt(q[free], n, resid, jac, prior, robust)

    x, *_ = run(w, True)
    q[free] = x
    pos = np.full((n, 3), np.nan)
    M.free_positions(q, t0, t, kern, ap, consts, pos)
    r3 = pos - xyz
    scale = _robust_scale(r3)
    if np.isfinite(scale):
        noise = max(scale, NOISE_FLOOR)
        norm = np.linalg.norm(np.nan_to_num(r3, nan=1e3), axis=1) / noise
        out, _ = _reject(norm, np.ones(n, dtype=bool))
        w = np.where(out, 0.0, 1.0 / noise)
        x, *_ = run(w, False)
        q[free] = x
        M.free_positions(q, t0, t, kern, ap, consts, pos)
        r3 = pos - xyz
    res = np.empty(3 * n)
    M.free_residuals(q, t0, t, xyz, w, kern, ap, consts, res, pos)
    J = np.empty((3 * n, free.size))
    M.free_jacobian(q, free, FREE_STEPS, t0, t, xyz, w, kern, ap, consts, res, J)
    A = np.empty((free.size, free.size))
    g = np.empty(free.size)
    M.normal_equations(J, res, np.ones(n), A, g)
    for j, sj in zip(prior.index, prior.sigma):
        A[j, j] += 1.0 / sj**2
    dof = max(3 * int(np.count_nonzero(w)) - 6, 1)
    chi2 = float(np.sum(res**2)) / dof
    try:
        cov = np.linalg.inv(A) * max(1.0, chi2) if np.all(np.isfinite(A)) else np.full(A.shape, np.nan)
    except np.linalg.LinAlgError:
        cov = np.full(A.shape, np.nan)
    r3n = np.linalg.norm(r3, axis=1)
    used = w > 0
    rms = float(math.sqrt(np.mean(r3n[used] ** 2))) if used.any() else float("nan")
    return FreeFit(q.copy(), t0, free, cov, r3n, rms, noise, params, consts, out)
