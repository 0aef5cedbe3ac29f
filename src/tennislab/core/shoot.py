"""Shoot at a target: the launch angles that put a ball where it is wanted (the one aiming primitive).

A launch is known by its position p [m], its speed v [m/s] and its spin components in the launch
frame (topspin, sidespin, along the path) [rad/s] (:mod:`tennislab.core.launch`); its elevation a
and heading b [rad] are solved, for many launches at once, so that the flight of the compiled
batch kernel (:func:`tennislab.core.flight.fly_batch`)

* lands (first ground contact, ball centre at z = r) on a target point (x, y) [m]
  (``at="landing"``), on the **low** branch (the rising part of distance against elevation:
  drives, feeds) or the **high** one (the falling part: lobs); or
* crosses the net plane x = 0 at a point (y, z) [m] (``at="net"``: a serve through its measured
  net point, a shot clipping the tape).

Method
------
Newton's method on (a, b) with a forward finite-difference Jacobian (step :data:`FD_STEP`); every
iteration is one ``fly_batch`` call holding each unconverged launch and its two neighbours
(a + h, b) and (a, b + h), so N launches cost about 3 N flights per iteration.  A step is shortened
to at most :data:`MAX_STEP` in either angle.  Landing targets start from a scan of the elevation
(:func:`scan`, one ``fly_batch`` of the scan grid at the geometric heading): the distance flown
along the target's direction rises then falls with the elevation, so its crossings of the
target distance bracket the two branches and its longest flight splits them; a Newton step leaving
the branch's bracket (widened by :data:`BRACKET_WIDEN` grid steps for a curving ball, never past
the split) is halved back toward it (a safeguarded Newton method, Press et al. 2007 section 9.4).
A caller with a good start (a previous solution, a fitted inverse map) passes ``start`` and
``bounds`` and skips the scan.  Net targets start from a drag-free straight line to the net point
(:func:`first_guess`); a launch whose flight never reaches the net is aimed higher.

Machine steps
-------------
With ``steps=(elevations, headings)`` (the angles a machine can dial [rad]) the on-step
neighbours of every solution (floor - E .. ceil + E of each angle) are flown too and returned
with their misses (:class:`OnSteps`): the nearest on-step launch, and the candidates a caller's
own search over other settings (speed, spin, height) starts from.

References
----------
Wojcicki, Pucilowski & Kulesza (2010), Mathematical analysis for a new tennis ball launcher,
Acta Mech. Autom. 4(4) (seed 002: aiming the launcher's elevation and heading).
Press, Teukolsky, Vetterling & Flannery (2007), Numerical Recipes, 3rd ed., sections 9.4
(Newton's method with bracketing) and 9.7 (Newton's method for systems).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba as nb
import numpy as np

from tennislab.core._jit import JIT
from tennislab.core.events import COLUMNS
from tennislab.core.flight import FlightParams, FlightTable, fly_batch
from tennislab.core.launch import launch_rows, launch_states
from tennislab.errors import InputError

#: Finite-difference step of the angles [rad] (2 mm of landing for a 20 m flight: far above the batch
#: kernel's ~1e-6 m event noise at its default tolerance, far below any nonlinearity)
FD_STEP = 1e-4
TOL = 1e-5  #: [m] a launch has converged when its target point is matched to this distance
MAX_ITER = 25  #: Newton iterations at most
MAX_STEP = 0.1  #: [rad] largest change of an angle in one Newton step
#: Default elevation scan of a landing target [rad]: -20 to 80 deg in 1 deg steps (the launcher's range)
SCAN_GRID = np.radians(np.arange(-20.0, 80.5, 1.0))
BRACKET_WIDEN = 3  #: scan steps by which a branch's bracket is widened for the Newton safeguard
#: A final miss below this many ``tol`` counts as converged (the last Newton step is not re-checked)
CONVERGED_FACTOR = 10.0
#: Batches smaller than this are flown on one thread (on busy cores a parallel kernel waits for its slowest thread)
PARALLEL_MIN = 4096

BRANCHES = ("low", "high")
TARGETS = ("landing", "net")

#: ``Shots.reason`` codes: why a launch has no solution
OK, NO_FLIGHT, TOO_FAR, TOO_NEAR, NO_BRANCH, NOT_CONVERGED = range(6)
REASONS = (
    "ok",
    "no flight lands",
    "beyond the reach",
    "nearer than the shortest flight",
    "no such branch",
    "no convergence",
)


@dataclass(frozen=True)
class OnSteps:
    """The on-step neighbours of each solution, flown (``k`` candidates per launch, padded).

    ``elevation``, ``heading`` (N, k) [rad]; ``valid`` (N, k) marks real candidates; ``table`` the
    flights of the N k candidates (row i k + j is candidate j of launch i); ``miss`` (N, k) [m] the
    distance of each candidate's target point from the target (NaN where it has none); ``best``
    (N,) the index of the nearest candidate (-1 when none lands).
    """

    elevation: np.ndarray
    heading: np.ndarray
    valid: np.ndarray
    table: FlightTable
    miss: np.ndarray
    best: np.ndarray


@dataclass(frozen=True)
class Scan:
    """The elevation scan of landing targets (N launches; module docstring).

    ``reach`` (N, 2) [m]: the shortest and longest distance flown along the target's direction
    (NaN where no flight lands); ``split`` (N,) [rad] the elevation of the longest flight;
    ``bracket`` (N, 2) [rad] the grid interval holding the asked branch's crossing (NaN without);
    ``start`` (N,) [rad] its linear interpolation; ``nearest`` (N,) [rad] the grid elevation whose
    flight lands nearest the target distance (a best effort where there is no crossing);
    ``reason`` (N,) codes (:data:`REASONS`).
    """

    reach: np.ndarray
    split: np.ndarray
    bracket: np.ndarray
    start: np.ndarray
    nearest: np.ndarray
    reason: np.ndarray


@dataclass(frozen=True)
class Shots:
    """Launches aimed at their targets (arrays of N; angles [rad], lengths [m]).

    ``miss`` is the distance left between the flight's target point (landing, or net-plane
    crossing) and the target; ``converged`` marks launches matched to ``CONVERGED_FACTOR`` x ``tol``
    whose flight lands (status ``landed``); ``jacobian`` (N, 2, 2) [m/rad] the derivative of the
    target point with respect to (elevation, heading) at the last iteration (NaN if none);
    ``table`` the event table of the aimed flights; ``reason`` why a launch has no solution
    (:data:`REASONS`); ``scan`` the elevation scan (landing targets without a start);
    ``on_steps`` the on-step neighbours (with ``steps``).
    """

    elevation: np.ndarray
    heading: np.ndarray
    states: np.ndarray
    table: FlightTable
    miss: np.ndarray
    converged: np.ndarray
    jacobian: np.ndarray
    iterations: int
    flights: int
    reason: np.ndarray
    scan: Scan | None = None
    on_steps: OnSteps | None = None


def _fly(states: np.ndarray, params: FlightParams, rtol: float | None) -> FlightTable:
    return fly_batch(states, params, rtol=rtol, atol=rtol, parallel=len(states) >= PARALLEL_MIN)


def _point(tab: FlightTable, at: str) -> np.ndarray:
    """The target point of each flight (N, 2): landing (x, y) or net-plane crossing (y, z); NaN if none."""
    if at == "landing":
        xy = np.column_stack([tab["land_x"], tab["land_y"]])
        xy[~tab.ok] = np.nan
        return xy
    return np.column_stack([tab["net_y"], tab["net_z"]])


def first_guess(position, speed, net_yz, gravity: float = 9.81) -> tuple[np.ndarray, np.ndarray]:
    """Elevation and heading [rad] of a drag-free straight shot at the net point (the Newton start of net targets)."""
    p = np.asarray(position, dtype=float).reshape(-1, 3)
    ny, nz = np.asarray(net_yz, dtype=float).reshape(-1, 2).T
    dx = -p[:, 0]
    dy = ny - p[:, 1]
    dist = np.hypot(dx, dy)
    t = 1.1 * dist / np.maximum(np.asarray(speed, dtype=float), 1.0)
    return np.arctan2(nz - p[:, 2] + 0.5 * gravity * t * t, dist), np.arctan2(dy, dx)


def scan(position, speed, spin, target, params: FlightParams, branch: str, grid=SCAN_GRID, rtol=None) -> Scan:
    """Scan the elevation grid [rad] at the geometric heading of each landing target (module docstring).

    ``position`` (N, 3), ``speed`` (N,), ``spin`` (N, 3) components, ``target`` (N, 2); one
    ``fly_batch`` of N x len(grid) flights.  Returns the :class:`Scan` of the asked ``branch``.
    """
    p, v, w, tgt = position, speed, spin, target
    n, m = p.shape[0], grid.size
    dxy = tgt - p[:, :2]
    dist = np.hypot(dxy[:, 0], dxy[:, 1])
    e = dxy / np.maximum(dist, 1e-300)[:, None]
    head = np.arctan2(dxy[:, 1], dxy[:, 0])
    rep = np.repeat(np.arange(n), m)
    st = launch_states(p[rep], v[rep], np.tile(grid, n), head[rep], w[rep, 0], w[rep, 1], w[rep, 2])
    xy = _point(_fly(st, params, rtol), "landing").reshape(n, m, 2)
    f = np.einsum("nmk,nk->nm", xy - p[:, None, :2], e) - dist[:, None]
    ok = np.isfinite(f)
    reach = np.full((n, 2), np.nan)
    split = np.full(n, np.nan)
    bracket = np.full((n, 2), np.nan)
    start = np.full(n, np.nan)
    nearest = np.full(n, np.nan)
    reason = np.full(n, OK)
    for i in range(n):
        fi, oki = f[i], ok[i]
        if not oki.any():
            reason[i] = NO_FLIGHT
            continue
        nearest[i] = grid[int(np.argmin(np.where(oki, np.abs(fi), np.inf)))]
        reach[i] = dist[i] + np.nanmin(fi), dist[i] + np.nanmax(fi)
        split[i] = grid[int(np.argmax(np.where(oki, fi, -np.inf)))]
        if np.nanmax(fi) < 0:
            reason[i] = TOO_FAR
            continue
        if np.nanmin(fi) > 0:
            reason[i] = TOO_NEAR
            continue
        both = oki[:-1] & oki[1:]
        if branch == "low":
            cross = np.flatnonzero(both & (fi[:-1] < 0) & (fi[1:] >= 0))
            k = int(cross[0]) if cross.size else -1
        else:
            cross = np.flatnonzero(both & (fi[:-1] >= 0) & (fi[1:] < 0))
            k = int(cross[-1]) if cross.size else -1
        if k < 0:
            reason[i] = NO_BRANCH
            continue
        bracket[i] = grid[k], grid[k + 1]
        start[i] = grid[k] + (grid[k + 1] - grid[k]) * fi[k] / (fi[k] - fi[k + 1])
    return Scan(reach, split, bracket, start, nearest, reason)


def _rows(position, speed, spin, target, n_hint: int | None = None):
    """Broadcast the inputs to N rows: position (N, 3), speed (N,), spin (N, 3), target (N, 2)."""
    p = np.asarray(position, dtype=float)
    v = np.asarray(speed, dtype=float).reshape(-1)
    w = np.asarray(spin, dtype=float)
    t = np.asarray(target, dtype=float)
    if p.shape[-1:] != (3,) or p.ndim > 2:
        raise InputError(f"position: expected (3,) or (N, 3), got shape {p.shape}")
    if w.shape[-1:] != (3,) or w.ndim > 2:
        raise InputError(f"spin: expected (3,) or (N, 3) components [rad/s], got shape {w.shape}")
    if t.shape[-1:] != (2,) or t.ndim > 2:
        raise InputError(f"target: expected (2,) or (N, 2), got shape {t.shape}")
    try:
        n = np.broadcast_shapes(p.shape[:-1] or (1,), v.shape, w.shape[:-1] or (1,), t.shape[:-1] or (1,))[0]
    except ValueError:
        raise InputError("shoot: position, speed, spin and target do not broadcast to one number of launches") from None
    return (
        np.ascontiguousarray(np.broadcast_to(p.reshape(-1, 3), (n, 3))),
        np.broadcast_to(v, (n,)).copy(),
        np.ascontiguousarray(np.broadcast_to(w.reshape(-1, 3), (n, 3))),
        np.ascontiguousarray(np.broadcast_to(t.reshape(-1, 2), (n, 2))),
    )


def shoot(
    position,
    speed,
    target,
    params: FlightParams,
    *,
    spin=(0.0, 0.0, 0.0),
    at: str = "landing",
    branch: str = "low",
    start: tuple | None = None,
    bounds: tuple | None = None,
    grid=SCAN_GRID,
    tol: float = TOL,
    max_iter: int = MAX_ITER,
    rtol: float | None = None,
    steps: tuple | None = None,
    step_extra: tuple[int, int] = (0, 0),
) -> Shots:
    """Solve elevation and heading of N launches so that each reaches its target (module docstring).

    Parameters
    ----------
    position : (3,) or (N, 3) launch points (ball centre) [m]
    speed : scalar or (N,) launch speeds [m/s]
    target : (2,) or (N, 2): landing points (x, y) [m] (``at="landing"``) or net-plane
        crossings (y, z) [m] (``at="net"``; the launch must not lie on x = 0)
    params : flight physics
    spin : (3,) or (N, 3) spin components (topspin, sidespin, along the path) [rad/s] in the
        launch frame (:func:`tennislab.core.launch.spin_vector`), kept as the angles change
    at : ``landing`` or ``net``
    branch : ``low`` or ``high`` (landing targets)
    start : optional (elevation, heading) [rad], scalars or (N,) (a previous solution); landing
        targets without a start are scanned over ``grid`` [rad]
    bounds : optional (lo, hi) elevations [rad], scalars or (N,), keeping a landing Newton on its branch
    tol : [m] convergence distance; ``max_iter`` iterations at most
    rtol : ``fly_batch`` tolerance (default: the aero model's ``batch_tol``)
    steps : optional (elevations, headings) [rad], the sorted angles a machine can dial; with
        ``step_extra`` (E_a, E_b) extra steps beyond floor/ceil of each solution
    """
    if at not in TARGETS:
        raise InputError(f"at: {at!r} is not one of {', '.join(TARGETS)}")
    if at == "landing" and branch not in BRANCHES:
        raise InputError(f"branch: {branch!r} is not one of {', '.join(BRANCHES)}")
    p, v, w, tgt = _rows(position, speed, spin, target)
    n = p.shape[0]
    if at == "net" and np.any(p[:, 0] == 0.0):
        raise InputError("position: a launch point lies on the net plane x = 0")
    reason = np.full(n, OK)
    sc = None
    flights0 = 0
    if start is not None:
        a, b = (np.array(np.broadcast_to(np.asarray(s, dtype=float), (n,)), copy=True) for s in start)
        lo, hi = (-0.5 * math.pi, 0.5 * math.pi) if bounds is None else bounds
        lo, hi = (np.broadcast_to(np.asarray(x, dtype=float), (n,)).copy() for x in (lo, hi))
    elif at == "net":
        a, b = first_guess(p, v, tgt, params.atmosphere.gravity)
        lo, hi = np.full(n, -0.5 * math.pi), np.full(n, 0.5 * math.pi)
    else:
        grid = np.asarray(grid, dtype=float)
        step = float(np.median(np.diff(grid))) if grid.size > 1 else math.radians(1.0)
        sc = scan(p, v, w, tgt, params, branch, grid, rtol)
        flights0 = n * grid.size
        reason = sc.reason.copy()
        a = np.where(reason == OK, sc.start, 0.0)
        b = np.arctan2(tgt[:, 1] - p[:, 1], tgt[:, 0] - p[:, 0])
        wide = BRACKET_WIDEN * step
        if branch == "low":
            lo = np.maximum(grid[0], sc.bracket[:, 0] - wide)
            hi = np.maximum(sc.bracket[:, 1], np.minimum(sc.split, sc.bracket[:, 1] + wide))
        else:
            lo = np.minimum(sc.bracket[:, 0], np.maximum(sc.split, sc.bracket[:, 0] - wide))
            hi = np.minimum(grid[-1], sc.bracket[:, 1] + wide)
        if bounds is not None:
            lo = np.maximum(lo, bounds[0])
            hi = np.minimum(hi, bounds[1])
    a, b, jac, it, flights, rows = _newton(p, v, w, tgt, params, at, a, b, lo, hi, reason == OK, tol, max_iter, rtol)
    flights += flights0
    st = launch_states(p, v, a, b, w[:, 0], w[:, 1], w[:, 2])
    again = np.isnan(rows[:, 0])  # a launch matched in an iteration kept its angles: that flight is its table row
    if again.any():
        rows[again] = _fly(st[again], params, rtol).data
        flights += int(again.sum())
    tab = FlightTable(rows, params.ball.radius)
    miss = np.hypot(*(_point(tab, at) - tgt).T)
    conv = (reason == OK) & np.isfinite(miss) & (miss < CONVERGED_FACTOR * tol) & tab.ok
    reason = np.where((reason == OK) & ~conv, NOT_CONVERGED, reason)
    on = None
    if steps is not None:
        on = _on_steps(p, v, w, tgt, params, at, a, b, steps, step_extra, sc, branch, rtol)
        flights += int(on.valid.sum())
    return Shots(a, b, st, tab, miss, conv, jac, it, flights, reason, sc, on)


def _newton(p, v, w, tgt, params, at, a, b, lo, hi, live, tol, max_iter, rtol):
    """The batched Newton iterations (module docstring); returns (a, b, jacobian, iterations, flights, rows): per
    launch matched within ``tol`` its flight's event-table row (it is not moved again, so the final table needs
    no new flight of it), NaN rows for the others."""
    n = p.shape[0]
    jac = np.full((n, 2, 2), np.nan)
    rows = np.full((n, len(COLUMNS)), np.nan)
    active = np.flatnonzero(live)
    flights = 0
    it = 0
    h = FD_STEP
    for it in range(1, max_iter + 1):  # noqa: B007  (the count is reported)
        m = active.size
        if m == 0:
            break
        ia = active
        idx = np.concatenate([ia, ia, ia])
        aa = np.concatenate([a[ia], a[ia] + h, a[ia]])
        bb = np.concatenate([b[ia], b[ia], b[ia] + h])
        st = launch_rows(p[idx], idx.size, v[idx], aa, bb, w[idx, 0], w[idx, 1], w[idx, 2])  # (all (3m,) already)
        tab = _fly(st, params, rtol)
        pt = _point(tab, at)
        flights += 3 * m
        done = _newton_update(pt, tgt, ia, a, b, lo, hi, jac, h, tol, at == "landing")
        rows[ia[done]] = tab.data[:m][done]
        active = ia[~done]
    return a, b, jac, it, flights, rows


@nb.njit(**JIT)
def _newton_update(pt, tgt, ia, a, b, lo, hi, jac, h, tol, landing):
    """One safeguarded Newton step of the launches ``ia`` in place (module docstring), from the target points
    ``pt`` (3 m, 2) of (a, b), (a + h, b), (a, b + h): updates ``a``, ``b`` and ``jac``; returns the mask (m,)
    of those already within ``tol`` (not moved)."""
    m = ia.size
    done = np.zeros(m, dtype=np.bool_)
    for j in range(m):
        i = ia[j]
        f0x, f0y = pt[j, 0] - tgt[i, 0], pt[j, 1] - tgt[i, 1]
        jax, jay = (pt[m + j, 0] - pt[j, 0]) / h, (pt[m + j, 1] - pt[j, 1]) / h
        jbx, jby = (pt[2 * m + j, 0] - pt[j, 0]) / h, (pt[2 * m + j, 1] - pt[j, 1]) / h
        jac[i, 0, 0], jac[i, 1, 0], jac[i, 0, 1], jac[i, 1, 1] = jax, jay, jbx, jby
        miss = math.hypot(f0x, f0y)
        ok = math.isfinite(miss) and math.isfinite(jax) and math.isfinite(jay)
        ok = ok and math.isfinite(jbx) and math.isfinite(jby)
        dn = ok and miss < tol
        det = jax * jby - jay * jbx
        good = ok and math.isfinite(det) and abs(det) > 1e-12 and not dn
        da, db = 0.0, 0.0
        if good:
            da = -(jby * f0x - jbx * f0y) / det
            db = -(-jay * f0x + jax * f0y) / det
        scale = max(1.0, max(abs(da), abs(db)) / MAX_STEP)
        an = a[i] + da / scale
        b[i] += db / scale
        if not landing:
            if not ok:
                an += 0.02  # a launch whose flight never reached the net: aim higher and retry
        else:  # a landing target: back into the bracket (halfway to its bound, or to its middle when lost)
            if an < lo[i]:
                an = 0.5 * (a[i] + lo[i])
            if an > hi[i]:
                an = 0.5 * (a[i] + hi[i])
            if not ok or (not good and not dn):
                an = 0.5 * (a[i] + 0.5 * (lo[i] + hi[i]))
        a[i] = an
        done[j] = dn
    return done


def _neighbours(values: np.ndarray, x: np.ndarray, extra: int) -> np.ndarray:
    """Indices (N, 2 + 2 extra) of the steps floor - extra .. ceil + extra around each x (-1 outside)."""
    k = np.searchsorted(values, x, side="right") - 1  # floor
    offs = np.arange(-extra, extra + 2)
    idx = k[:, None] + offs[None, :]
    return np.where((idx >= 0) & (idx < values.size), idx, -1)


def _on_steps(p, v, w, tgt, params, at, a, b, steps, extra, sc, branch, rtol) -> OnSteps:
    elev, head = (np.sort(np.asarray(s, dtype=float)) for s in steps)
    ia = _neighbours(elev, a, int(extra[0]))
    ib = _neighbours(head, b, int(extra[1]))
    n, ka, kb = a.size, ia.shape[1], ib.shape[1]
    A = np.repeat(np.where(ia >= 0, elev[np.maximum(ia, 0)], np.nan), kb, axis=1)
    B = np.tile(np.where(ib >= 0, head[np.maximum(ib, 0)], np.nan), (1, ka))
    valid = np.isfinite(A) & np.isfinite(B) & np.isfinite(a)[:, None]
    if at == "landing" and sc is not None:  # keep the branch's side of the longest flight
        s = sc.split[:, None]
        with np.errstate(invalid="ignore"):
            valid &= ~(A > s + 1e-12) if branch == "low" else ~(A < s - 1e-12)
    k = A.shape[1]
    rows = np.repeat(np.arange(n), k)
    flat = valid.reshape(-1)
    st = launch_states(
        p[rows],
        v[rows],
        np.where(flat, A.reshape(-1), 0.0),
        np.where(flat, B.reshape(-1), 0.0),
        w[rows, 0],
        w[rows, 1],
        w[rows, 2],
    )
    st[~flat, 2] = np.nan  # padding: a bad start, never flown to a result
    tab = _fly(st, params, rtol)
    miss = np.hypot(*(_point(tab, at) - tgt[rows]).T).reshape(n, k)
    miss[~valid] = np.nan
    fin = np.where(np.isfinite(miss), miss, np.inf)
    best = np.where(np.isfinite(fin).any(axis=1) & (fin.min(axis=1) < np.inf), fin.argmin(axis=1), -1)
    return OnSteps(A, B, valid, tab, miss, best)


__all__ = [
    "BRANCHES",
    "FD_STEP",
    "MAX_ITER",
    "OnSteps",
    "REASONS",
    "SCAN_GRID",
    "Scan",
    "Shots",
    "TOL",
    "first_guess",
    "scan",
    "shoot",
]
