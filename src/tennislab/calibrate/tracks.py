"""Calibration of the aero coefficients on tracks: time-stamped 3-D ball positions of free flights.

Each track (a :class:`tennislab.io.track.Track`: t, x, y, z[, sigma]) is one segment of free flight
(no bounce, no hit).  Its initial position and velocity at its first sample are free.  Its spin is
either not given (the tracks are flown without spin and only ``cd`` can be fitted: a real spin's
Magnus force then biases it) or given as a rate [rpm] about an axis relative to each track's
initial direction (a name or angle of :mod:`tennislab.core.launch`, e.g. a launcher's topspin
setting): with the linear lift law only the product cl x spin reaches the flight, so ``cl`` is
fitted only against a known spin.  The global coefficients of
the family (:mod:`~.family`) are fitted jointly over all tracks.

The flight is integrated with fixed-step classical Runge-Kutta (:func:`tennislab.core.integrators.rk4_step`,
steps of at most :data:`H_MAX`, landing exactly on every sample time), through the same table model
that is written out, so that the residuals vary smoothly with the parameters.  Least squares:
SciPy's trust-region reflective method with a forward-difference Jacobian over the block-sparse
structure (a track's state moves only its own residuals); residuals weighted by 1 / sigma (the
track's column, or 1 mm).  Uncertainties: the covariance (J^T J)^-1 s^2, s^2 the reduced
chi-square (at least 1).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numba as nb
import numpy as np
from scipy.optimize import least_squares
from scipy.sparse import lil_matrix

from tennislab.calibrate.family import BOUNDS, FORMULA, aero_table_csv, family_model, family_table
from tennislab.core.aero import DEFAULT_AERO, AeroModel, get_aero_model, inline_tag
from tennislab.core.flight import FlightParams
from tennislab.core.integrators import rk4_step
from tennislab.core.launch import launch_spin, spin_axis_angle
from tennislab.errors import InputError, check_range
from tennislab.io.track import Track
from tennislab.results import Table, jsonable
from tennislab.units import RPM

H_MAX = 1e-3  #: [s] largest Runge-Kutta step (the error is then ~1e-9 m over a flight)
DEFAULT_SIGMA = 1e-3  #: [m] noise assumed when a track has no sigma column
MAX_TRACKS = 5000  #: most tracks in one calibration


@nb.njit(cache=True)
def _sample(y0, times, aero, ap, k, g, r, wx, wy, wz, dec, out):
    """Positions (n, 3) at ``times`` (times[0] is the start of ``y0``) by fixed-step RK4."""
    y = y0.copy()
    ynew = np.empty(9)
    work = np.empty((5, 9))
    t = times[0]
    for i in range(times.size):
        target = times[i]
        while target - t > 1e-12:
            h = min(H_MAX, target - t)
            rk4_step(y, h, aero, ap, k, k, g, r, wx, wy, wz, dec, work, ynew)
            for c in range(9):
                y[c] = ynew[c]
            t += h
        out[i, 0] = y[0]
        out[i, 1] = y[1]
        out[i, 2] = y[2]


def _kernel_args(params: FlightParams):
    aero = params.aero
    tag = inline_tag(aero.kernel)
    wind = params.atmosphere.wind
    return (
        tag if tag is not None else aero.kernel,
        aero.params,
        params.k,
        params.atmosphere.gravity,
        params.ball.radius,
        float(wind[0]),
        float(wind[1]),
        float(wind[2]),
        params.spin_decay,
    )


def _start_state(tr: Track) -> np.ndarray:
    """Position and velocity at the first sample from a quadratic fit of the first points."""
    n = min(len(tr), 12)
    t = tr.t[:n] - tr.t[0]
    out = np.empty(6)
    for c in range(3):
        coef = np.polyfit(t, tr.xyz[:n, c], 2)
        out[c] = coef[2]
        out[3 + c] = coef[1]
    return out


@dataclass(frozen=True)
class TrackCalibrationResult(Table):
    """Aero coefficients fitted to tracks (:func:`calibrate_tracks`).

    ``to_dict()`` keys: ``family``, ``values`` {cd, cl, cd_s}, ``free``, ``sd`` {name: standard
    error}, ``correlation``, ``n_tracks``, ``n_points``, ``spin`` (the assumption),
    ``rms_before_mm`` / ``rms_after_mm`` (residual RMS per coordinate over all points, baseline
    model vs calibrated, each with its own fitted track states), ``baseline``, ``chi2_dof``,
    ``tracks`` (per track: ``n``, ``rms_before_mm``, ``rms_after_mm``, ``speed_ms`` at its start).
    """

    values: dict
    free: tuple[str, ...]
    sd: dict
    correlation: dict
    n_tracks: int
    n_points: int
    spin: dict
    baseline: str
    rms_before_mm: float
    rms_after_mm: float
    chi2_dof: float
    per_track: tuple
    table: tuple

    def to_dict(self) -> dict:
        return jsonable(
            {
                "family": FORMULA,
                "values": self.values,
                "free": list(self.free),
                "sd": self.sd,
                "correlation": self.correlation,
                "n_tracks": self.n_tracks,
                "n_points": self.n_points,
                "spin": self.spin,
                "baseline": self.baseline,
                "rms_before_mm": self.rms_before_mm,
                "rms_after_mm": self.rms_after_mm,
                "chi2_dof": self.chi2_dof,
                "tracks": list(self.per_track),
            }
        )

    def rows(self) -> list[dict]:
        return [dict(r) for r in self.per_track]

    def table_csv(self) -> str:
        return aero_table_csv(*self.table)


class _TrackProblem:
    def __init__(self, tracks, base: FlightParams, free, values, spin_rate, spin_angle, aero: AeroModel | None):
        self.tracks = tracks
        self.base = base
        self.free = tuple(free)
        self.values = dict(values)
        self.spin_rate = spin_rate
        self.spin_angle = spin_angle
        self.aero = aero
        self.sig = [tr.sigma if tr.sigma is not None else np.full(len(tr), DEFAULT_SIGMA) for tr in tracks]
        self.npts = [len(tr) for tr in tracks]
        self.offsets = np.concatenate([[0], np.cumsum([3 * n for n in self.npts])])

    def params(self, vals) -> FlightParams:
        aero = self.aero or family_model(vals["cd"], vals["cl"], vals["cd_s"], radius=self.base.ball.radius)
        return dataclasses.replace(self.base, aero=aero)

    def unpack(self, x):
        k = len(self.free)
        vals = dict(self.values)
        for p, v in zip(self.free, x[:k]):
            vals[p] = float(v)
        return vals, x[k:].reshape(len(self.tracks), 6)

    def positions(self, x) -> list[np.ndarray]:
        vals, states = self.unpack(x)
        args = _kernel_args(self.params(vals))
        out = []
        for tr, st in zip(self.tracks, states):
            v = st[3:6]
            sp = float(np.linalg.norm(v))
            if self.spin_rate > 0.0 and sp > 0.0:
                a = np.arcsin(np.clip(v[2] / sp, -1.0, 1.0))
                b = np.arctan2(v[1], v[0])
                w = launch_spin(self.spin_rate, a, b, self.spin_angle)
            else:
                w = np.zeros(3)
            y0 = np.ascontiguousarray(np.concatenate([st, w]))
            pos = np.empty((len(tr), 3))
            _sample(y0, np.ascontiguousarray(tr.t), *args, pos)  # type: ignore[call-arg]
            out.append(pos)
        return out

    def residuals(self, x) -> np.ndarray:
        parts = []
        for tr, pos, s in zip(self.tracks, self.positions(x), self.sig):
            parts.append(((pos - tr.xyz) / s[:, None]).ravel())
        r = np.concatenate(parts)
        return np.where(np.isfinite(r), r, 1e6)

    def sparsity(self):
        k = len(self.free)
        m = int(self.offsets[-1])
        sp = lil_matrix((m, k + 6 * len(self.tracks)), dtype=int)
        sp[:, :k] = 1
        for i in range(len(self.tracks)):
            sp[self.offsets[i] : self.offsets[i + 1], k + 6 * i : k + 6 * i + 6] = 1
        return sp

    def solve(self):
        k = len(self.free)
        x0 = np.concatenate([[self.values[p] for p in self.free]] + [_start_state(tr) for tr in self.tracks])
        lo = np.full(x0.size, -np.inf)
        hi = np.full(x0.size, np.inf)
        for i, p in enumerate(self.free):
            lo[i], hi[i] = BOUNDS[p]
        x0[:k] = np.clip(x0[:k], lo[:k] + 1e-9, hi[:k] - 1e-9)
        sol = least_squares(
            self.residuals,
            x0,
            jac="2-point",
            jac_sparsity=self.sparsity(),
            bounds=(lo, hi),
            x_scale="jac",
            method="trf",
            max_nfev=200,
            xtol=1e-10,
            ftol=1e-10,
            diff_step=1e-7,
        )
        return sol


def calibrate_tracks(
    tracks: Sequence[Track],
    *,
    fit: Sequence[str] | str | None = None,
    cd: float | None = None,
    cl: float | None = None,
    cd_s: float | None = None,
    spin_rpm: float | None = None,
    spin_axis="topspin",
    baseline: str = DEFAULT_AERO,
    physics: dict | None = None,
    progress: Callable[[str], None] | None = None,
) -> TrackCalibrationResult:
    """Fit the aero family to free-flight tracks (module docstring).

    Parameters
    ----------
    tracks : :class:`~tennislab.io.track.Track` segments (each one free flight, >= 10 points)
    fit : free parameters among ``cd``, ``cl``, ``cd_s`` (default ``cd, cl`` with ``spin_rpm``, else
        ``cd``; ``cl`` and ``cd_s`` need ``spin_rpm``)
    cd, cl, cd_s : start (free) or fixed values (defaults 0.6, 0.6, 0)
    spin_rpm : the tracks' spin rate [rpm] (None: no spin)
    spin_axis : axis of that spin relative to each track's initial direction (name or angle [deg])
    baseline : the model of the "before" residuals (default :data:`DEFAULT_AERO`, with the same spin)
    physics : other :meth:`FlightParams.from_options` options
    """
    if fit is None:
        fit = ("cd", "cl") if spin_rpm else ("cd",)
    names = tuple(s.strip() for s in (fit.split(",") if isinstance(fit, str) else fit) if s.strip())
    for n in names:
        if n not in ("cd", "cl", "cd_s"):
            raise InputError(f"fit: unknown parameter {n!r} for tracks; allowed: cd, cl, cd_s")
    if not tracks:
        raise InputError("tracks: no tracks given")
    if len(tracks) > MAX_TRACKS:
        raise InputError(f"tracks: {len(tracks)} tracks, more than the {MAX_TRACKS} allowed")
    rate = 0.0 if spin_rpm is None else check_range("spin_rpm", spin_rpm, 0.0, 10_000.0, "rpm") * RPM
    if rate == 0.0 and ("cl" in names or "cd_s" in names):
        raise InputError("fit: cl and cd_s need the tracks' spin (spin_rpm); fit cd alone without it")
    angle = spin_axis_angle(spin_axis)
    values = {"cd": 0.6, "cl": 0.6, "cd_s": 0.0}
    for nm, val in (("cd", cd), ("cl", cl), ("cd_s", cd_s)):
        if val is not None:
            lo, hi = BOUNDS[nm]
            values[nm] = check_range(nm, val, lo, hi)
    base = FlightParams.from_options(**(physics or {}))
    say = progress or (lambda _m: None)
    for i, tr in enumerate(tracks):
        if len(tr) < 4:
            raise InputError(f"tracks: track {i + 1} has {len(tr)} points; need at least 4")
        if tr.t[-1] - tr.t[0] > 10.0:
            raise InputError(f"tracks: track {i + 1} lasts {tr.t[-1] - tr.t[0]:g} s; a free flight lasts < 10 s")
    say(f"fitting the baseline {baseline} (track states only)")
    before = _TrackProblem(tracks, base, (), values, rate, angle, get_aero_model(baseline))
    sb = before.solve()
    say(f"fitting {', '.join(names) or 'nothing'} on {len(tracks)} tracks")
    prob = _TrackProblem(tracks, base, names, values, rate, angle, None)
    sol = prob.solve()
    vals, states = prob.unpack(sol.x)
    n_res = sol.fun.size
    dof = max(n_res - sol.x.size, 1)
    chi2 = float(np.sum(sol.fun**2) / dof)
    k = len(names)
    sd: dict = {}
    corr: dict = {}
    if k:
        J = sol.jac.toarray() if hasattr(sol.jac, "toarray") else np.asarray(sol.jac)
        try:
            cov = np.linalg.pinv(J.T @ J) * max(chi2, 1.0)
        except np.linalg.LinAlgError:  # pragma: no cover
            cov = np.full((sol.x.size, sol.x.size), np.nan)
        d = np.sqrt(np.clip(np.diag(cov)[:k], 0.0, None))
        sd = {n: float(s) for n, s in zip(names, d)}
        for i in range(k):
            for j in range(i + 1, k):
                if d[i] > 0 and d[j] > 0:
                    corr[f"{names[i]}:{names[j]}"] = float(cov[i, j] / (d[i] * d[j]))

    def rms(problem, x):
        pos = problem.positions(x)
        return [float(np.sqrt(np.mean((p - tr.xyz) ** 2))) for p, tr in zip(pos, tracks)], pos

    rb, _ = rms(before, sb.x)
    ra, _ = rms(prob, sol.x)
    npts = np.array([len(tr) for tr in tracks])
    all_b = float(np.sqrt(np.sum(np.array(rb) ** 2 * npts) / npts.sum()))
    all_a = float(np.sqrt(np.sum(np.array(ra) ** 2 * npts) / npts.sum()))
    per = tuple(
        {
            "track": i + 1,
            "n": int(len(tr)),
            "speed_ms": float(np.linalg.norm(states[i, 3:6])),
            "rms_before_mm": 1000 * rb[i],
            "rms_after_mm": 1000 * ra[i],
        }
        for i, tr in enumerate(tracks)
    )
    table = family_table(vals["cd"], vals["cl"], vals["cd_s"], radius=base.ball.radius)
    return TrackCalibrationResult(
        values={k2: vals[k2] for k2 in ("cd", "cl", "cd_s")},
        free=names,
        sd=sd,
        correlation=corr,
        n_tracks=len(tracks),
        n_points=int(npts.sum()),
        spin={"rpm": rate / RPM, "axis_deg": float(np.degrees(angle)) if rate else None},
        baseline=baseline,
        rms_before_mm=1000 * all_b,
        rms_after_mm=1000 * all_a,
        chi2_dof=chi2,
        per_track=per,
        table=table,
    )
