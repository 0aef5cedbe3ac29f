"""Aiming on the machine's steps: a search over every setting, heights included, built on a few flights.

The machine dials its height in 0.1 m, its speed in 1 km/h, its elevation, heading and spin axis in
1 deg and its spin rate in 1 rpm steps (Wojcicki, Pucilowski & Kulesza 2010, section 2).  Rounding the
exact angles alone misses by decimetres; the search below moves every setting within the user's
tolerances to land nearer, and flies only what can win.

Rows.  One row per launch height searched (the asked one, or every step when the height is free)
and per branch (low, high).  The reach map (:mod:`.reach`) says where each row's exact elevation
lies; three elevation steps around it are flown at the asked (rounded) speed and spin, at a heading
b0 near the exact one, plus three flights that give the landing's sensitivity to the speed (one speed
step away: a parent of stage 2, taken from there, not flown again) and to the two spin components.
The three landings bracket the row's exact solution (else the row is solved by
:func:`tennislab.core.shoot.shoot` from a scan, and flown again).

Headings cost no flight.  Without wind a launch turned by db lands where it landed, turned by db
about the machine: every heading step of a row is predicted exactly from the flights at b0.

Candidates.  For each speed step within the speed tolerance, the elevation steps around that
speed's exact elevation (predicted from the row's sensitivities) are flown at b0; every heading
step around the exact heading and, per (elevation, speed, heading), the quantised spins of
:func:`._spin.variants` give candidates with predicted landings (the spin's effect linear, with the
row's sensitivity).  The best :data:`TOP` of each branch (and the best of those whose parent flight
clears the net and meets the preferences) are flown; the best :data:`REFINE` flown candidates are
refined :data:`ROUNDS` times (their measured miss, the spin variants again, flown).  Everything
flown is returned; :mod:`.aim` chooses.

Physics of what it can reach: speed, elevation, height and the topspin component move the landing
along the flight; only the heading (rays 1 deg apart: 0.37 m at 21 m) and a sidespin component move
it across (docs/launcher.md, "What the machine's steps allow").
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numba as nb
import numpy as np

import tennislab.launcher._select as _select
import tennislab.launcher._spin as _spin
from tennislab.core.flight import FlightParams, FlightTable, fly_batch
from tennislab.core.shoot import shoot
from tennislab.launcher.machine import MachineSpec, Range, machine_states
from tennislab.launcher.preferences import Preferences, Tolerances, spin_change_rpm
from tennislab.launcher.reach import ReachMap
from tennislab.units import KMH, RPM

#: The height preferred when it is searched (ties of the miss go to the height nearest it) [m]
REFERENCE_HEIGHT_M = 1.0
SPIN_FD_RPM = 20.0  #: spin-component step of the sensitivity flights [rpm]
TOP = 32  #: predicted-best candidates flown per branch
PRUNE = 64  #: (parent flight, heading step) pairs per branch whose quantised spins are predicted
REFINE = 8  #: flown candidates refined per branch and round
PER_REFINE = 4  #: new spins flown per refined candidate
CLEARING = 8  #: parents that clear the net flown as they are, for a branch no candidate of which does
#: Tolerance (rtol = atol) of the flights that only guide the search (rows, parents, sensitivities): on the aim's
#: flights their landings move by at most 0.09 mm from those at the default 2e-7 (choppin2018; 0.03 mm
#: launcher2015), net clearance 0.16 mm, and the batches fly 28 % faster; the heading's steps are 0.37 m apart
#: at 21 m.  Measured, not tuned to an answer (the answers are candidates flown at the model's tolerance).
EXPLORE_TOL = 3e-6
#: The piecewise-linear tennislab2026 (batch_tol 2e-8) moves its landings by 1.6 mm at 15 times its tolerance:
#: models of a tolerance below this explore at their own
SMOOTH_BATCH_TOL = 2e-7
ROUNDS = 1  #: refinement rounds (the spin is nearly linear: one round rarely moves the answer)
#: Speeds, extra elevation and heading steps per row: of the asked (or the reference) height (False), of every
#: other height when the height is searched (True: 30 rows a branch; with the slowest of the False speeds too)
SPEEDS = {False: 7, True: 3}
ELEVATION_EXTRA = {False: 2, True: 0}
HEADING_EXTRA = {False: 1, True: 0}


@dataclass(frozen=True)
class Ask:
    """What is asked (edge units): target (x, y) [m]; ``speed_kmh``, ``spin_rpm``, ``spin_axis_deg`` as asked
    (validated, not rounded) and rounded to the steps (``q_*``); heights [m] searched; tolerances."""

    target: tuple[float, float]
    speed_kmh: float
    spin_rpm: float
    spin_axis_deg: float
    q_speed_kmh: float
    q_spin_rpm: float
    q_spin_axis_deg: float
    heights: np.ndarray
    height_free: bool
    tolerances: Tolerances


@dataclass(frozen=True)
class Row:
    """One row (height, branch) solved at the rounded asked settings: exact elevation ``a`` and heading
    ``b`` [deg], the heading ``b0`` [deg] its flights were flown at, the elevation of the longest flight
    ``split`` [deg], d rho / d a ``slope`` [m/deg], and in the frame of the launch direction the
    landing's sensitivity to the speed ``dv`` (2,) [m per km/h] and to the spin components ``J``
    (2, 2) [m/rpm]."""

    height: float
    branch: str
    a: float
    b: float
    b0: float
    split: float
    slope: float
    dv: np.ndarray
    J: np.ndarray


class Rows:
    """A search's rows as arrays (n rows): ``height`` [m], ``low`` (the branch), ``a``, ``b``, ``b0``, ``split``
    [deg], ``slope`` [m/deg], ``dv`` (n, 2) and ``J`` (n, 2, 2) (the fields of :class:`Row`); and, once the
    search has them, ``full`` (:func:`_full_rows`).  ``rows[i]`` is row i as a :class:`Row`."""

    FIELDS = ("height", "low", "a", "b", "b0", "split", "slope", "dv", "J")

    def __init__(self, height, low, a, b, b0, split, slope, dv, J):
        self.height, self.low = np.asarray(height, float), np.asarray(low, bool)
        self.a, self.b, self.b0 = np.asarray(a, float), np.asarray(b, float), np.asarray(b0, float)
        self.split, self.slope = np.asarray(split, float), np.asarray(slope, float)
        self.dv, self.J = np.asarray(dv, float).reshape(-1, 2), np.asarray(J, float).reshape(-1, 2, 2)
        self.full = np.ones(self.height.size, bool)  # every row, until :meth:`searched`

    @classmethod
    def of(cls, rows: list[Row]) -> Rows:
        """The rows of a list of :class:`Row`."""
        cols = {k: [getattr(r, k) for r in rows] for k in cls.FIELDS if k != "low"}
        return cls(low=[r.branch == "low" for r in rows], **cols)

    def __len__(self) -> int:
        return self.height.size

    def __getitem__(self, i) -> Row:
        i = int(i)
        br = "low" if self.low[i] else "high"
        a, b, b0, sp, sl = (float(getattr(self, k)[i]) for k in ("a", "b", "b0", "split", "slope"))
        return Row(float(self.height[i]), br, a, b, b0, sp, sl, self.dv[i], self.J[i])

    def __iter__(self):
        return (self[i] for i in range(len(self)))

    def take(self, idx) -> Rows:
        """The rows ``idx`` (a mask or indices)."""
        return Rows(*(getattr(self, k)[idx] for k in self.FIELDS))

    def plus(self, other: Rows) -> Rows:
        """These rows, then ``other``'s."""
        return Rows(*(np.concatenate([getattr(self, k), getattr(other, k)]) for k in self.FIELDS))

    def searched(self, ask: Ask) -> Rows:
        """These rows with ``full`` (:func:`_full_rows`) for ``ask``."""
        out = Rows(*(getattr(self, k) for k in self.FIELDS))
        out.full = _full_rows(ask, self.height)
        return out

    def on(self, name: str) -> np.ndarray:
        """Mask of the rows of branch ``name``."""
        return self.low if name == "low" else ~self.low


