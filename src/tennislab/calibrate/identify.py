"""Joint identification of a ball's global aerodynamic curves and every flight's launch state and spin.

**Model.** Every flight of a ball type flies core's equations of motion
(:func:`tennislab.core.dynamics.derivative`) with the same *global* curves (:class:`Curves`)::

    C_D = s_D [cd(v) + cd_s min(S, 0.5)],   C_L = cl(S),   S = r |w| / v,   dw/dt = -lambda w,
    air velocity v - wind

cd(v) and cl(S) piecewise linear on knots (:func:`tennislab.core.aero.curves_model`), lambda the spin
decay [1/s], the wind horizontal [m/s].  Each flight has its own state at its last sample (position,
velocity), its spin vector perpendicular to its path there (two components: a spin *along* the path
moves a ball only through S, which positions cannot separate from the rest) and, optionally, its own
drag scale s_D with a Gaussian prior N(1, sigma_D^2): balls differ from shot to shot (Cross & Lindsey
2014, Sports Eng. 17:89, found "significant shot-to-shot variations" of C_D in flight; Goodwill et al.
2004 lower drag for worn balls).

**What positions cannot tell.** Only the products of lift and spin reach a flight: stretching cl(S)
along S and every spin by the same factor leaves every track unchanged (exactly for a linear cl, up to
cd_s and the decay otherwise).  The stretch is fixed by holding the first lift knot at
:data:`CL_ANCHOR_SLOPE` x S (Cross 2020, Sports Eng. 23:9: C_L = 0.6 S); the other knots give the
curve's shape relative to it.

**Method.** Variable projection: for given globals every flight is fitted alone (trust-region least
squares, its own 8 or 9 parameters), and the globals take Levenberg-Marquardt steps on the profiled
cost, with the flights' Jacobians (forward differences through :mod:`._sweeps`, i.e. core's RK4) projected
off each flight's own parameters (Golub & Pereyra 1973, SIAM J. Numer. Anal. 10:413).  Residuals are
positions over sigma (the track's, else :data:`SIGMA`); weak Gaussian priors hold the knots (second
differences, :data:`SMOOTH_SIGMA`; each value, :data:`RIDGE_SIGMA`, toward the start); each flight gets
a Huber weight on its RMS (c = 3 x median), so that a flight the model cannot follow (a frame the
tracker got wrong) does not steer the curves.  Uncertainties: the sandwich covariance clustered by
flight, H^-1 (sum_k g_k g_k^T) H^-1 (H the Gauss-Newton Hessian with the priors, g_k flight k's
gradient): a flight's residuals are correlated (a model error is systematic along it), so the
flight, not the sample, is the independent unit (the bootstrap over flights has the same limit).

References
----------
.. [1] Cross & Lindsey (2014), Sports Eng. 17:89 (shot-to-shot variations of C_D in flight)
.. [2] Goodwill, Chin & Haake (2004), J. Wind Eng. Ind. Aerodyn. 92:935 (lower drag for worn balls)
.. [3] Cross (2020), Sports Eng. 23:9 (C_L = 0.6 S: the lift anchor)
.. [4] Golub & Pereyra (1973), SIAM J. Numer. Anal. 10:413 (variable projection)
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

import tennislab.calibrate._sweeps as _sweeps
from tennislab.calibrate.flights import Flight
from tennislab.core.aero import CURVES_CD_S_RANGE, AeroModel, curves_drag_positive, curves_model
from tennislab.core.flight import FlightParams
from tennislab.core.launch import path_spin_basis
from tennislab.errors import InputError
from tennislab.units import RPM

H_STEP = 0.01  #: [s] RK4 step of the sweeps (below 7 um from DOP853 over the flights of tests/calibrate)
SIGMA = 1e-3  #: [m] per-axis sigma of a sample when the track gives none
MAX_SPIN = 1100.0  #: [rad/s] bound of each fitted spin component (10,500 rpm; guard rail 10,000 rpm)
DRAG_SCALE_BOUNDS = (0.2, 3.0)  #: allowed per-flight drag scale s_D
SPEED_KNOTS = (10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 50.0, 60.0)  #: [m/s] default drag knots
S_KNOTS = (0.1, 0.2, 0.3, 0.4, 0.6)  #: default lift knots (spin parameter)
CL_ANCHOR_SLOPE = 0.6  #: C_L / S held at the first lift knot (Cross 2020; the stretch positions cannot fix)
SMOOTH_SIGMA = 0.05  #: prior sigma of a second difference of adjacent knot values [-]
RIDGE_SIGMA = 0.5  #: prior sigma of each knot value about its start [-] (only keeps unseen knots defined)
DECAY_SIGMA = 5.0  #: [1/s] prior sigma of the spin decay about its start
WIND_SIGMA = 5.0  #: [m/s] prior sigma of each wind component about 0
HUBER = 3.0  #: a flight's weight is min(1, HUBER x median RMS / its RMS)
GROUPS = ("cd_v", "cd_s", "cl_s", "decay", "wind")  #: the global parameter groups that can be freed


@dataclass(frozen=True)
class Curves:
    """Global aerodynamics of one ball type (module docstring): drag knots ``speed`` [m/s] / ``cd``,
    lift knots ``s`` [-] / ``cl``, ``cd_s`` [-], spin ``decay`` [1/s], ``wind`` (x, y) [m/s]."""

    speed: tuple[float, ...] = SPEED_KNOTS
    cd: tuple[float, ...] = (0.6,) * len(SPEED_KNOTS)
    s: tuple[float, ...] = S_KNOTS
    cl: tuple[float, ...] = tuple(min(CL_ANCHOR_SLOPE * x, 0.5) for x in S_KNOTS)
    cd_s: float = 0.0
    decay: float = 0.0
    wind: tuple[float, float] = (0.0, 0.0)

    def model(self, name: str = "curves") -> AeroModel:
        """The curves as an aero model (:func:`tennislab.core.aero.curves_model`)."""
        return curves_model(self.speed, self.cd, self.s, self.cl, self.cd_s, name=name)

    def ext(self) -> np.ndarray:
        """The global vector of :mod:`._sweeps`: the model's parameters, decay, wind (x, y, 0)."""
        return np.ascontiguousarray(np.concatenate([self.model().params, [self.decay, *self.wind, 0.0]]))

    def layout(self) -> dict[str, np.ndarray]:
        """Indices into :meth:`ext` of each group of :data:`GROUPS` (``cl_s`` without its anchored first knot)."""
        nv, ns = len(self.speed), len(self.s)
        ocd = 2 + nv
        ocl = ocd + nv + ns
        n = 2 + 2 * nv + 2 * ns + 2 + 4
        return {
            "cd_v": np.arange(ocd, ocd + nv),
            "cl_s": np.arange(ocl + 1, ocl + ns),
            "cd_s": np.array([ocl + ns]),
            "decay": np.array([n - 4]),
            "wind": np.array([n - 3, n - 2]),
        }

    def with_ext(self, ext: np.ndarray) -> Curves:
        lay = self.layout()
        ocl = int(lay["cl_s"][0]) - 1
        return dataclasses.replace(
            self,
            cd=tuple(float(v) for v in ext[lay["cd_v"]]),
            cl=tuple(float(v) for v in ext[ocl : ocl + len(self.s)]),
            cd_s=float(ext[lay["cd_s"][0]]),
            decay=float(ext[lay["decay"][0]]),
            wind=(float(ext[lay["wind"][0]]), float(ext[lay["wind"][1]])),
        )

    def names(self, idx: np.ndarray) -> list[str]:
        """Names of the global parameters at ``idx`` (``cd@20``, ``cl@0.3``, ``cd_s``, ``decay``, ``wind_x``)."""
        lay = self.layout()
        label = {}
        for i, v in zip(lay["cd_v"], self.speed):
            label[int(i)] = f"cd@{v:g}"
        for i, v in zip(lay["cl_s"], self.s[1:]):
            label[int(i)] = f"cl@{v:g}"
        label[int(lay["cd_s"][0])] = "cd_s"
        label[int(lay["decay"][0])] = "decay"
        label[int(lay["wind"][0])] = "wind_x"
        label[int(lay["wind"][1])] = "wind_y"
        return [label[int(i)] for i in idx]


