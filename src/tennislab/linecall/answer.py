"""What a line call answers: :class:`TrackCall` (the one result of every line-call workflow) and its
typed bounce, :class:`BounceEstimate`; the dictionaries of its JSON parts built in one place.

Every call is a :class:`TrackCall` built by its dataclass constructor, with only what that call has:
a ``review`` without a bounce (:func:`review_call`), a ball stopped by the net, a fitted track, a
flown state.  Its ``bounce`` is a :class:`BounceEstimate` or None (the JSON then has the bounce's
keys with null values).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

import tennislab.linecall.model as M
from tennislab.core.launch import describe_velocity, direction, spin_basis
from tennislab.core.mark import BallMark
from tennislab.core.surfaces import get_surface
from tennislab.linecall.fit import TrackFit
from tennislab.linecall.local_fit import LocalFit
from tennislab.results import Table, jsonable
from tennislab.units import RPM

#: every answer: ``volley`` (hit again before it landed) and ``dead`` (after the point was over) are
#: :func:`~tennislab.linecall.rally.call_rally`'s, for shots with no line to call
CALLS = ("in", "out", "net", "let", "review", "volley", "dead")
#: the reason of a first contact on the hitter's own side of the net
OWN_SIDE = "lands before the net: first contact on the hitter's own side"


#: the bounce's JSON keys when there is no bounce (each null)
NO_BOUNCE = {"x": None, "y": None, "t": None, "sigma_mm": None}


@dataclass(frozen=True)
class BounceEstimate:
    """Where and when the ball first touched the ground, as a line call places it (SI; JSON: :meth:`to_dict`).

    ``x``, ``y`` [m]: the ball centre at first contact (height = the ball's radius); ``t`` [s] (absolute
    clock); ``sigma_mm``: 1-sigma along the worst direction [mm] (0 for a flown state); ``cov_xy_m2``
    the 2x2 covariance of (x, y) [m^2]; the velocities [m/s] and spins [rad/s] in and out; ``mode``:
    the bounce model's regime (slide, roll, grip) when a model gave the velocity out.  Optional
    fields left None are not in the JSON.
    """

    x: float
    y: float
    t: float
    sigma_mm: float
    sigma_x_mm: float | None = None
    sigma_y_mm: float | None = None
    sigma_t_ms: float | None = None
    cov_xy_m2: np.ndarray | None = None
    velocity_in: np.ndarray | None = None
    spin_in: np.ndarray | None = None
    velocity_out: np.ndarray | None = None
    spin_out: np.ndarray | None = None
    speed_in_ms: float | None = None
    mode: str | None = None

    @classmethod
    def from_fit(cls, fit: TrackFit, t_ref: float = 0.0) -> BounceEstimate:
        """The bounce of a track fit (times relative to ``t_ref`` [s])."""
        sb = np.sqrt(np.clip(np.diag(fit.cov)[:3], 0, None))
        return cls(
            x=float(fit.p[M.P_XB]),
            y=float(fit.p[M.P_YB]),
            t=fit.t_bounce + t_ref,
            sigma_mm=fit.sigma_bounce * 1000.0,
            sigma_x_mm=float(sb[0]) * 1000,
            sigma_y_mm=float(sb[1]) * 1000,
            sigma_t_ms=float(sb[2]) * 1000,
            cov_xy_m2=fit.bounce_cov,
            velocity_in=fit.velocity_in,
            spin_in=fit.spin_in,
            velocity_out=fit.velocity_out,
            spin_out=fit.spin_out,
            speed_in_ms=float(np.linalg.norm(fit.velocity_in)),
        )

    def __getitem__(self, key: str):
        """Dictionary-style reading (``call.bounce["x"]``), as when the bounce was a dict."""
        return self.to_dict()[key]

    def get(self, key: str, default=None):
        return self.to_dict().get(key, default)

    def to_dict(self) -> dict:
        out: dict = {"x": self.x, "y": self.y, "t": self.t, "sigma_mm": self.sigma_mm}
        for k in ("sigma_x_mm", "sigma_y_mm", "sigma_t_ms", "cov_xy_m2", "velocity_in", "spin_in"):
            if getattr(self, k) is not None:
                out[k] = getattr(self, k)
        for k in ("velocity_out", "spin_out", "speed_in_ms", "mode"):
            if getattr(self, k) is not None:
                out[k] = getattr(self, k)
        return out


@dataclass(frozen=True)
class TrackCall(Table):
    """One line call (``tennislab call --track/--position/--cameras --json`` is :meth:`to_dict`).

    ``call`` is one of :data:`CALLS`; ``provisional_call`` the in/out of the numbers when the call is
    ``review``; ``decision`` the output of :func:`~tennislab.linecall.decide.call_mark` (``p_in``,
    ``distance_mm``, ``target``/``line``, ``lines``).  ``fit_result``, ``mark_result`` and ``track``
    are the objects behind it (for plots; not in the JSON); their times are relative to
    ``time_offset`` [s] (the first sample), the JSON's are absolute.  ``rows()`` / ``to_frame()``: the
    samples the call used and the fit's residuals (:meth:`rows`; none for a state or cameras' call).
    """

    COLUMNS = ("t_s", "x_m", "y_m", "z_m", "segment", "outlier", "residual_mm", "sigma_mm")

    method: str
    call: str
    surface: str
    physics: dict
    provisional_call: str | None = None
    review_reasons: tuple[str, ...] = ()
    decision: dict | None = None
    bounce: BounceEstimate | None = None
    mark: dict | None = None
    fit: dict = field(default_factory=lambda: no_fit(0))
    spin: dict | None = None
    net: dict | None = None
    later_bounces: tuple[dict, ...] = ()
    extra: dict = field(default_factory=dict)
    fit_result: TrackFit | None = field(default=None, repr=False, compare=False)
    mark_result: BallMark | None = field(default=None, repr=False, compare=False)
    track: tuple | None = field(default=None, repr=False, compare=False)
    time_offset: float = field(default=0.0, repr=False, compare=False)
    notes: tuple[str, ...] = ()  #: why a confident call is what it is, when it needs saying (``reason``)

    @property
    def p_in(self) -> float | None:
        return None if self.decision is None else self.decision["p_in"]

    @property
    def distance_mm(self) -> float | None:
        return None if self.decision is None else self.decision["distance_mm"]

    def rows(self) -> list[dict]:
        """One row per sample of the track the call used: time [s, absolute], position [m]; with a fit
        its ``segment`` (``before`` / ``after`` the bounce, ``unused``: in the contact, outside the
        window or rejected), ``outlier``, the 3-D residual of the fitted flight and the point's sigma
        [mm] (None where no fit was made)."""
        if self.track is None:
            return []
        t, xyz = self.track
        f = self.fit_result
        names = {M.SEG_PRE: "before", M.SEG_POST: "after", M.SEG_OFF: "unused"}
        out: list[dict] = []
        for i in range(len(t)):
            row: dict = {"t_s": float(t[i]) + self.time_offset, "x_m": float(xyz[i, 0]), "y_m": float(xyz[i, 1])}
            row["z_m"] = float(xyz[i, 2])
            if f is None:
                row.update(segment=None, outlier=None, residual_mm=None, sigma_mm=None)
            else:
                res, sig = float(f.residual[i]), float(f.sigma[i])
                row["segment"] = names.get(int(f.segment[i]), "unused")
                row["outlier"] = bool(f.outlier[i])
                row["residual_mm"] = 1000.0 * res if math.isfinite(res) else None
                row["sigma_mm"] = 1000.0 * sig if math.isfinite(sig) else None
            out.append(row)
        return out

    def to_dict(self) -> dict:
        d = self.decision or {}
        out: dict = {"method": self.method}
        out.update(self.extra)
        out["bounce"] = dict(NO_BOUNCE) if self.bounce is None else self.bounce.to_dict()
        out["mark"] = self.mark
        out["call"] = self.call
        out["p_in"] = d.get("p_in")
        out["distance_mm"] = d.get("distance_mm")
        if "line" in d:
            out["line"] = d["line"]
        else:
            out["target"] = d.get("target")
        out["lines"] = d.get("lines", {})
        out["provisional_call"] = self.provisional_call
        out["review_reasons"] = list(self.review_reasons)
        out["reason"] = "; ".join(self.review_reasons or self.notes) or None
        out["fit"] = self.fit
        out["spin"] = self.spin
        out["net"] = self.net
        out["bounces"] = list(self.later_bounces)
        out["n_bounces"] = (0 if self.bounce is None else 1) + len(self.later_bounces)
        out["surface"] = self.surface
        out["physics"] = self.physics
        return jsonable(out)


def spin_components(spin, velocity, cov=None, tracker_rpm: float | None = None) -> dict:
    """Spin vector [rad/s] in the launch vocabulary of :mod:`tennislab.core.launch` relative to
    ``velocity``: topspin (about h = unit(z x d); < 0 backspin), sidespin (about u = d x h; > 0 curves
    the ball to its left) and along the path (about d), in rpm, with 1-sigma from ``cov``
    (3x3 [rad^2/s^2]) and the tracker's signed rpm compared with the topspin component."""
    w = np.asarray(spin, dtype=float)
    _, a, b = describe_velocity(velocity)
    h, u = spin_basis(a, b)
    axes = np.vstack([h, u, direction(a, b)])
    comp = axes @ w / RPM
    out = {
        "vector": w,
        "rpm": float(np.linalg.norm(w) / RPM),
        "topspin_rpm": float(comp[0]),
        "sidespin_rpm": float(comp[1]),
        "along_path_rpm": float(comp[2]),
    }
    if cov is not None:
        c = axes @ np.asarray(cov, dtype=float) @ axes.T
        sd = np.sqrt(np.clip(np.diag(c), 0.0, None)) / RPM
        out["topspin_sigma_rpm"] = float(sd[0])
        out["sidespin_sigma_rpm"] = float(sd[1])
        out["along_path_sigma_rpm"] = float(sd[2])
        nw = float(np.linalg.norm(w))
        if nw > 0:
            e = w / nw
            out["rpm_sigma"] = float(math.sqrt(max(float(e @ np.asarray(cov) @ e), 0.0)) / RPM)
        out["cov"] = np.asarray(cov, dtype=float)
        # told apart from no spin: the rate beyond twice the vector's 1-sigma (root sum of the components'
        # variances; a serve's spin is often not: the tracked flight barely bends for its speed); a rate of
        # 0 never is, whatever its sigma
        rate = float(np.linalg.norm(w) / RPM)
        sigma = float(np.sqrt(np.sum(sd**2)))
        out["identified"] = bool(math.isfinite(sigma) and rate > 2.0 * sigma)
    if tracker_rpm is not None:
        out["tracker_rpm"] = float(tracker_rpm)
        out["topspin_minus_tracker_rpm"] = float(comp[0] - tracker_rpm)
    return out


