"""Line calls against real tracker output: the bounce against an independent estimate, the fit's
residuals, the bounce sigmas' coverage, the spin against the tracker's (:func:`check_rally`).

Tracker output (Hawk-Eye-style point JSON) stores each flight as the tracker's own smooth curve
sampled on a regular grid; the tracker's own *bounce sample* sits off that grid with its time rounded
to the millisecond, a median 0.7 ms before contact (10-20 mm of path), so it is a weak reference.
The independent estimate used instead (:func:`independent_bounces`): a quadratic in time through the
last :data:`N_LAST` on-grid samples before each bounce event, per axis, crossing the height
:data:`Z_CONTACT` (1.2 mm median from the true contact on noise-free 50 Hz flights; the data's
README).  It uses nothing of tennislab's physics, so it can judge it.

Everything here reads the calls (:class:`~tennislab.linecall.rally.RallyCall`) and the points; it
calls nothing and changes nothing.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from tennislab.io.hawkeye import Point
from tennislab.linecall.detect import off_grid
from tennislab.results import Result, jsonable

N_LAST = 6  #: on-grid samples before a bounce event the independent estimate fits
Z_CONTACT = 0.033  #: [m] ball-centre height at contact the independent estimate crosses
MAX_GAP = 0.05  #: [s] the last of those samples at most this long before the event
MATCH = 0.05  #: [s] a call's bounce and an estimate within this time are the same bounce
CHI2_2D = {1: 2.2957, 2: 6.1801}  #: squared radii of the 2-D 1-sigma / 2-sigma (68.3 / 95.4 %) ellipses


@dataclass(frozen=True)
class IndependentBounce:
    """A bounce of a point by the independent estimate: the event's time, the crossing's [s, m]."""

    t_event: float
    t: float
    x: float
    y: float


def independent_bounces(point: Point, n: int = N_LAST, z: float = Z_CONTACT) -> list[IndependentBounce]:
    """The independent estimate of every bounce event of ``point`` (see the module docstring)."""
    t, xyz = point.t, point.xyz
    on = ~off_grid(t)
    out = []
    for te, kind, *_ in point.event_positions:
        if kind != "bounce":
            continue
        sel = np.nonzero(on & (t < te - 1e-4))[0][-n:]
        if sel.size < n or te - t[sel[-1]] > MAX_GAP:
            continue
        tt = t[sel] - te
        cz = np.polyfit(tt, xyz[sel, 2], 2)
        real = [r.real for r in np.roots(cz - np.array([0.0, 0.0, z])) if abs(r.imag) < 1e-12]
        near = [r for r in real if -MAX_GAP < r < MAX_GAP]
        if not near:
            continue
        tr = min(near, key=abs)
        x = float(np.polyval(np.polyfit(tt, xyz[sel, 0], 2), tr))
        y = float(np.polyval(np.polyfit(tt, xyz[sel, 1], 2), tr))
        out.append(IndependentBounce(float(te), float(te + tr), x, y))
    return out


def _stats(values) -> dict:
    a = np.asarray([v for v in values if v is not None and np.isfinite(v)], dtype=float)
    if a.size == 0:
        return {"n": 0, "median": None, "p90": None, "mean": None}
    return {
        "n": int(a.size),
        "median": float(np.median(a)),
        "p90": float(np.percentile(a, 90)),
        "mean": float(a.mean()),
    }


def _spearman(a: np.ndarray, b: np.ndarray) -> float | None:
    if a.size < 5:
        return None
    ra = np.argsort(np.argsort(a)).astype(float)
    rb = np.argsort(np.argsort(b)).astype(float)
    c = np.corrcoef(ra, rb)[0, 1]
    return float(c) if np.isfinite(c) else None


@dataclass(frozen=True)
class TrackerCheck(Result):
    """:func:`check_rally`'s answer: one row per called shot with an independent estimate, and the summary."""

    rows: tuple[dict, ...]
    summary: dict

    def to_dict(self) -> dict:
        return jsonable({"summary": self.summary, "shots": list(self.rows)})