def baseline_ext(model: AeroModel, decay: float = 0.0, wind=(0.0, 0.0, 0.0)) -> np.ndarray:
    """The global vector of :mod:`._sweeps` for any aero model, spin decay [1/s] and wind [m/s]."""
    return np.ascontiguousarray(np.concatenate([model.params, [decay, *(float(v) for v in wind)]]))


class ShotFit:
    """One flight's own fit (its parameters ``p``: position, velocity at the last sample, the two spin
    components about ``axes``, optionally the drag scale), for given globals."""

    def __init__(self, flight: Flight, consts: np.ndarray, *, drag_sigma: float | None):
        self.flight = flight
        self.n = len(flight)
        self.t = np.ascontiguousarray(flight.t, dtype=float)
        self.x = np.ascontiguousarray(flight.xyz, dtype=float)
        sig = flight.sigma if flight.sigma is not None else np.full(self.n, SIGMA)
        self.w = np.ascontiguousarray(1.0 / np.asarray(sig, dtype=float))
        self.consts = consts
        self.drag_sigma = drag_sigma
        self.np = 9 if drag_sigma is not None else 8
        pos, vel = _start(self.t, self.x)
        # the spin's two axes span the plane perpendicular to the path (spin along the path bends
        # nothing): core.launch's topspin axis h and up axis u, built from the velocity vector itself
        # (path_spin_basis; through the angles they differ by round-off only, which moves the weakly
        # determined knots of the documented identification by a few 1e-3)
        self.axes = np.stack(path_spin_basis(vel), axis=1)
        spin0 = (flight.spin_rpm or 0.0) * RPM
        self.p0 = np.concatenate([pos, vel, [np.clip(spin0, -MAX_SPIN / 2, MAX_SPIN / 2), 0.0]])
        if drag_sigma is not None:
            self.p0 = np.append(self.p0, 1.0)
        self.p = self.p0.copy()
        self.qfree = np.arange(10 if drag_sigma is not None else 9, dtype=np.int64)
        self.steps = np.array([1e-6] * 6 + [1e-3] * 3 + ([1e-5] if drag_sigma is not None else []))
        self.res = np.empty(3 * self.n)
        self.jac = np.empty((3 * self.n, self.qfree.size))
        self.r = np.zeros(3 * self.n)
        self.J = np.zeros((3 * self.n, self.np))
        self.cost = math.inf

    def q_of(self, p: np.ndarray) -> np.ndarray:
        q = np.empty(10 if self.drag_sigma is not None else 9)
        q[:6] = p[:6]
        q[6:9] = self.axes @ p[6:8]
        if self.drag_sigma is not None:
            q[9] = p[8]
        return q

    def _eval(self, p, kernel, ext):
        q = self.q_of(p)
        _sweeps.shot_jacobian(
            q, self.t, self.x, self.w, H_STEP, kernel, ext, self.consts, self.qfree, self.steps, self.res, self.jac
        )
        J = np.empty((3 * self.n, self.np))
        J[:, :6] = self.jac[:, :6]
        J[:, 6:8] = self.jac[:, 6:9] @ self.axes
        r = self.res.copy()
        if self.drag_sigma is not None:
            J[:, 8] = self.jac[:, 9]
            r = np.append(r, (p[8] - 1.0) / self.drag_sigma)
            row = np.zeros((1, self.np))
            row[0, 8] = 1.0 / self.drag_sigma
            J = np.vstack([J, row])
        return r, J

    def fit(self, kernel, ext, p0: np.ndarray | None = None) -> None:
        """Fit the flight's parameters (from ``p0``, else its last ones)."""
        start = self.p if p0 is None else p0
        lo = np.array([-np.inf] * 6 + [-MAX_SPIN] * 2 + ([DRAG_SCALE_BOUNDS[0]] if self.drag_sigma else []))
        hi = np.array([np.inf] * 6 + [MAX_SPIN] * 2 + ([DRAG_SCALE_BOUNDS[1]] if self.drag_sigma else []))
        last: dict = {}

        def fun(p):  # a non-finite residual (a flight that left the model's range) is far off, its slope 0
            r, J = self._eval(p, kernel, ext)
            last["J"] = np.where(np.isfinite(J), J, 0.0)
            return np.where(np.isfinite(r), r, 1e6)

        sol = least_squares(
            fun,
            np.clip(start, lo + 1e-9, hi - 1e-9),
            jac=lambda p: last["J"],
            bounds=(lo, hi),
            method="trf",
            x_scale="jac",
            xtol=1e-10,
            ftol=1e-12,
        )
        self.p, self.r, self.J = sol.x, sol.fun, np.asarray(sol.jac)
        self.cost = float(sol.fun @ sol.fun)

    def positions(self, kernel, ext) -> np.ndarray:
        out = np.empty((self.n, 3))
        _sweeps.positions(self.q_of(self.p), self.t, H_STEP, kernel, ext, self.consts, out)
        return out

    def rms_mm(self, kernel, ext) -> float:
        """3-D RMS [mm] of the fitted flight's distance from the samples."""
        d = self.positions(kernel, ext) - self.x
        return 1000.0 * math.sqrt(float(np.mean(np.sum(d * d, axis=1))))

    def global_jacobian(self, kernel, ext, free, steps) -> np.ndarray:
        m = 3 * self.n
        res = np.empty(m)
        jac = np.empty((m, free.size))
        _sweeps.global_jacobian(
            self.q_of(self.p), self.t, self.x, self.w, H_STEP, kernel, ext, self.consts, free, steps, res, jac
        )
        if self.r.size > m:
            jac = np.vstack([jac, np.zeros((self.r.size - m, free.size))])
        return jac

    @property
    def spin_rpm(self) -> float:
        return float(np.linalg.norm(self.p[6:8])) / RPM

    @property
    def drag_scale(self) -> float:
        return float(self.p[8]) if self.drag_sigma is not None else 1.0


