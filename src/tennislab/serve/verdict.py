"""Why a serve failed and what would fix it (the ``verdict`` of :class:`tennislab.serve.ServeResult`).

:func:`describe` names the reason (:data:`tennislab.serve.pipeline.REASONS`: ``net``, ``short``,
``long``, ``wide``, ``no-landing``) with one sentence of numbers.  :func:`advise` computes the fix
with the same physics: it simulates the serve again with the face angle beta changed by up to
+-30 deg (0.5 deg steps), with the impact angle alpha over 0-89.5 deg at the same beta, and in 3-D
with the face azimuth changed by up to +-30 deg; it proposes the nearest setting that goes in, moved
1 deg inside the interval of settings that go in (or to its middle when it is narrower than 2 deg),
and gives that interval.  For a serve that goes in it gives the margin in beta.
"""

from __future__ import annotations

import numpy as np

from tennislab.core.events import STATUS_NET
from tennislab.serve.pipeline import REASON_CODES, Setup, box_name, serves

STEP = 0.5  #: scan step [deg]
SPAN = 30.0  #: scan half-width of beta and azimuth [deg]
ALPHA_MAX = 89.5  #: largest impact angle scanned [deg]
SCANNED = ("alpha", "beta", "azimuth")


def describe(setup: Setup, table, o: dict, clearance: float) -> tuple[str | None, str]:
    """(reason, one sentence with the numbers) for the first serve of a :func:`serves` result; the
    reason is the pipeline's judgement (:func:`tennislab.serve.pipeline.judge`)."""
    crit = setup.criteria
    reason: str | None = REASON_CODES[int(o["reason"][0])]
    X = float(o["landing_x"][0])
    Y = float(o["net_height"][0])
    land_x, land_y = float(table["land_x"][0]), float(table["land_y"][0])
    if reason == "in":
        reason = None
    if reason == "no-landing":
        return reason, f"the ball does not land within {setup.flight.t_max:g} s of flight"
    if reason == "short":
        return reason, f"the ball lands {X:.2f} m from the impact point, {-crit.server_x - X:.2f} m before the net"
    if reason == "net" and table["status"][0] == STATUS_NET:
        x, z = float(table["net_hit_x"][0]), float(table["net_hit_z"][0])
        return reason, f"the ball hits the net and stops there (ball centre at x = {x:.3f} m, {z:.3f} m high)"
    if setup.target is None:
        if reason == "net":
            return reason, (
                f"the ball centre crosses the net at {Y:.3f} m, {crit.net_top - Y:.3f} m below the "
                f"{crit.net_top:.3f} m the paper's test needs (net clearance {clearance:+.3f} m)"
            )
        if reason == "long":
            return reason, (
                f"the ball lands {X:.2f} m from the impact point, {X - crit.service_line:.2f} m beyond the service "
                f"line of the paper's test ({crit.service_line:.3f} m)"
            )
        return None, (
            f"the ball clears the net by {clearance:.3f} m (centre at {Y:.3f} m) and lands {X:.2f} m from the "
            f"impact point, {crit.service_line - X:.2f} m inside the service line"
        )
    box = box_name(setup.target)
    x0, x1, y0, y1 = setup.flight.court.area_bounds(box)
    if reason == "net":
        return reason, (
            f"the ball hits the net: its centre passes the net at {Y:.3f} m, {-clearance:.3f} m too low "
            f"(net clearance {clearance:+.3f} m)"
        )
    if reason == "long":
        return reason, f"the ball lands at x = {land_x:.2f} m, {land_x - x1:.2f} m beyond the service line ({x1:.2f} m)"
    if reason == "wide":
        out = max(y0 - land_y, land_y - y1)
        return reason, f"the ball lands at y = {land_y:.2f} m, {out:.2f} m outside the {box}"
    return None, (
        f"the ball clears the net by {clearance:.3f} m and lands at x = {land_x:.2f} m, y = {land_y:.2f} m: "
        f"{x1 - land_x:.2f} m inside the service line, {min(land_y - y0, y1 - land_y):.2f} m inside the side lines"
    )


def runs(values: np.ndarray, ok: np.ndarray) -> list[tuple[float, float]]:
    """Intervals [lo, hi] of consecutive ``values`` where ``ok``."""
    out: list[tuple[float, float]] = []
    start = None
    for i, good in enumerate(ok):
        if good and start is None:
            start = i
        if start is not None and (not good or i == ok.size - 1):
            end = i if good else i - 1
            out.append((float(values[start]), float(values[end])))
            start = None
    return out