@dataclass(frozen=True)
class Candidates:
    """Every candidate flown: settings columns (edge units), its row and branch, and flight results."""

    height_m: np.ndarray
    elevation_deg: np.ndarray
    heading_deg: np.ndarray
    speed_kmh: np.ndarray
    spin_rpm: np.ndarray
    spin_axis_deg: np.ndarray
    row: np.ndarray
    land_x: np.ndarray
    land_y: np.ndarray
    miss_m: np.ndarray
    clearance_m: np.ndarray
    net_status: np.ndarray
    apex_z_m: np.ndarray
    flight_time_s: np.ndarray
    landing_speed_ms: np.ndarray
    landed: np.ndarray

    def take(self, mask) -> Candidates:
        return Candidates(**{k: v[mask] for k, v in self.__dict__.items()})


class Parents:
    """The flights at each row's heading b0 with the rounded asked spin, the parents of the candidates:
    keyed by (row index, speed step, elevation step) of machine ``spec``; the landing in the
    launch-direction frame (n, 2) [m] and (:func:`_info`) net clearance, net status, apex and flight time.
    Flights of the same kind flown for another purpose wait as ``spare`` (:meth:`add_spare`): a parent the
    search asks for is taken from them (:meth:`spare_of`) instead of flown again."""

    def __init__(self, spec: MachineSpec):
        self.spec = spec
        self.parts: list = []
        self.keys: list[np.ndarray] = []
        self.spare: tuple | None = None  # (row, speed, elevation, landing, info, key) of the spare flights

    def _key(self, ri, v, a) -> np.ndarray:
        sr, er = self.spec.speed, self.spec.elevation
        nv = int(round((sr.hi - sr.lo) / sr.step)) + 3
        na = int(round((er.hi - er.lo) / er.step)) + 3
        iv = np.rint((np.asarray(v, float) - sr.lo) / sr.step).astype(np.int64) + 1
        ia = np.rint((np.asarray(a, float) - er.lo) / er.step).astype(np.int64) + 1
        return (np.asarray(ri, np.int64) * nv + iv) * na + ia

    def new(self, ri, v, a) -> np.ndarray:
        """Mask of the (row, speed, elevation) not flown yet (to a landing)."""
        if not self.keys:
            return np.ones(np.shape(ri), bool)
        have = np.sort(np.concatenate(self.keys))
        if have.size == 0:
            return np.ones(np.shape(ri), bool)
        k = self._key(ri, v, a)
        return have[np.minimum(np.searchsorted(have, k), have.size - 1)] != k

    def __len__(self) -> int:
        return sum(k.size for k in self.keys)

    def add(self, ri, v, a, ell, info) -> None:
        ri, v, a = (np.broadcast_to(np.asarray(x), (len(ell),)) for x in (ri, v, a))
        ok = np.isfinite(ell[:, 0])
        part = (ri[ok].astype(int), v[ok].astype(float), a[ok].astype(float), ell[ok], info[ok])
        self.parts.append(part)
        self.keys.append(self._key(part[0], part[1], part[2]))

    def add_spare(self, ri, v, a, ell, info) -> None:
        """Flights (one per (row, speed, elevation)) kept aside, for :meth:`spare_of` (replaces any before)."""
        ri, v, a = (np.broadcast_to(np.asarray(x), (len(ell),)) for x in (ri, v, a))
        ri, v, a = ri.astype(int), v.astype(float), a.astype(float)
        self.spare = (ri, v, a, np.asarray(ell, float), np.asarray(info, float), self._key(ri, v, a))

    def spare_of(self, ri, v, a) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Of the (row, speed, elevation) asked, the mask of those a spare flight covers and its landings (n, 2)
        and info (n, 4)."""
        if self.spare is None or self.spare[5].size == 0:
            return np.zeros(np.shape(ri), bool), np.empty((0, 2)), np.empty((0, 4))
        sk = self.spare[5]
        order = np.argsort(sk, kind="stable")
        k = self._key(ri, v, a)
        pos = np.minimum(np.searchsorted(sk, k, sorter=order), sk.size - 1)
        hit = sk[order[pos]] == k
        idx = order[pos[hit]]
        return hit, self.spare[3][idx], self.spare[4][idx]

    def keep(self, mask) -> Parents:
        """The parents (and spare flights) of the rows ``mask`` (over the rows they index) keeps, their rows
        renumbered as those rows are once the others are dropped (so that they index the kept rows); these
        parents themselves when every row is kept."""
        mask = np.asarray(mask, bool)
        if mask.all():
            return self
        renumber = np.cumsum(mask) - 1
        out = Parents(self.spec)
        for ri, v, a, ell, info in self.parts:
            ok = mask[ri]
            out.add(renumber[ri[ok]], v[ok], a[ok], ell[ok], info[ok])
        if self.spare is not None:
            ri, v, a, ell, info, _ = self.spare
            ok = mask[ri]
            out.add_spare(renumber[ri[ok]], v[ok], a[ok], ell[ok], info[ok])
        return out

    def arrays(self):
        """(row, speed, elevation, landing (n, 2), info (n, 4)) of every parent."""
        return tuple(np.concatenate([p[k] for p in self.parts]) for k in range(5))


def speed_steps(rng: Range, asked: float, tol: float, count: int | None = None) -> np.ndarray:
    """Machine speed steps within ``tol`` of ``asked`` (and always the nearest step) [km/h]; with ``count``,
    the ``count`` nearest the asked speed."""
    return _speed_steps(rng, float(asked), float(tol), count).copy()


@functools.lru_cache(maxsize=64)
def _speed_steps(rng: Range, asked: float, tol: float, count: int | None) -> np.ndarray:
    """:func:`speed_steps`, kept for the last requests."""
    lo, hi = max(rng.lo, asked - tol), min(rng.hi, asked + tol)
    k0 = math.ceil((lo - rng.lo) / rng.step - 1e-9)
    k1 = math.floor((hi - rng.lo) / rng.step + 1e-9)
    vals = np.unique(np.round(np.append(rng.lo + np.arange(k0, k1 + 1) * rng.step, rng.quantise(asked)), 9))
    if count is not None and vals.size > count:
        vals = np.sort(vals[np.argsort(np.abs(vals - asked), kind="stable")[:count]])
    return vals


class Shooter:
    """Flies arrays of settings from the machine (one ``fly_batch`` per call, on every core: even a batch of 8
    flights is faster so on 2 cores, 28 against 32 us, 512 flights 0.47 against 0.94 ms; worker processes run
    with one thread each, :mod:`tennislab.batch.schedulers`) and counts the flights.

    ``explore=True`` flies at :data:`EXPLORE_TOL` (the flights that only guide the search: stages 1 and 2) when
    the aero model is smooth (its ``batch_tol`` at least :data:`SMOOTH_BATCH_TOL`); the candidates, whose
    landings are the answers, are flown at the model's own tolerance."""

    def __init__(self, spec: MachineSpec, params: FlightParams):
        self.spec, self.params, self.flights = spec, params, 0
        tol = params.aero.batch_tol
        self.explore_tol = max(tol, EXPLORE_TOL) if tol >= SMOOTH_BATCH_TOL else tol

    def __call__(self, h, v, a, b, w, g, explore: bool = False) -> FlightTable:
        st = machine_states(self.spec, h, v, a, b, w, g)
        self.flights += len(st)
        if explore:
            return fly_batch(st, self.params, rtol=self.explore_tol, atol=self.explore_tol)
        return fly_batch(st, self.params)


