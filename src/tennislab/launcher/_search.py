"""Aiming on the machine's steps: a joint search of the quantised neighbourhood of every setting.

Given the exact (continuous) elevation a* and heading b* that land a ball of the asked speed v0,
spin rate w0 and spin axis g0 on the target, the machine can only dial 1 deg, 1 km/h, 1 rpm and
1 deg steps (Wojcicki, Pucilowski & Kulesza 2010, section 2).  Rounding a* and b* alone misses by
up to half a step of each times the landing's sensitivity: decimetres.  This module searches
jointly:

* elevation: the steps floor(a*) - E .. ceil(a*) + E (E = :data:`ELEVATION_EXTRA`), heading: floor(b*)
  - 1 .. ceil(b*) + 1, speed: every step within the speed tolerance of v0 (and the nearest step);
* for each such combination, the spin vector omega (two components about the flight, the
  rate and axis of the machine) that lands the ball on the target, by Newton's method with a
  finite-difference Jacobian (the Magnus force of the seed's model is linear in omega, so 2-3
  iterations converge), kept within the spin tolerance |omega - omega_asked| <= tol;
* then the spin rate and axis steps around that omega (4 x 4) and the rounded asked spin.

Every candidate is flown (one :func:`fly_batch` call, ~1 us per flight); the answer is the
candidate nearest the target that clears the net and meets the trajectory preferences; ties (within
0.01 mm) go to the smaller change of speed, then of spin.  Height stays as given.

Physics of what it can reach: speed, elevation and the topspin component move the landing along
the flight; only the heading (rays 1 deg apart: 0.37 m at 21 m) and a sidespin component move it
across.  A sidespin of s [rad/s] shifts the bounce by about 1/2 k s D t across (k = c_l pi r^3 rho /
(2 m), D the distance flown, t the flight time); a 100 rpm tolerance covers the half gap between two
rays only for flights longer than ~2.3 s (docs/launcher.md, "Aiming on the machine's steps").
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tennislab.errors import InputError
from tennislab.launcher.machine import MachineSpec, Range
from tennislab.launcher.preferences import Preferences, Tolerances, spin_change_rpm, spin_components, wrap_deg

#: Extra elevation steps searched beyond floor/ceil of the exact elevation (range coverage).
ELEVATION_EXTRA = 2
#: Extra heading steps beyond floor/ceil of the exact heading.
HEADING_EXTRA = 1
#: Newton iterations on the spin vector per combination, and the finite-difference step [rpm].
SPIN_ITERATIONS = 3
SPIN_FD_RPM = 5.0
#: Combinations whose Newton spin lands nearest (linearised) whose spin steps are all flown.
BEST_COMBOS = 24


@dataclass(frozen=True)
class Candidates:
    """Every candidate flown: settings columns (edge units) and flight results, one row each."""

    elevation_deg: np.ndarray
    heading_deg: np.ndarray
    speed_kmh: np.ndarray
    spin_rpm: np.ndarray
    spin_axis_deg: np.ndarray
    land_x: np.ndarray
    land_y: np.ndarray
    miss_m: np.ndarray
    clearance_m: np.ndarray
    net_status: np.ndarray
    apex_z_m: np.ndarray
    flight_time_s: np.ndarray
    landing_speed_ms: np.ndarray
    landed: np.ndarray


def speed_steps(rng: Range, asked: float, tol: float) -> np.ndarray:
    """Machine speed steps within ``tol`` of ``asked`` (and always the nearest step) [km/h]."""
    lo, hi = max(rng.lo, asked - tol), min(rng.hi, asked + tol)
    k0 = math.ceil((lo - rng.lo) / rng.step - 1e-9)
    k1 = math.floor((hi - rng.lo) / rng.step + 1e-9)
    vals = rng.lo + np.arange(k0, k1 + 1) * rng.step
    return np.unique(np.round(np.append(vals, rng.quantise(asked)), 9))


def _project(W: np.ndarray, o0: np.ndarray, tol: float, wmax: float) -> np.ndarray:
    """Spin vectors (n, 2) [rpm] pulled into the disc |W - o0| <= tol, then to |W| <= wmax."""
    d = W - o0
    n = np.hypot(d[:, 0], d[:, 1])
    W = o0 + d * np.where(n > tol, tol / np.maximum(n, 1e-300), 1.0)[:, None]
    m = np.hypot(W[:, 0], W[:, 1])
    return W * np.where(m > wmax, wmax / np.maximum(m, 1e-300), 1.0)[:, None]


def _landing(tab) -> np.ndarray:
    xy = np.column_stack([tab["land_x"], tab["land_y"]])
    xy[~tab.ok] = np.nan
    return xy


def _trust_step(J: np.ndarray, r: np.ndarray, tol: float) -> np.ndarray:
    """Per row, the offset d (n, 2) minimising |r + J d| subject to |d| <= tol (2 x 2 trust-region problems).

    Inside the disc it is the Newton step; on its edge (J^T J + lam I) d = -J^T r with the lam >= 0
    that gives |d| = tol, found by bisection on log(lam) (60 halvings: far below a 1 rpm step).
    """
    JtJ = np.einsum("nki,nkj->nij", J, J)
    g = np.einsum("nki,nk->ni", J, r)

    def solve(lam):
        a, b, c = JtJ[:, 0, 0] + lam, JtJ[:, 0, 1], JtJ[:, 1, 1] + lam
        det = a * c - b * b
        det = np.where(np.abs(det) > 1e-300, det, 1e-300)
        return -np.column_stack([(c * g[:, 0] - b * g[:, 1]) / det, (a * g[:, 1] - b * g[:, 0]) / det])

    d = solve(np.zeros(len(r)))
    out = ~(np.hypot(d[:, 0], d[:, 1]) <= tol)
    if out.any():
        lo = np.full(out.sum(), -12.0)
        hi = np.full(out.sum(), 12.0)
        scale = np.maximum(np.trace(JtJ[out], axis1=1, axis2=2), 1e-300)
        Jo, go = JtJ[out], g[out]
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lam = scale * 10.0**mid
            a, b, c = Jo[:, 0, 0] + lam, Jo[:, 0, 1], Jo[:, 1, 1] + lam
            det = a * c - b * b
            dd = -np.column_stack([(c * go[:, 0] - b * go[:, 1]) / det, (a * go[:, 1] - b * go[:, 0]) / det])
            big = np.hypot(dd[:, 0], dd[:, 1]) > tol
            lo, hi = np.where(big, mid, lo), np.where(big, hi, mid)
        lam = scale * 10.0**hi
        a, b, c = Jo[:, 0, 0] + lam, Jo[:, 0, 1], Jo[:, 1, 1] + lam
        det = a * c - b * b
        d[out] = -np.column_stack([(c * go[:, 0] - b * go[:, 1]) / det, (a * go[:, 1] - b * go[:, 0]) / det])
    return d


def _spin_newton(shoot, A, B, V, target, o0, tol, wmax) -> tuple[np.ndarray, np.ndarray]:
    """Per combination (A, B, V), the spin vector (n, 2) [rpm] within tolerance landing nearest the target.

    Gauss-Newton on the two spin components with a finite-difference Jacobian; each step is the
    exact minimiser of the linearised miss within the tolerance disc (:func:`_trust_step`).
    """
    n = A.size
    W = np.tile(o0, (n, 1))
    d = SPIN_FD_RPM
    offs = np.array([[0.0, 0.0], [d, 0.0], [0.0, d]])
    pred = np.full(n, np.inf)
    for _ in range(SPIN_ITERATIONS):
        Wk = (W[:, None, :] + offs[None]).reshape(-1, 2)
        tab = shoot(
            np.repeat(A, 3),
            np.repeat(B, 3),
            np.repeat(V, 3),
            np.hypot(Wk[:, 0], Wk[:, 1]),
            np.degrees(np.arctan2(Wk[:, 1], Wk[:, 0])),
        )
        xy = _landing(tab).reshape(n, 3, 2)
        r = xy[:, 0] - np.asarray(target, float)
        J = np.stack([(xy[:, 1] - xy[:, 0]) / d, (xy[:, 2] - xy[:, 0]) / d], axis=2)
        ok = np.isfinite(J).all(axis=(1, 2)) & np.isfinite(r).all(axis=1)
        pred[:] = np.inf
        if ok.any():
            c = W[ok] - o0  # offset from the asked spin; the new offset solves |r - J c + J c'| -> min, |c'| <= tol
            rp = r[ok] - np.einsum("nij,nj->ni", J[ok], c)
            cn = _trust_step(J[ok], rp, tol)
            W[ok] = o0 + cn
            res = rp + np.einsum("nij,nj->ni", J[ok], cn)
            pred[ok] = np.hypot(res[:, 0], res[:, 1])
        W = _project(W, o0, tol, wmax)
    return W, pred


def _spin_box_newton(shoot, A, B, V, target, box) -> tuple[np.ndarray, np.ndarray]:
    """Per combination, spin (rate [rpm], axis [deg]) within the box ((w_lo, w_hi), (g_lo, g_hi)) landing nearest.

    Gauss-Newton in (rate, axis) with a finite-difference Jacobian, each step clipped to the box.
    Returns (n, 2) spin vectors [rpm] (components about the flight, as :func:`_spin_newton`) and the
    linearised miss [m] of each.
    """
    n = A.size
    (w_lo, w_hi), (g_lo, g_hi) = box
    P = np.tile([0.5 * (w_lo + w_hi), 0.5 * (g_lo + g_hi)], (n, 1))
    offs = np.array([[0.0, 0.0], [SPIN_FD_RPM, 0.0], [0.0, 0.2]])
    pred = np.full(n, np.inf)
    for _ in range(SPIN_ITERATIONS):
        Pk = (P[:, None, :] + offs[None]).reshape(-1, 2)
        tab = shoot(np.repeat(A, 3), np.repeat(B, 3), np.repeat(V, 3), Pk[:, 0], Pk[:, 1])
        xy = _landing(tab).reshape(n, 3, 2)
        r = xy[:, 0] - np.asarray(target, float)
        J = np.stack([(xy[:, 1] - xy[:, 0]) / offs[1, 0], (xy[:, 2] - xy[:, 0]) / offs[2, 1]], axis=2)
        ok = np.isfinite(J).all(axis=(1, 2)) & np.isfinite(r).all(axis=1)
        Jd = np.where(ok[:, None, None], J, np.eye(2))
        ok &= np.abs(np.linalg.det(Jd)) > 1e-12
        P0 = P.copy()
        if ok.any():
            P[ok] = P[ok] - np.linalg.solve(Jd[ok], r[ok][..., None])[..., 0]
        P[:, 0] = np.clip(P[:, 0], w_lo, w_hi)
        P[:, 1] = np.clip(P[:, 1], g_lo, g_hi)
        res = r + np.einsum("nij,nj->ni", J, P - P0)
        pred = np.where(ok, np.hypot(res[:, 0], res[:, 1]), np.inf)
    return spin_components(P[:, 0], P[:, 1]), pred


def search(
    shoot,
    spec: MachineSpec,
    target: tuple[float, float],
    exact: tuple[float, float],
    asked: dict,
    tolerances: Tolerances,
    elevation_limits: tuple[float, float],
) -> Candidates:
    """Fly the quantised neighbourhood of an exact solution (module docstring); every candidate.

    ``shoot(elevation, heading, speed, spin, axis)`` flies arrays of settings (height fixed) and
    returns a ``FlightTable``; ``asked`` holds ``speed_kmh``, ``spin_rpm``, ``spin_axis_deg`` as
    asked (validated, not rounded); ``elevation_limits`` (lo, hi) [deg] keeps the elevations on the
    branch being searched (low: below the elevation of the longest flight, high: above).
    """
    er, hr, sr, wr, gr = spec.elevation, spec.heading, spec.speed, spec.spin, spec.spin_axis
    A0 = er.neighbours(exact[0], ELEVATION_EXTRA)
    A0 = A0[(A0 >= elevation_limits[0] - 1e-9) & (A0 <= elevation_limits[1] + 1e-9)]
    if A0.size == 0:
        A0 = np.array([er.quantise(exact[0])])
    B0 = hr.neighbours(exact[1], HEADING_EXTRA)
    V0 = speed_steps(sr, asked["speed_kmh"], tolerances.speed_kmh)
    A, B, V = (x.ravel() for x in np.meshgrid(A0, B0, V0, indexing="ij"))
    w0, g0 = float(asked["spin_rpm"]), float(asked["spin_axis_deg"])
    o0 = spin_components(w0, g0)
    w0q, g0q = wr.quantise(w0), gr.quantise(g0)
    tol_w = tolerances.spin_rpm
    spins = [np.full((A.size, 2), (w0q, g0q))]  # the rounding of the asked spin is always allowed
    tol_g = tolerances.spin_axis_deg
    found = []
    if tol_w > 0:
        found.append(_spin_newton(shoot, A, B, V, target, o0, tol_w, wr.hi))
    if tol_g > 0 and w0 > 0:
        box = ((max(wr.lo, w0 - tol_w), min(wr.hi, w0 + tol_w)), (g0 - tol_g, g0 + tol_g))
        found.append(_spin_box_newton(shoot, A, B, V, target, box))
    combos = [(A, B, V)]
    for W, pred in found:
        top = np.argsort(pred, kind="stable")[:BEST_COMBOS]  # the combinations the spin brings nearest
        top = top[np.isfinite(pred[top])]
        w = np.hypot(W[top, 0], W[top, 1])
        g = np.degrees(np.arctan2(W[top, 1], W[top, 0]))
        for dw in (-1, 0, 1, 2):
            for dg in (-1, 0, 1, 2):
                wq = np.clip(np.floor(w / wr.step) * wr.step + dw * wr.step, wr.lo, wr.hi)
                gq = wrap_deg(np.floor(g / gr.step) * gr.step + dg * gr.step)
                spins.append(np.column_stack([wq, gq]))
                combos.append((A[top], B[top], V[top]))
    S = np.concatenate(spins)
    AA, BB, VV = (np.concatenate(x) for x in zip(*combos))
    wq, gq = S[:, 0], np.where(S[:, 0] == 0.0, g0q, S[:, 1])  # zero spin: one axis (same flight)
    keep = tolerances.allows(wq, gq, w0, g0) | ((wq == w0q) & (gq == g0q))
    keep &= (wq >= wr.lo) & (wq <= wr.hi)
    rows = np.column_stack([AA, BB, VV, wq, gq])[keep]
    rows = np.unique(np.round(rows, 9), axis=0)
    if rows.shape[0] == 0:  # pragma: no cover - the rounded asked spin is always kept
        raise InputError("target: no candidate settings within the tolerances")
    tab = shoot(rows[:, 0], rows[:, 1], rows[:, 2], rows[:, 3], rows[:, 4])
    xy = _landing(tab)
    return Candidates(
        elevation_deg=rows[:, 0],
        heading_deg=rows[:, 1],
        speed_kmh=rows[:, 2],
        spin_rpm=rows[:, 3],
        spin_axis_deg=rows[:, 4],
        land_x=xy[:, 0],
        land_y=xy[:, 1],
        miss_m=np.hypot(xy[:, 0] - target[0], xy[:, 1] - target[1]),
        clearance_m=tab.clearance,
        net_status=tab["net_status"].astype(int),
        apex_z_m=tab["apex_z"],
        flight_time_s=tab["land_t"],
        landing_speed_ms=np.sqrt(tab["land_vx"] ** 2 + tab["land_vy"] ** 2 + tab["land_vz"] ** 2),
        landed=tab.ok & np.isfinite(xy).all(axis=1),
    )


def choose(c: Candidates, asked: dict, exact: tuple[float, float], mask: np.ndarray) -> int:
    """Index of the best candidate among ``mask``: smallest miss; ties (0.01 mm) to the smaller changes."""
    idx = np.flatnonzero(mask)
    if idx.size == 0:
        return -1
    miss = np.round(c.miss_m[idx] * 1e5)  # 0.01 mm
    dv = np.abs(c.speed_kmh[idx] - asked["speed_kmh"])
    dw = spin_change_rpm(c.spin_rpm[idx], c.spin_axis_deg[idx], asked["spin_rpm"], asked["spin_axis_deg"])
    dang = np.abs(c.elevation_deg[idx] - exact[0]) + np.abs(c.heading_deg[idx] - exact[1])
    order = np.lexsort((dang, dw, dv, miss))
    return int(idx[order[0]])


def acceptable(c: Candidates, need_net: bool, prefs: Preferences) -> tuple[np.ndarray, np.ndarray]:
    """(flights that land and clear the net when they must, those of them meeting the preferences)."""
    ok = c.landed.copy()
    if need_net:
        with np.errstate(invalid="ignore"):
            ok &= (c.net_status == 1) & (c.clearance_m >= 0)
    return ok, ok & prefs.accepts(c.apex_z_m, c.clearance_m, c.flight_time_s)