def _start(t: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position and velocity at the last sample from a quadratic through the (up to 8) nearest samples."""
    tt = t - t[-1]
    sel = np.argsort(np.abs(tt))[: min(8, t.size)]
    deg = 2 if sel.size >= 4 else 1
    coef = [np.polyfit(tt[sel], x[sel, c], deg) for c in range(3)]
    return np.array([c[-1] for c in coef]), np.array([c[-2] for c in coef])


def consts_of(params: FlightParams) -> np.ndarray:
    """(k [1/m], gravity [m/s^2], radius [m]) of the sweeps."""
    return np.array([params.k, params.atmosphere.gravity, params.ball.radius])


def fit_shots(shots: Sequence[ShotFit], kernel, ext, progress: Callable[[str], None] | None = None) -> None:
    """Fit every flight alone for given globals (from its start values)."""
    for i, s in enumerate(shots):
        s.fit(kernel, ext, s.p0)
        if progress is not None and (i + 1) % 50 == 0:
            progress(f"  {i + 1} of {len(shots)} flights fitted")


def cubic_floor_mm(t: np.ndarray, pos: np.ndarray) -> float:
    """3-D RMS [mm] of a flight's distance from its own best cubic in time: the residual a fit of
    the true flight leaves on a tracker that stores each flight as a cubic (the README of the 50 Hz
    data: its samples are a cubic in time to 0.27 mm between a hit and its bounce)."""
    tt = t - t.mean()
    if t.size <= 4:
        return 0.0
    v = np.vander(tt / max(float(np.ptp(tt)), 1e-9), 4)
    coef, *_ = np.linalg.lstsq(v, pos, rcond=None)
    d = pos - v @ coef
    return 1000.0 * math.sqrt(float(np.mean(np.sum(d * d, axis=1))))


@dataclass
class Identification:
    """What :func:`identify` found: the curves, the free globals' names, values and covariance, and the
    flights' fits (``shots``, ``weights``) at the curves."""

    curves: Curves
    names: list[str]
    values: np.ndarray
    cov: np.ndarray
    shots: list[ShotFit]
    weights: np.ndarray
    iterations: int
    cost: float
    #: why the iterations ended: ``converged`` (every global's last step under 1e-4), ``no_descent`` (no
    #: Levenberg-Marquardt step lowered the cost), ``max_iter``, or ``nothing_free``
    stopped: str


def _prior(ext, ext0, free, lay):
    """Rows (L restricted to ``free``, values) of the Gaussian priors in chi units."""
    rows, vals = [], []
    n = ext.size
    sig = {}
    for g, s in (("cd_v", RIDGE_SIGMA), ("cl_s", RIDGE_SIGMA), ("cd_s", RIDGE_SIGMA), ("decay", DECAY_SIGMA)):
        for i in lay[g]:
            sig[int(i)] = s
    for i in lay["wind"]:
        sig[int(i)] = WIND_SIGMA
    fs = {int(i) for i in free}
    for i in free:
        c = np.zeros(n)
        c[i] = 1.0 / sig[int(i)]
        rows.append(c)
        vals.append((ext[i] - ext0[i]) / sig[int(i)])
    for g in ("cd_v", "cl_s"):
        blk = [int(i) for i in lay[g]]
        if g == "cl_s":
            blk = [blk[0] - 1, *blk]  # the anchored knot takes part in the curvature
        for a, b, c_ in zip(blk[:-2], blk[1:-1], blk[2:]):
            if not ({a, b, c_} & fs):
                continue
            c = np.zeros(n)
            c[a], c[b], c[c_] = 1.0 / SMOOTH_SIGMA, -2.0 / SMOOTH_SIGMA, 1.0 / SMOOTH_SIGMA
            rows.append(c)
            vals.append((ext[a] - 2 * ext[b] + ext[c_]) / SMOOTH_SIGMA)
    if not rows:
        return np.zeros((0, free.size)), np.zeros(0)
    return np.array(rows)[:, free], np.array(vals)


def _profile(shots, kernel, ext, free, steps, weights, need_jac=True):
    g_n = free.size
    A = np.zeros((g_n, g_n))
    b = np.zeros(g_n)
    grads = np.zeros((len(shots), g_n))
    cost = 0.0
    for k, s in enumerate(shots):
        s.fit(kernel, ext)
        if not math.isfinite(s.cost):
            return math.inf, A, b, grads
        cost += weights[k] * s.cost
        if not need_jac:
            continue
        jg = s.global_jacobian(kernel, ext, free, steps)
        q, _ = np.linalg.qr(s.J)
        jp = jg - q @ (q.T @ jg)
        A += weights[k] * jp.T @ jp
        grads[k] = weights[k] * jp.T @ s.r
        b += grads[k]
    return cost, A, b, grads


def _normalise(ext: np.ndarray, shots: Sequence[ShotFit], lay) -> np.ndarray:
    """The same flights with the drag curve times the flights' median drag scale and each scale over
    it: only the products s_D C_D reach a flight, and the curves are to be the median flight's."""
    m = float(np.median([s.drag_scale for s in shots]))
    if not (0.2 < m < 5.0) or abs(m - 1.0) < 1e-6:
        return ext
    out = ext.copy()
    out[lay["cd_v"]] *= m
    out[lay["cd_s"]] *= m
    for s in shots:
        s.p[8] = float(np.clip(s.p[8] / m, *DRAG_SCALE_BOUNDS))
        s.p0[8] = 1.0
    return out


def _valid(ext, lay) -> bool:
    """Globals a step may try: finite, in the search's box, and curves core accepts (positive drag at every
    spin, :func:`tennislab.core.aero.curves_drag_positive`; ``cd_s`` in its range)."""
    if not np.all(np.isfinite(ext)):
        return False
    cd, cds = ext[lay["cd_v"]], float(ext[lay["cd_s"][0]])
    return bool(
        np.all(cd > 0.05)
        and np.all(cd < 2.0)
        and np.all(ext[lay["cl_s"]] > -1.0)
        and np.all(ext[lay["cl_s"]] < 2.0)
        and -1.0 < ext[lay["decay"][0]] < 10.0
        and CURVES_CD_S_RANGE[0] <= cds <= CURVES_CD_S_RANGE[1]
        and curves_drag_positive(float(cd.min()), cds)
    )


def identify(
    flights: Sequence[Flight],
    params: FlightParams,
    *,
    start: Curves | None = None,
    free: Sequence[str] = ("cd_v", "cl_s", "decay"),
    drag_sigma: float | None = 0.15,
    max_iter: int = 20,
    progress: Callable[[str], None] | None = None,
) -> Identification:
    """Fit the global curves (groups ``free`` of :data:`GROUPS`) and every flight (module docstring)."""
    bad = [g for g in free if g not in GROUPS]
    if bad:
        raise InputError(f"fit: unknown group {bad[0]!r}; allowed: {', '.join(GROUPS)}")
    say = progress or (lambda _m: None)
    curves = start or Curves()
    lay = curves.layout()
    ext0 = curves.ext()
    ext = ext0.copy()
    kernel = curves.model().kernel
    fidx = np.concatenate([lay[g] for g in free]).astype(np.int64) if free else np.zeros(0, dtype=np.int64)
    steps = np.full(fidx.size, 1e-4)
    consts = consts_of(params)
    shots = [ShotFit(f, consts, drag_sigma=drag_sigma) for f in flights]
    say(f"fitting {len(shots)} flights alone at the start curves")
    fit_shots(shots, kernel, ext, say)
    weights = np.ones(len(shots))
    lam = 1e-3
    it = 0
    cost = math.inf
    stopped = "max_iter"
    for it in range(1, max_iter + 1):
        if drag_sigma is not None and {"cd_v", "cd_s"} & set(free):
            ext = _normalise(ext, shots, lay)
        rms = np.array([math.sqrt(s.cost / s.n) for s in shots])
        weights = np.minimum(1.0, HUBER * float(np.median(rms)) / np.maximum(rms, 1e-12))
        cost, A, b, _ = _profile(shots, kernel, ext, fidx, steps, weights)
        if fidx.size == 0:
            stopped = "nothing_free"
            break
        saved = [s.p.copy() for s in shots]
        L, v = _prior(ext, ext0, fidx, lay)
        total = cost + float(v @ v)
        step_max = 0.0
        while lam < 1e8:
            H = A + L.T @ L
            grad = b + L.T @ v
            dg = -np.linalg.solve(H + lam * np.diag(np.maximum(np.diag(H), 1e-12)), grad)
            trial = ext.copy()
            trial[fidx] += dg
            if _valid(trial, lay):
                c2, *_ = _profile(shots, kernel, trial, fidx, steps, weights, need_jac=False)
                _, v2 = _prior(trial, ext0, fidx, lay)
                if c2 + float(v2 @ v2) < total:
                    ext = trial
                    lam = max(lam / 3.0, 1e-9)
                    step_max = float(np.max(np.abs(dg)))
                    break
            for s, p in zip(shots, saved):
                s.p = p.copy()
            lam *= 10.0
        med = float(np.median([s.rms_mm(kernel, ext) for s in shots]))
        say(f"iteration {it}: weighted cost {cost:.6g}, median flight rms {med:.2f} mm")
        if lam >= 1e8:
            stopped = "no_descent"
            break
        if step_max < 1e-4:
            stopped = "converged"
            break
    say(f"stopped after {it} iteration{'s' if it != 1 else ''}: {stopped.replace('_', ' ')}")
    if drag_sigma is not None and {"cd_v", "cd_s"} & set(free):
        ext = _normalise(ext, shots, lay)
    cost, A, b, grads = _profile(shots, kernel, ext, fidx, steps, weights)
    L, v = _prior(ext, ext0, fidx, lay)
    H = A + L.T @ L
    Hi = np.linalg.pinv(H)
    cov = Hi @ (grads.T @ grads) @ Hi if fidx.size else np.zeros((0, 0))
    fitted = curves.with_ext(ext)
    return Identification(
        curves=fitted,
        names=curves.names(fidx),
        values=ext[fidx].copy(),
        cov=cov,
        shots=shots,
        weights=weights,
        iterations=it,
        cost=cost,
        stopped=stopped,
    )