def _polar(tab: FlightTable, pos, b0) -> np.ndarray:
    """Landings relative to the machine in the frame of heading b0 [deg] (n, 2) (NaN where none)."""
    xy = np.column_stack([tab["land_x"] - pos[0], tab["land_y"] - pos[1]])
    xy[~tab.ok] = np.nan
    c, s = np.cos(np.radians(b0)), np.sin(np.radians(b0))
    return np.column_stack([c * xy[:, 0] + s * xy[:, 1], -s * xy[:, 0] + c * xy[:, 1]])


def _rotate(ell: np.ndarray, b) -> np.ndarray:
    """Vectors (..., 2) of the heading-0 frame turned by b [deg]."""
    c, s = np.cos(np.radians(b)), np.sin(np.radians(b))
    return np.stack([c * ell[..., 0] - s * ell[..., 1], s * ell[..., 0] + c * ell[..., 1]], axis=-1)


def _components(w, g) -> np.ndarray:
    g = np.radians(g)
    return np.stack([w * np.cos(g), w * np.sin(g)], axis=-1)


def _rate_axis(om) -> tuple[np.ndarray, np.ndarray]:
    return np.hypot(om[..., 0], om[..., 1]), np.degrees(np.arctan2(om[..., 1], om[..., 0]))


def _speed_fd(spec: MachineSpec, vq: float) -> float:
    """The speed of the speed-sensitivity flight from the step ``vq`` [km/h]: one step of the machine up (down at
    the top of the range), so that it is a setting of the machine (a parent stage 2 may ask for)."""
    up = round(vq + spec.speed.step, 9)
    return up if up <= spec.speed.hi + 1e-9 else round(vq - spec.speed.step, 9)


