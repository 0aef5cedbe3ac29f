"""The calibrated family fitted to free-flight tracks (``calibrate tracks --fit cd[,cl,cd_s]``).

Each track (a :class:`tennislab.io.track.Track`: t, x, y, z[, sigma]) is one segment of free flight
(no bounce, no hit).  Its initial position and velocity at its first sample are free.  Its spin is
either not given (the tracks are flown without spin and only ``cd`` can be fitted: a real spin's
Magnus force then biases it) or given as a rate [rpm] about an axis relative to each track's
initial direction (a name or angle of :mod:`tennislab.core.launch`, e.g. a launcher's topspin
setting): with the linear lift law only the product cl x spin reaches the flight, so ``cl`` is
fitted only against a known spin.  The global coefficients of the family (:mod:`~.family`) are
fitted jointly over all tracks.

The flight is core's: :func:`tennislab.core.integrators.sweep_positions` (fixed-step RK4 of
:data:`~tennislab.calibrate.identify.H_STEP` on :func:`tennislab.core.dynamics.derivative`, cubic
Hermite positions between steps) through the same table model that is written out, so that the
residuals vary smoothly with the parameters.  Least squares: SciPy's trust-region reflective method
with a forward-difference Jacobian over the block-sparse structure (a track's state moves only its own
residuals); residuals weighted by 1 / sigma (the track's column, or 1 mm).  Uncertainties: the
covariance (J^T J)^-1 s^2, s^2 the reduced chi-square (at least 1).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence

import numpy as np
from scipy.optimize import least_squares
from scipy.sparse import lil_matrix

from tennislab.calibrate._sweeps import positions_forward
from tennislab.calibrate.family import BOUNDS, family_model, family_table
from tennislab.calibrate.identify import H_STEP, baseline_ext, consts_of
from tennislab.core.aero import AeroModel, get_aero_model
from tennislab.core.flight import FlightParams
from tennislab.core.launch import describe_velocity, launch_spin, spin_axis_angle
from tennislab.errors import InputError, check_range
from tennislab.io.track import Track
from tennislab.units import RPM

DEFAULT_SIGMA = 1e-3  #: [m] noise assumed when a track has no sigma column
FAMILY_PARAMS = ("cd", "cl", "cd_s")  #: the family's free parameters


def _ext(params: FlightParams) -> np.ndarray:
    """The sweeps' global vector of a flight's physics (its aero model, spin decay and wind)."""
    return baseline_ext(params.aero, params.spin_decay, params.atmosphere.wind)


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
        params = self.params(vals)
        kernel, ext, consts = params.aero.kernel, _ext(params), consts_of(params)
        out = []
        for tr, st in zip(self.tracks, states):
            sp, a, b = describe_velocity(st[3:6])
            if self.spin_rate > 0.0 and sp > 0.0:
                w = launch_spin(self.spin_rate, a, b, self.spin_angle)
            else:
                w = np.zeros(3)
            y0 = np.ascontiguousarray(np.concatenate([st, w]))
            pos = np.empty((len(tr), 3))
            positions_forward(y0, np.ascontiguousarray(tr.t, dtype=float), H_STEP, kernel, ext, consts, pos)
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


@dataclasses.dataclass(frozen=True)
class FamilyFit:
    """What :func:`fit_family` found (the fields of the track calibration's result)."""

    values: dict
    sd: dict
    correlation: dict
    chi2_dof: float
    rms_before: list
    rms_after: list
    speeds: list
    table: tuple


def family_options(fit, cd, cl, cd_s, spin_rpm) -> tuple[tuple[str, ...], dict, float]:
    """(free names, start values, spin rate [rad/s]) of a family fit, checked."""
    if fit is None:
        fit = ("cd", "cl") if spin_rpm else ("cd",)
    names = tuple(s.strip() for s in (fit.split(",") if isinstance(fit, str) else fit) if s.strip())
    rate = 0.0 if spin_rpm is None else check_range("spin_rpm", spin_rpm, 0.0, 10_000.0, "rpm") * RPM
    if rate == 0.0 and ("cl" in names or "cd_s" in names):
        raise InputError("fit: cl and cd_s need the tracks' spin (spin_rpm); fit cd alone without it")
    values = {"cd": 0.6, "cl": 0.6, "cd_s": 0.0}
    for nm, val in (("cd", cd), ("cl", cl), ("cd_s", cd_s)):
        if val is not None:
            lo, hi = BOUNDS[nm]
            values[nm] = check_range(nm, val, lo, hi)
    return names, values, rate


def fit_family(
    tracks: Sequence[Track],
    names: tuple[str, ...],
    values: dict,
    rate: float,
    spin_axis,
    base: FlightParams,
    baseline: str,
    say: Callable[[str], None],
) -> FamilyFit:
    """Fit the family's ``names`` to ``tracks`` (module docstring); the baseline with the states only."""
    angle = spin_axis_angle(spin_axis)
    say(f"fitting the baseline {baseline} (track states only)")
    before = _TrackProblem(tracks, base, (), values, rate, angle, get_aero_model(baseline))
    sb = before.solve()
    say(f"fitting {', '.join(names) or 'nothing'} on {len(tracks)} tracks")
    prob = _TrackProblem(tracks, base, names, values, rate, angle, None)
    sol = prob.solve()
    vals, states = prob.unpack(sol.x)
    dof = max(sol.fun.size - sol.x.size, 1)
    chi2 = float(np.sum(sol.fun**2) / dof)
    k = len(names)
    sd: dict = {}
    corr: dict = {}
    if k:
        J = sol.jac.toarray() if hasattr(sol.jac, "toarray") else np.asarray(sol.jac)
        cov = np.linalg.pinv(J.T @ J) * max(chi2, 1.0)
        d = np.sqrt(np.clip(np.diag(cov)[:k], 0.0, None))
        sd = {n: float(s) for n, s in zip(names, d)}
        for i in range(k):
            for j in range(i + 1, k):
                if d[i] > 0 and d[j] > 0:
                    corr[f"{names[i]}:{names[j]}"] = float(cov[i, j] / (d[i] * d[j]))

    def rms(problem, x):
        return [float(np.sqrt(np.mean((p - tr.xyz) ** 2))) for p, tr in zip(problem.positions(x), tracks)]

    return FamilyFit(
        values={k2: vals[k2] for k2 in FAMILY_PARAMS},
        sd=sd,
        correlation=corr,
        chi2_dof=chi2,
        rms_before=rms(before, sb.x),
        rms_after=rms(prob, sol.x),
        speeds=[float(np.linalg.norm(s[3:6])) for s in states],
        table=family_table(vals["cd"], vals["cl"], vals["cd_s"], radius=base.ball.radius),
    )
