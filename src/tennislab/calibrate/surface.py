"""The court's restitution and friction fitted to measured bounces (issue 13, section 3).

Each bounce of a real track gives the ball's velocity just before and just after it (the line-call
fit measures the incoming velocity and spin from the flight before the bounce and the outgoing
velocity from the samples after it: ``tennislab call --json`` keys ``bounce.velocity_in``,
``spin_in``, ``velocity_out``).  :func:`calibrate_surface` fits the parameters of the bounce model
(:mod:`tennislab.core.bounce`: vertical restitution ``e``, sliding friction ``mu`` and, for gripping
balls, the tangential restitution ``e_x``) so that the model's outgoing velocities match the measured
ones, in the least-squares sense with a soft-L1 loss (a badly measured bounce cannot drag the fit).

The uncertainties are the Gauss-Newton covariance at the solution scaled by the residual variance
(``sd``); the ITF Court Pace Rating of the fitted surface (:func:`tennislab.core.bounce.court_pace_rating`)
says where it sits among courts.  The result's :meth:`SurfaceCalibrationResult.surface_toml` is a
surface file every command with ``--surface`` accepts (``--surface court.toml``).

References
----------
.. [1] ITF CS 01/02, court pace rating (ITF Technical Booklet 2015)
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from tennislab.core.ball import Ball
from tennislab.core.bounce import bounce_batch, court_pace_rating
from tennislab.core.surfaces import Surface, cpr_category, get_surface
from tennislab.errors import InputError
from tennislab.results import Table

#: parameters that can be fitted and their allowed ranges (those of :class:`Surface`)
SURFACE_BOUNDS = {"e": (0.05, 1.0), "mu": (0.0, 2.0), "e_x": (0.0, 1.0)}
#: fewest bounces a fit accepts (two parameters from three velocity components each)
MIN_BOUNCES = 3


@dataclass(frozen=True)
class SurfaceCalibrationResult(Table):
    """The fitted surface: ``values`` and their ``sd``, the residuals of the outgoing velocity [m/s]
    before (the base surface) and after, per bounce (:meth:`rows`), and the court pace rating."""

    surface: Surface
    base: Surface
    free: tuple[str, ...]
    sd: dict
    n_bounces: int
    rms_before_ms: float
    rms_after_ms: float
    residuals: np.ndarray = field(repr=False)  #: (N, 3) measured - model after the fit [m/s]
    velocity_in: np.ndarray = field(repr=False)
    velocity_out: np.ndarray = field(repr=False)

    @property
    def cpr(self) -> float:
        """ITF Court Pace Rating of the fitted surface (simulated test; docs/bounce.md)."""
        return float(court_pace_rating(self.surface)["cpr"])

    def to_dict(self) -> dict:
        s = self.surface
        cpr = self.cpr
        return {
            "surface": {"name": s.name, "e": s.e, "mu": s.mu, "e_x": s.e_x, "source": s.source},
            "base": {"name": self.base.name, "e": self.base.e, "mu": self.base.mu, "e_x": self.base.e_x},
            "free": list(self.free),
            "sd": dict(self.sd),
            "n_bounces": self.n_bounces,
            "rms_before_ms": self.rms_before_ms,
            "rms_after_ms": self.rms_after_ms,
            "cpr": cpr,
            "cpr_category": cpr_category(cpr),
        }

    def rows(self) -> list[dict]:
        out = []
        for i in range(self.n_bounces):
            vi, vo, r = self.velocity_in[i], self.velocity_out[i], self.residuals[i]
            out.append(
                {
                    "bounce": i,
                    "vin_x_ms": vi[0], "vin_y_ms": vi[1], "vin_z_ms": vi[2],
                    "vout_x_ms": vo[0], "vout_y_ms": vo[1], "vout_z_ms": vo[2],
                    "res_x_ms": r[0], "res_y_ms": r[1], "res_z_ms": r[2],
                }
            )  # fmt: skip
        return out

    def surface_toml(self) -> str:
        """The fitted surface as a surface file (``--surface FILE.toml``; :mod:`tennislab.io.surface_file`)."""
        s = self.surface
        sd = "; ".join(f"{k} +- {v:.3g}" for k, v in self.sd.items())
        return (
            f"# tennislab surface fitted to {self.n_bounces} measured bounces ({sd});\n"
            f"# outgoing-velocity rms {self.rms_before_ms:.3f} m/s with {self.base.name}"
            f" -> {self.rms_after_ms:.3f} m/s\n"
            f'name = "{s.name}"\n'
            f"e = {s.e:.4f}\n"
            f"mu = {s.mu:.4f}\n"
            f"e_x = {s.e_x:.4f}\n"
            f'source = "{s.source}"\n'
        )


def _array(name: str, a) -> np.ndarray:
    x = np.asarray(a, dtype=float)
    if x.ndim != 2 or x.shape[1] != 3:
        raise InputError(f"{name}: expected an (N, 3) array, got shape {x.shape}")
    return x


def measured_bounces(calls) -> tuple[list, list, list]:
    """(velocity_in, spin_in, velocity_out) lists of the bounces whose outgoing velocity was measured
    from the samples after them: ``calls`` are line calls as dicts (``TrackCall.to_dict()``, or a rally's
    ``shots``), of which those whose fit says ``velocity_out_from == "post-fit"`` count."""
    vi: list = []
    wi: list = []
    vo: list = []
    for d in calls:
        b, fit = d.get("bounce"), d.get("fit") or {}
        if b and fit.get("velocity_out_from") == "post-fit" and b.get("velocity_out") is not None:
            vi.append(b["velocity_in"])
            wi.append(b["spin_in"])
            vo.append(b["velocity_out"])
    return vi, wi, vo


def calibrate_surface(
    velocity_in,
    spin_in,
    velocity_out,
    *,
    base="hard",
    fit=("e", "mu"),
    ball: Ball | None = None,
    name: str = "calibrated",
) -> SurfaceCalibrationResult:
    """Fit the surface parameters ``fit`` (of ``e``, ``mu``, ``e_x``) to measured bounces.

    ``velocity_in``, ``spin_in``, ``velocity_out``: (N, 3) arrays [m/s, rad/s, m/s] of N bounces (v_z
    in < 0 < v_z out); ``base``: the surface whose other parameters are kept and which starts the fit
    (a registered name or a :class:`Surface`).  Bounces with a non-finite value or an impossible
    direction are dropped; fewer than :data:`MIN_BOUNCES` left is an :class:`InputError`.
    """
    b0 = get_surface(base)
    free = tuple(fit)
    for k in free:
        if k not in SURFACE_BOUNDS:
            raise InputError(f"fit: unknown parameter {k!r}; allowed: {', '.join(SURFACE_BOUNDS)}")
    if not free:
        raise InputError("fit: give at least one of e, mu, e_x")
    vi, wi, vo = _array("velocity_in", velocity_in), _array("spin_in", spin_in), _array("velocity_out", velocity_out)
    if not (len(vi) == len(wi) == len(vo)):
        raise InputError(f"velocity_out: {len(vo)} bounces, but {len(vi)} velocities in and {len(wi)} spins")
    keep = np.all(np.isfinite(vi), axis=1) & np.all(np.isfinite(wi), axis=1) & np.all(np.isfinite(vo), axis=1)
    keep &= (vi[:, 2] < 0) & (vo[:, 2] > 0)
    vi, wi, vo = vi[keep], wi[keep], vo[keep]
    if len(vi) < MIN_BOUNCES:
        raise InputError(
            f"velocity_out: {len(vi)} usable bounces (ball down before, up after); the fit needs {MIN_BOUNCES}"
        )
    ball = ball or Ball()

    def surface_of(p) -> Surface:
        vals = {"e": b0.e, "mu": b0.mu, "e_x": b0.e_x} | dict(zip(free, p))
        return Surface(name, e=vals["e"], mu=vals["mu"], e_x=vals["e_x"], source=f"fitted to {len(vi)} bounces")

    def residuals(p) -> np.ndarray:
        out, _, _ = bounce_batch(vi, wi, surface_of(p), ball)
        return (vo - out).ravel()

    lo = np.array([SURFACE_BOUNDS[k][0] for k in free])
    hi = np.array([SURFACE_BOUNDS[k][1] for k in free])
    x0 = np.clip(np.array([getattr(b0, k) for k in free]), lo + 1e-6, hi - 1e-6)
    before = residuals(x0)
    sol = least_squares(residuals, x0, bounds=(lo, hi), loss="soft_l1", f_scale=0.5, diff_step=1e-6, max_nfev=200)
    res = sol.fun.reshape(-1, 3)
    dof = max(1, res.size - len(free))
    s2 = float(np.sum(res**2)) / dof
    try:
        cov = np.linalg.inv(sol.jac.T @ sol.jac) * s2
        sd = {k: float(np.sqrt(max(cov[i, i], 0.0))) for i, k in enumerate(free)}
    except np.linalg.LinAlgError:
        sd = {k: float("nan") for k in free}
    return SurfaceCalibrationResult(
        surface=surface_of(sol.x),
        base=b0,
        free=free,
        sd=sd,
        n_bounces=len(vi),
        rms_before_ms=float(np.sqrt(np.mean(before**2))),
        rms_after_ms=float(np.sqrt(np.mean(res**2))),
        residuals=res,
        velocity_in=vi,
        velocity_out=vo,
    )