def pick(current: float, intervals: list[tuple[float, float]]) -> tuple[float, float, float] | None:
    """(proposed value, lo, hi): the interval nearest to ``current`` and the value in it nearest to
    ``current`` at least 1 deg from its ends (its middle if it is narrower than 2 deg)."""
    if not intervals:
        return None

    def dist(iv):
        lo, hi = iv
        return 0.0 if lo <= current <= hi else min(abs(current - lo), abs(current - hi))

    lo, hi = min(intervals, key=dist)
    m = min(1.0, (hi - lo) / 2)
    return float(np.clip(current, lo + m, hi - m)), lo, hi


def _scan(setup: Setup, name: str, current: float, alpha: float, beta: float, azimuth: float):
    if name == "alpha":
        vals = np.arange(0.0, ALPHA_MAX + 1e-9, STEP)
    else:
        vals = np.unique(np.clip(current + np.arange(-SPAN, SPAN + 1e-9, STEP), -89.0, 89.0))
    a, b, z = (vals if name == key else np.full(vals.size, x) for key, x in zip(SCANNED, (alpha, beta, azimuth)))
    # with a falling toss the racket must still approach the ball (V cos(alpha) above the toss's normal part)
    approach = setup.player.racket_speed * np.cos(np.radians(a)) > -np.sin(np.radians(b)) * setup.toss_vz + 1e-9
    ok = np.zeros(vals.size, bool)
    if approach.any():
        ok[approach] = serves(setup, a[approach], b[approach], z[approach])["success"]
    return vals, runs(vals, ok)


def _deg(x: float) -> str:
    """An angle [deg] for people: to 0.1 deg (the scans step by 0.5 deg)."""
    return f"{round(x, 1) + 0.0:g}"


def advise(setup: Setup, reason: str | None, alpha: float, beta: float, azimuth: float) -> str | None:
    """What would put the serve in (or its margin when it is in); None if no scanned change does."""
    _, beta_runs = _scan(setup, "beta", beta, alpha, beta, azimuth)
    if reason is None:
        p = pick(beta, beta_runs)
        if p is None:  # pragma: no cover - the nominal serve itself is in the scan
            return None
        _, lo, hi = p
        return (
            f"Margin: in for beta {_deg(lo)} to {_deg(hi)} deg at alpha {_deg(alpha)} "
            f"({_deg(beta - lo)} deg lower, {_deg(hi - beta)} deg higher)"
        )
    tips = []
    if setup.target is not None:
        _, az_runs = _scan(setup, "azimuth", azimuth, alpha, beta, azimuth)
        p = pick(azimuth, az_runs)
        if p is not None:
            t, lo, hi = p
            side = "left" if t > azimuth else "right"
            tips.append(
                f"turn the face {_deg(abs(t - azimuth))} deg to the {side} (azimuth {_deg(azimuth)} -> {_deg(t)} deg; "
                f"in for azimuth {_deg(lo)} to {_deg(hi)} deg)"
            )
    p = pick(beta, beta_runs)
    if p is not None:
        t, lo, hi = p
        verb = "open" if t < beta else "close"
        tips.append(
            f"{verb} the face by {_deg(abs(beta - t))} deg (beta {_deg(beta)} -> {_deg(t)}; in for beta {_deg(lo)} to "
            f"{_deg(hi)} deg at alpha {_deg(alpha)})"
        )
    _, alpha_runs = _scan(setup, "alpha", alpha, alpha, beta, azimuth)
    p = pick(alpha, alpha_runs)
    if p is not None:
        t, lo, hi = p
        tips.append(
            f"keep beta {_deg(beta)} and hit at alpha {_deg(t)} deg ({'more' if t > alpha else 'less'} brush; in for "
            f"alpha {_deg(lo)} to {_deg(hi)} deg)"
        )
    text = "; or ".join(tips)  # azimuth (3-D), face angle, impact angle: the smallest change of technique first
    if not text:
        return (
            f"no face angle within {SPAN:g} deg of {_deg(beta)}"
            + (f", no azimuth within {SPAN:g} deg" if setup.target is not None else "")
            + f" and no impact angle at beta {_deg(beta)} puts this serve in for {setup.player.name}"
        )
    return text[0].upper() + text[1:]