def _steps(rng: Range, lo: float, hi: float) -> np.ndarray:
    """The steps of ``rng`` in [lo, hi]."""
    k0 = math.ceil((max(lo, rng.lo) - rng.lo) / rng.step - 1e-9)
    k1 = math.floor((min(hi, rng.hi) - rng.lo) / rng.step + 1e-9)
    return np.round(rng.lo + np.arange(k0, k1 + 1) * rng.step, 9)


def rows_of(shoot5, spec: MachineSpec, params: FlightParams, rmap: ReachMap, ask: Ask) -> tuple[Rows, Parents]:
    """Stage 1 (module docstring): every row's exact solution and sensitivities; and the flights at b0
    by (row index, speed, elevation) -> landing in the launch-direction frame (for reuse)."""
    P = np.asarray(spec.position, float)
    T = np.asarray(ask.target, float)
    D = float(np.hypot(*(T - P)))
    beta = math.degrees(math.atan2(T[1] - P[1], T[0] - P[0]))
    er = spec.elevation
    om_q = _components(ask.q_spin_rpm, ask.q_spin_axis_deg)
    maps = rmap.aim_both(D, ask.heights, ask.q_speed_kmh, om_q[0], om_q[1])  # (low, high) over the heights
    el, phi, split = (np.concatenate([m[k] for m in maps]) for k in ("elevation_deg", "phi", "split_deg"))
    hit = np.isfinite(el)
    if not hit.any():
        return Rows.of([]), Parents(spec)
    nh = len(ask.heights)
    H = np.tile(np.asarray(ask.heights, float), 2)[hit]
    low = np.repeat([True, False], nh)[hit]
    el, split = el[hit], split[hit]
    n = H.size
    b0 = beta - np.degrees(phi[hit])
    ac = np.clip(np.round(el), er.lo, er.hi)
    E = np.clip(ac[:, None] + np.array([-1.0, 0.0, 1.0]), er.lo, er.hi)
    v_fd = _speed_fd(spec, ask.q_speed_kmh)
    fw, fg = _rate_axis(om_q + np.array([[SPIN_FD_RPM, 0.0], [0.0, SPIN_FD_RPM]]))
    vq, wq, gq = ask.q_speed_kmh, ask.q_spin_rpm, ask.q_spin_axis_deg
    tab = shoot5(
        np.concatenate([np.repeat(H, 3), H, H, H]),
        np.concatenate([np.full(3 * n, vq), np.full(n, v_fd), np.full(2 * n, vq)]),
        np.concatenate([E.reshape(-1), ac, ac, ac]),
        np.concatenate([np.repeat(b0, 3), b0, b0, b0]),
        np.concatenate([np.full(4 * n, wq), np.full(n, fw[0]), np.full(n, fw[1])]),
        np.concatenate([np.full(4 * n, gq), np.full(n, fg[0]), np.full(n, fg[1])]),
        explore=True,
    )
    ell = _polar(tab, P, np.concatenate([np.repeat(b0, 3), b0, b0, b0]))
    le = ell[: 3 * n].reshape(n, 3, 2)
    info_all = _info(tab)
    info = info_all[: 3 * n].reshape(n, 3, 4)
    a, b, slope = _brackets(E, le, D, beta, low)
    base = le[:, 1]
    dv = (ell[3 * n : 4 * n] - base) / (v_fd - vq)
    J = np.stack([ell[4 * n : 5 * n] - base, ell[5 * n :] - base], axis=2) / SPIN_FD_RPM
    good = np.isfinite(a) & np.isfinite(dv).all(axis=1) & np.isfinite(J).all(axis=(1, 2))
    rows = Rows(H, low, a, b, b0, split, slope, dv, J).take(good)
    flown = Parents(spec)
    gi = np.flatnonzero(good)
    flown.add(np.repeat(np.arange(gi.size), 3), vq, E[gi].reshape(-1), le[gi].reshape(-1, 2), info[gi].reshape(-1, 4))
    # the speed's sensitivity flights, one speed step away: stage 2 may ask for them as parents
    flown.add_spare(np.arange(gi.size), v_fd, ac[gi], ell[3 * n : 4 * n][gi], info_all[3 * n : 4 * n][gi])
    solved = []
    for i in np.flatnonzero(~good).tolist():
        row, _ = _solve_row(shoot5, spec, params, ask, float(H[i]), "low" if low[i] else "high", float(split[i]))
        if row is not None:
            solved.append(row)
    return (rows.plus(Rows.of(solved)) if solved else rows), flown


def probe(shoot5, spec: MachineSpec, params: FlightParams, ask: Ask, branch: str, rows: Rows) -> tuple[Rows, list]:
    """A branch the map found no row for: scanned for real at a few heights (the map may miss the edge of
    the reach).  Returns ``rows`` with the row found (if any) appended, and the (height, ``Shots``) of the
    failed scans (none once a row is found)."""
    hs = ask.heights
    picks = [hs[np.argmin(np.abs(hs - REFERENCE_HEIGHT_M))], hs.min(), hs.max()] if ask.height_free else [hs[0]]
    failed = []
    for h in dict.fromkeys(float(x) for x in picks):
        row, shots = _solve_row(shoot5, spec, params, ask, h, branch, math.nan)
        if row is not None:
            return rows.plus(Rows.of([row])), []
        failed.append((h, shots))
    return rows, failed