def review_call(
    reasons, params, surface, *, net=None, method="track-fit", extra=None, n_points=0, track=None, time_offset=0.0
):
    """A ``review`` answer without a bounce (the reasons say why); ``track`` times relative to ``time_offset``."""
    surface = get_surface(surface)
    return TrackCall(
        method=method,
        call="review",
        surface=surface.name,
        physics=params.to_dict(),
        review_reasons=tuple(reasons),
        fit=no_fit(n_points),
        net=net,
        extra=extra or {},
        track=track,
        time_offset=time_offset,
    )


def no_fit(n_points: int) -> dict:
    """The ``fit`` entry of a call made without a track fit."""
    return {"rms_mm": None, "outliers": 0, "n_points": int(n_points)}


def fit_entry(fit: TrackFit, n_points: int, elapsed: float, noise: float, local: LocalFit | None = None) -> dict:
    """The ``fit`` entry of a call made by a track fit (its residuals, scales, counts and timing; with the
    local refits near the bounce: ``bounce_window_s`` ... ``bounce_windows``)."""
    pre = (fit.segment == M.SEG_PRE) & np.isfinite(fit.residual)
    out = {
        "rms_mm": fit.rms * 1000.0,
        "flight_rms_mm": float(math.sqrt(np.mean(fit.residual[pre] ** 2)) * 1000.0) if pre.any() else None,
        "outliers": int(fit.outlier.sum()),
        "outlier_rows": np.nonzero(fit.outlier)[0],
        "n_points": int(n_points),
        "n_used": int(np.count_nonzero(fit.segment >= 0)),
        "n_pre": fit.n_pre,
        "n_post": fit.n_post,
        "has_post_bounce": fit.has_post,
        "velocity_out_from": fit.vout_source,
        "chi2_dof": fit.chi2_dof,
        "sigma_mm": float(np.nanmedian(fit.sigma) * 1000),
        "noise_mm": noise * 1000.0,
        "drag_scale": fit.drag_scale,
        "drag_scale_sigma": fit.param_sigma(M.P_DRAG),
        "lift_scale": fit.lift_scale,
        "lift_scale_sigma": fit.param_sigma(M.P_LIFT),
        **effective_aero(fit),
        "contact_offset_mm": fit.contact_offset * 1000,
        "rejection_capped": fit.rejection_capped,
        "converged": fit.converged,
        "evaluations": fit.n_iter,
        "elapsed_ms": elapsed * 1000,
    }
    if local is not None:
        out.update(
            bounce_window_s=local.window,
            bounce_rms_mm=local.rms * 1000.0,
            bounce_n_points=int(local.rows.size),
            bounce_windows=[
                {"window_s": w, "x": x, "y": y, "sigma_mm": sg * 1000.0, "n_points": k}
                for w, x, y, sg, k in local.tried
            ],
        )
    return out


def effective_aero(fit: TrackFit) -> dict:
    """C_D and C_L the fitted flight used at the bounce: the aero model's at the incoming speed and spin,
    times the fitted scales (``cd_effective``, ``cl_effective``)."""
    v = float(np.linalg.norm(fit.velocity_in))
    w = float(np.linalg.norm(fit.spin_in))
    if not (np.isfinite(v) and np.isfinite(w)):
        return {"cd_effective": None, "cl_effective": None}
    aero = fit.params.aero
    cd, cl = aero.kernel(v, w, fit.params.ball.radius, aero.params)
    return {"cd_effective": float(cd) * fit.drag_scale, "cl_effective": float(cl) * fit.lift_scale}