def _row(s: dict, est: IndependentBounce) -> dict:
    b = s["bounce"]
    dx, dy = b["x"] - est.x, b["y"] - est.y
    cov = np.asarray(b.get("cov_xy_m2") or np.full((2, 2), np.nan), dtype=float)
    d = np.array([dx, dy])
    try:
        m2 = float(d @ np.linalg.solve(cov, d))
    except np.linalg.LinAlgError:
        m2 = math.nan
    sp = s.get("spin") or {}
    tr = s.get("tracker") or {}
    return {
        "point": s["point"],
        "shot": s["shot"],
        "serve": bool(s["serve"]),
        "call": s["call"],
        "error_mm": 1000.0 * math.hypot(dx, dy),
        "mahalanobis2": m2,
        "flight_rms_mm": (s.get("fit") or {}).get("flight_rms_mm"),
        "spin_rpm": sp.get("rpm"),
        "spin_sigma_rpm": sp.get("rpm_sigma"),
        "spin_identified": sp.get("identified"),
        "tracker_spin_rpm": tr.get("spin_rpm"),
    }


def check_rally(rally, points: Sequence[Point]) -> TrackerCheck:
    """The calls of ``rally`` (:func:`~tennislab.linecall.call_rally` of ``points``) against the tracker.

    Summary: calls per answer and the tracker's agreement (as ``rally.summary``); the bounce error
    against the independent estimate [mm] (median, p90, mean; all, serves, rally shots); the coverage
    of the 1-sigma and 2-sigma ellipses of the reported bounce covariance (expected 68.3 / 95.4 %); the
    whole-flight fit residual [mm]; the spin rate against the tracker's (median ratio of rally shots,
    Spearman rank correlation of serves, and how many serves' fitted rates are told apart from zero).
    """
    est = {p.name: independent_bounces(p) for p in points}
    rows = []
    for s in rally.shots:
        b = s.get("bounce") or {}
        if s["call"] not in ("in", "out", "let") or b.get("x") is None or b.get("t") is None:
            continue
        cands = [e for e in est.get(s["point"], []) if abs(e.t_event - b["t"]) < MATCH]
        if cands:
            rows.append(_row(s, min(cands, key=lambda e: abs(e.t_event - b["t"]))))
    summary = {k: rally.summary[k] for k in ("n_shots", "calls", "tracker_calls_compared", "tracker_calls_agree")}
    for label, pick in (("all", lambda r: True), ("serve", lambda r: r["serve"]), ("rally", lambda r: not r["serve"])):
        sel = [r for r in rows if pick(r)]
        summary[f"bounce_error_mm_{label}"] = _stats(r["error_mm"] for r in sel)
        summary[f"flight_rms_mm_{label}"] = _stats(r["flight_rms_mm"] for r in sel)
    m2 = np.array([r["mahalanobis2"] for r in rows if np.isfinite(r["mahalanobis2"])])
    summary["coverage"] = {f"{k}sigma": (float(np.mean(m2 <= c)) if m2.size else None) for k, c in CHI2_2D.items()} | {
        "expected_1sigma": 0.683,
        "expected_2sigma": 0.954,
        "n": int(m2.size),
    }
    summary["spin"] = _spin_summary(rows)
    return TrackerCheck(tuple(rows), summary)


def _spin_summary(rows: list[dict]) -> dict:
    ok = [r for r in rows if r["spin_rpm"] is not None and r["tracker_spin_rpm"]]
    rally = np.array([(r["spin_rpm"], abs(r["tracker_spin_rpm"])) for r in ok if not r["serve"]], dtype=float)
    serve = np.array(
        [(r["spin_rpm"], abs(r["tracker_spin_rpm"]), r["spin_sigma_rpm"] or np.nan) for r in ok if r["serve"]],
        dtype=float,
    ).reshape(-1, 3)
    told = np.array([bool(r["spin_identified"]) for r in ok if r["serve"]], dtype=bool)
    return {
        "rally_n": int(rally.shape[0]) if rally.size else 0,
        "rally_median_ratio": float(np.median(rally[:, 0] / rally[:, 1])) if rally.size else None,
        "rally_spearman": _spearman(rally[:, 0], rally[:, 1]) if rally.size else None,
        "serve_n": int(serve.shape[0]),
        "serve_median_ratio": float(np.median(serve[:, 0] / serve[:, 1])) if serve.size else None,
        "serve_spearman": _spearman(serve[:, 0], serve[:, 1]) if serve.size else None,
        "serve_median_sigma_rpm": float(np.nanmedian(serve[:, 2])) if serve.size else None,
        "serve_told_apart_from_zero": int(np.count_nonzero(told)),
    }