def _brackets(E, le, D, beta, low):
    """Per row, the exact elevation [deg] between two of its three flown steps (rho - D changes sign on the
    branch's side: rising for ``low``), its heading [deg] and d rho / d a [m/deg]; NaN where none (the lower
    interval wins when both bracket).  Compiled: :func:`_brackets_kernel`."""
    n = E.shape[0]
    out = np.empty((n, 3))
    _brackets_kernel(
        np.ascontiguousarray(E, dtype=float), np.ascontiguousarray(le, dtype=float), float(D), float(beta), low, out
    )
    return out[:, 0], out[:, 1], out[:, 2]


@nb.njit(cache=True, error_model="numpy")
def _brackets_kernel(E, le, D, beta, low, out):
    for i in range(E.shape[0]):
        out[i, 0] = out[i, 1] = out[i, 2] = np.nan
        for k in (0, 1):
            e0, e1 = E[i, k], E[i, k + 1]
            f0 = math.hypot(le[i, k, 0], le[i, k, 1]) - D
            f1 = math.hypot(le[i, k + 1, 0], le[i, k + 1, 1]) - D
            ok = math.isfinite(f0) and math.isfinite(f1) and e1 != e0 and f0 * f1 <= 0 and (f1 > f0) == low[i]
            if not ok:
                continue
            t = f0 / (f0 - f1 if f0 != f1 else 1.0)
            x = le[i, k, 0] + t * (le[i, k + 1, 0] - le[i, k, 0])
            y = le[i, k, 1] + t * (le[i, k + 1, 1] - le[i, k, 1])
            out[i, 0] = e0 + t * (e1 - e0)
            out[i, 1] = beta - math.atan2(y, x) * (180.0 / math.pi)
            out[i, 2] = (f1 - f0) / (e1 - e0)
            break


def _solve_row(shoot5, spec: MachineSpec, params: FlightParams, ask: Ask, h: float, branch: str, split: float):
    """A row the map did not bracket: :func:`~tennislab.core.shoot.shoot` from a scan, and its sensitivities."""
    P = np.asarray(spec.position, float)
    om = _components(ask.q_spin_rpm, ask.q_spin_axis_deg)
    grid = np.radians(_steps(spec.elevation, spec.elevation.lo, spec.elevation.hi))
    s = shoot(
        (P[0], P[1], h),
        ask.q_speed_kmh * KMH,
        ask.target,
        params,
        spin=(om[0] * RPM, om[1] * RPM, 0.0),
        branch=branch,
        grid=grid,
    )
    shoot5.flights += s.flights
    if not s.converged[0] or not spec.heading.lo - 10 <= math.degrees(s.heading[0]) <= spec.heading.hi + 10:
        return None, s
    a, b = math.degrees(s.elevation[0]), math.degrees(s.heading[0])
    vq = ask.q_speed_kmh
    v_fd = _speed_fd(spec, vq)
    w, g = _rate_axis(om + np.array([[0.0, 0.0], [0.0, 0.0], [SPIN_FD_RPM, 0.0], [0.0, SPIN_FD_RPM]]))
    ell = _polar(shoot5(h, [vq, v_fd, vq, vq], a, b, w, g, explore=True), P, b)
    e = ell[0] / max(np.hypot(*ell[0]), 1e-300)
    slope = float(e @ _rotate(s.jacobian[0][:, 0][None, :], -b)[0]) * math.radians(1.0)
    sp = math.degrees(float(s.scan.split[0])) if s.scan is not None else split
    J = np.column_stack([ell[2] - ell[0], ell[3] - ell[0]]) / SPIN_FD_RPM
    return Row(h, branch, a, b, b, sp, slope, (ell[1] - ell[0]) / (v_fd - vq), J), s


def _info(tab: FlightTable) -> np.ndarray:
    """Per flight (n, 4): net clearance [m], net status, apex [m], flight time [s] (for the acceptability pools)."""
    return np.column_stack([tab.clearance, tab["net_status"], tab["apex_z"], tab["land_t"]])


def _combos(shoot5, spec: MachineSpec, ask: Ask, ra: Rows, flown: Parents) -> Parents:
    """Stage 2: per row, the speed steps and the elevation steps around each speed's exact elevation, flown
    at the row's b0 with the rounded asked spin (those of stage 1 reused).  Updates and returns ``flown``."""
    er = spec.elevation
    P = np.asarray(spec.position, float)
    beta = math.degrees(math.atan2(ask.target[1] - P[1], ask.target[0] - P[0]))
    speeds = speed_steps(spec.speed, ask.speed_kmh, ask.tolerances.speed_kmh, SPEEDS[False])
    # the other heights: the speeds nearest the asked one, and the slowest, whose longer flight lets a sidespin
    # move the bounce farthest across (where the heading's steps leave a flat ball's worst misses)
    few = np.union1d(speed_steps(spec.speed, ask.speed_kmh, ask.tolerances.speed_kmh, SPEEDS[True]), speeds.min())
    extra = ELEVATION_EXTRA[False]
    full = ra.full  # the asked (or reference) height: the whole neighbourhood
    vq = ask.q_speed_kmh
    phi = np.radians(beta - ra.b)
    dv, slope, split, low = ra.dv, ra.slope, ra.split, ra.low
    drho_dv = np.cos(phi) * dv[:, 0] + np.sin(phi) * dv[:, 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        a_v = ra.a[:, None] - np.where(slope != 0, drho_dv / slope, 0.0)[:, None] * (speeds[None, :] - vq)  # (n, m)
    offs = np.arange(-extra, extra + 2) * er.step
    A = np.floor((a_v - er.lo) / er.step)[..., None] * er.step + er.lo + offs  # (n, m, k) elevation steps
    A = np.round(A, 9)
    inside = (A >= er.lo - 1e-9) & (A <= er.hi + 1e-9)
    side = np.where(low[:, None, None], A <= split[:, None, None] + 1e-9, A >= split[:, None, None] - 1e-9)
    keep = inside & side
    in_few = np.isin(speeds, few)
    light = ~full[:, None, None] & (~in_few[None, :, None] | (np.abs(offs - 0.5 * er.step) > er.step)[None, None, :])
    keep &= ~light  # the other heights: the speeds nearest the asked one, the floor and ceil of each elevation
    none = ~keep.any(axis=2) & (full[:, None] | in_few[None, :])  # none on the branch's side: the nearest
    A[..., 0] = np.where(none, np.clip(np.round((a_v - er.lo) / er.step) * er.step + er.lo, er.lo, er.hi), A[..., 0])
    keep[..., 0] |= none
    ri, mi, _ = np.nonzero(keep)
    vv, aa = speeds[mi], A[keep]
    todo = flown.new(ri, vv, aa)
    if todo.any():
        ri, vv, aa = ri[todo], vv[todo], aa[todo]
        have, ell_s, info_s = flown.spare_of(ri, vv, aa)  # flown already (stage 1's speed sensitivity)
        ell, info = np.empty((ri.size, 2)), np.empty((ri.size, 4))
        ell[have], info[have] = ell_s, info_s
        fly = np.flatnonzero(~have)
        if fly.size:
            b0 = ra.b0[ri[fly]]
            tab = shoot5(ra.height[ri[fly]], vv[fly], aa[fly], b0, ask.q_spin_rpm, ask.q_spin_axis_deg, explore=True)
            ell[fly], info[fly] = _polar(tab, P, b0), _info(tab)
        flown.add(ri, vv, aa, ell, info)  # in the order asked, spare or flown
    return flown


def _full_rows(ask: Ask, h: np.ndarray) -> np.ndarray:
    """Rows (their heights ``h`` [m]) searched in the whole neighbourhood: every row of an asked height; of a
    searched one, the rows at the step nearest :data:`REFERENCE_HEIGHT_M` (so that searching the height never
    lands farther than the reference height alone)."""
    if not ask.height_free:
        return np.ones(h.size, bool)
    ref = ask.heights[np.argmin(np.abs(ask.heights - REFERENCE_HEIGHT_M))]
    return np.abs(h - ref) < 1e-9


def _parent_ok(info: np.ndarray, need_net: bool, prefs: Preferences) -> np.ndarray:
    """Parents (flights at b0) that clear the net when they must and meet the preferences (an estimate for
    their candidates: a heading step or a spin change moves these little)."""
    with np.errstate(invalid="ignore"):
        ok = prefs.accepts(info[:, 2], info[:, 0], info[:, 3])
        if need_net:
            ok &= (info[:, 1] == 1) & (info[:, 0] >= 0)
    return ok


def _pools(low: np.ndarray, good: np.ndarray, ref: np.ndarray | None, top: int) -> tuple[np.ndarray, np.ndarray]:
    """The selection pools of the search, per branch (``low``, then the other): every entry (``top`` of them),
    those whose parent is acceptable (``good``, half as many) and, when the height is searched, the same two at
    the reference height (``ref``: it keeps the quota it has when it is asked).  Returns the pools' masks
    (pools, entries) and sizes."""
    pools = [(np.ones(low.size, bool), top), (good, top // 2)]
    if ref is not None:
        pools += [(ref, top), (ref & good, top // 2)]
    members = np.array([mask & on for on in (low, ~low) for mask, _ in pools])
    return members, np.array([size for _ in (0, 1) for _, size in pools], np.int64)


def _predicted(spec: MachineSpec, ask: Ask, ra: Rows, flown: Parents, need_net: bool, prefs: Preferences):
    """Every (flown parent, heading step, quantised spin) candidate with its predicted miss (module docstring):
    a :class:`Predicted`."""
    hr = spec.heading
    P = np.asarray(spec.position, float)
    T = np.asarray(ask.target, float)
    beta = math.degrees(math.atan2(T[1] - P[1], T[0] - P[0]))
    ri, speed, elev, ell, info = flown.arrays()
    need = beta - np.degrees(np.arctan2(ell[:, 1], ell[:, 0]))  # the heading that puts each on the target's ray
    extra = HEADING_EXTRA[False]
    offs = np.arange(-extra, extra + 2)
    base = hr.lo + np.floor((need - hr.lo) / hr.step) * hr.step
    B = np.round(base[:, None] + offs[None, :] * hr.step, 9)  # (n, m)
    n, m = B.shape
    par = np.repeat(np.arange(n), m)
    full = ra.full[ri][par]
    light = np.tile((offs < 0) | (offs > 1), n)  # the other heights: the floor and ceil of the heading
    B = B.reshape(-1)
    inside = (B >= hr.lo - 1e-9) & (B <= hr.hi + 1e-9) & (full | ~light)
    par, B, full = par[inside], B[inside], full[inside]
    L0 = P + _rotate(ell[par], B)
    om = _components(ask.q_spin_rpm, ask.q_spin_axis_deg)
    asked = (ask.spin_rpm, ask.spin_axis_deg)
    # prune: a candidate whose landing no allowed spin can bring near the best bound is not worth a variant (the
    # bound of a row's sensitivity: a turn of the heading does not change it)
    moves = _spin.reach(ra.J, np.broadcast_to(om, (ra.J.shape[0], 2)), asked, ask.tolerances)
    lb = np.maximum(np.hypot(*(L0 - T).T) - moves[ri[par]], 0.0)
    low = ra.low[ri[par]]
    good = _parent_ok(info[par], need_net, prefs)
    # the best bounds of each pool (a landing-less parent's NaN bound predicts no candidate: left out)
    keep = _select.best_of_pools(lb, *_pools(low, good, full if ask.height_free else None, PRUNE))
    par, B, L0 = par[keep], B[keep], L0[keep]
    J = ra.J[ri[par]]
    Jc = np.stack([_rotate(J[:, :, 0], B), _rotate(J[:, :, 1], B)], axis=2)
    om_b = np.broadcast_to(om, (len(par), 2))
    W, G, miss = _spin.variants(L0, Jc, om_b, T, asked, ask.tolerances, spec.spin, spec.spin_axis)
    r = ri[par]
    entries = {
        "row": r,
        "height": ra.height[r],
        "speed": speed[par],
        "elevation": elev[par],
        "heading": B,
        "info": info[par],
    }
    return Predicted(entries, W, G, miss)


class Predicted:
    """The candidates of :func:`_predicted`: n (parent flight, heading step) entries (``entries``: ``row``,
    ``height``, ``speed``, ``elevation``, ``heading``, ``info`` (n, 4)) times k spin variants each (``W``,
    ``G``, ``miss`` (n, k)); candidate j (flat) is variant j % k of entry j // k."""

    def __init__(self, entries: dict, W: np.ndarray, G: np.ndarray, miss: np.ndarray):
        self.entries, self.k = entries, W.shape[1]
        self.rate, self.axis, self.pred = W.reshape(-1), G.reshape(-1), miss.reshape(-1)

    def at(self, name: str, idx: np.ndarray) -> np.ndarray:
        """Column ``name`` (an entry's, or ``rate``, ``axis``, ``pred``) of the candidates ``idx``."""
        if name in ("rate", "axis", "pred"):
            return getattr(self, name)[idx]
        return self.entries[name][idx // self.k]


def _fly_candidates(shoot5, spec: MachineSpec, ask: Ask, rows_idx, cols) -> Candidates:
    h, v, a, b, w, g = cols
    tab = shoot5(h, v, a, b, w, g)
    xy = np.column_stack([tab["land_x"], tab["land_y"]])
    xy[~tab.ok] = np.nan
    return Candidates(
        height_m=np.asarray(h, float),
        elevation_deg=np.asarray(a, float),
        heading_deg=np.asarray(b, float),
        speed_kmh=np.asarray(v, float),
        spin_rpm=np.asarray(w, float),
        spin_axis_deg=np.asarray(g, float),
        row=np.asarray(rows_idx, int),
        land_x=xy[:, 0],
        land_y=xy[:, 1],
        miss_m=np.hypot(xy[:, 0] - ask.target[0], xy[:, 1] - ask.target[1]),
        clearance_m=tab.clearance,
        net_status=tab["net_status"].astype(int),
        apex_z_m=tab["apex_z"],
        flight_time_s=tab["land_t"],
        landing_speed_ms=np.sqrt(tab["land_vx"] ** 2 + tab["land_vy"] ** 2 + tab["land_vz"] ** 2),
        landed=tab.ok & np.isfinite(xy).all(axis=1),
    )


def _concat(parts: list[Candidates]) -> Candidates:
    return Candidates(**{k: np.concatenate([getattr(p, k) for p in parts]) for k in Candidates.__dataclass_fields__})


def search(shoot5, spec: MachineSpec, ask: Ask, rows: Rows, flown: Parents, need_net: bool, prefs: Preferences):
    """Stages 2 and 3 (module docstring) on the rows of :func:`rows_of`: every candidate flown."""
    ra = rows.searched(ask)
    flown = _combos(shoot5, spec, ask, ra, flown)
    pr = _predicted(spec, ask, ra, flown, need_net, prefs)
    rows_e = pr.entries["row"]
    low = ra.low[rows_e]  # per entry
    parent_ok = _parent_ok(pr.entries["info"], need_net, prefs)
    cols = ("height", "speed", "elevation", "heading", "rate", "axis")
    members, tops = _pools(low, parent_ok, ra.full[rows_e] if ask.height_free else None, TOP)
    pick, keys = _select.pool_picks(spec, pr, members, tops, cols)
    seen = set(keys.tolist()) if keys.dtype == np.int64 else {k.tobytes() for k in keys}
    flown_c = [_fly_candidates(shoot5, spec, ask, pr.at("row", pick), [pr.at(c, pick) for c in cols])]
    extra = _clearing_parents(spec, ask, ra, flown, flown_c[0], need_net, prefs, seen)
    if extra is not None:
        flown_c.append(_fly_candidates(shoot5, spec, ask, extra[0], extra[1:]))
    for _ in range(ROUNDS):
        new = _refine(spec, ask, ra, _concat(flown_c), need_net, prefs, seen)
        if new is None:
            break
        flown_c.append(_fly_candidates(shoot5, spec, ask, new[0], new[1:]))
    return _concat(flown_c)


def _clearing_parents(spec, ask: Ask, ra: Rows, flown: Parents, c: Candidates, need_net, prefs, seen: set):
    """A branch none of whose flown candidates clears the net (or meets the preferences): its parents that do,
    nearest the target first, with the rounded asked spin at their nearest heading step (so that a refusal
    can say how far the nearest acceptable step lands)."""
    _, pref_ok = acceptable(c, need_net, prefs)
    have = ra.low[c.row[pref_ok]]
    ri, speed, elev, ell, info = flown.arrays()
    low = ra.low[ri]
    good = np.where(low, not have.any(), not (~have).any()) & _parent_ok(info, need_net, prefs)
    if not good.any():
        return None
    P = np.asarray(spec.position, float)
    T = np.asarray(ask.target, float)
    beta = math.degrees(math.atan2(T[1] - P[1], T[0] - P[0]))
    ell, ri = ell[good], ri[good]
    b = spec.heading.quantise(beta - np.degrees(np.arctan2(ell[:, 1], ell[:, 0])))
    miss = np.hypot(*(P + _rotate(ell, b) - T).T)
    order = np.argsort(miss, kind="stable")[:CLEARING]
    h = ra.height[ri]
    v, a = speed[good], elev[good]
    cols = [h[order], v[order], a[order], np.atleast_1d(b)[order]]
    w = np.full(order.size, ask.q_spin_rpm)
    g = np.full(order.size, ask.q_spin_axis_deg)
    kk = _select.settings_key(spec, cols[0], cols[1], cols[2], cols[3], w, g)
    fresh = [(k.item() if kk.dtype == np.int64 else k.tobytes()) not in seen for k in kk]
    if not any(fresh):
        return None
    f = np.array(fresh)
    return [ri[order][f]] + [x[f] for x in cols] + [w[f], g[f]]


def _refine(spec: MachineSpec, ask: Ask, ra: Rows, c: Candidates, need_net, prefs, seen: set):
    """New spins for the best flown candidates of each branch from their measured misses (module docstring)."""
    net_ok, pref_ok = acceptable(c, need_net, prefs)
    low = ra.low[c.row]
    picks = []
    for on in (low, ~low):
        for mask in (pref_ok, net_ok, c.landed):
            m = mask & on
            if m.any():
                break
        idx = np.flatnonzero(m)
        picks.append(idx[np.argsort(c.miss_m[idx], kind="stable")][:REFINE])
    idx = np.concatenate(picks)
    if idx.size == 0:
        return None
    T = np.asarray(ask.target, float)
    L0 = np.column_stack([c.land_x[idx], c.land_y[idx]])
    J = ra.J[c.row[idx]]
    B = c.heading_deg[idx]
    Jc = np.stack([_rotate(J[:, :, 0], B), _rotate(J[:, :, 1], B)], axis=2)
    om_b = _components(c.spin_rpm[idx], c.spin_axis_deg[idx])
    W, G, miss = _spin.variants(
        L0, Jc, om_b, T, (ask.spin_rpm, ask.spin_axis_deg), ask.tolerances, spec.spin, spec.spin_axis
    )
    n, k = W.shape
    rep = np.repeat(idx, k)
    keys = _select.settings_key(
        spec, c.height_m[rep], c.speed_kmh[rep], c.elevation_deg[rep], c.heading_deg[rep], W.ravel(), G.ravel()
    ).reshape(n, k)
    order = np.argsort(miss, axis=1, kind="stable")[:, : 4 * PER_REFINE]
    ks = keys.tolist() if keys.dtype == np.int64 else [[k.tobytes() for k in r] for r in keys]
    fin = np.isfinite(miss).tolist()
    rows_out, cols_out = [], []
    for j, ranks in enumerate(order.tolist()):  # in order: a key taken by one candidate is not flown again
        got = 0
        for kk in ranks:
            if got >= PER_REFINE or not fin[j][kk]:
                break
            key = ks[j][kk]
            if key in seen:
                continue
            seen.add(key)
            rows_out.append(j)
            cols_out.append(kk)
            got += 1
    if not rows_out:
        return None
    jj, kk = np.array(rows_out), np.array(cols_out)
    i, w, g = idx[jj], W[jj, kk], G[jj, kk]
    return [c.row[i], c.height_m[i], c.speed_kmh[i], c.elevation_deg[i], c.heading_deg[i], w, g]


def ranking(c: Candidates, asked: dict, ref_height: float | None = None) -> np.ndarray:
    """Every candidate in the order of preference of :func:`choose` (a stable sort: restricted to a mask, the
    order of the masked candidates among themselves)."""
    miss = np.round(c.miss_m * 1e5)  # 0.01 mm
    dh = np.zeros(miss.size) if ref_height is None else np.abs(c.height_m - ref_height)
    dv = np.abs(c.speed_kmh - asked["speed_kmh"])
    dw = spin_change_rpm(c.spin_rpm, c.spin_axis_deg, asked["spin_rpm"], asked["spin_axis_deg"])
    return np.lexsort((np.round(dw, 9), np.round(dv, 9), np.round(dh, 9), miss))


def first(order: np.ndarray, mask: np.ndarray) -> int:
    """The first candidate of ``order`` (:func:`ranking`) in ``mask``, -1 if none."""
    hit = order[mask[order]]
    return int(hit[0]) if hit.size else -1


def choose(c: Candidates, asked: dict, mask: np.ndarray, ref_height: float | None = None) -> int:
    """Index of the best candidate among ``mask``: smallest miss; ties (0.01 mm) to the smaller change of
    height (when searched, from ``ref_height``), speed, spin, then angles from the exact solution."""
    return first(ranking(c, asked, ref_height), np.asarray(mask, bool))


def acceptable(c: Candidates, need_net: bool, prefs: Preferences) -> tuple[np.ndarray, np.ndarray]:
    """(flights that land and clear the net when they must, those of them meeting the preferences)."""
    ok = c.landed.copy()
    if need_net:
        with np.errstate(invalid="ignore"):
            ok &= (c.net_status == 1) & (c.clearance_m >= 0)
    return ok, ok & prefs.accepts(c.apex_z_m, c.clearance_m, c.flight_time_s)
