"""The machine's whole reach as a fitted map: where every setting lands, and back (the inverse map).

A launch of the machine is known by its height h, speed v, elevation a, heading b and spin (two
components about the flight, topspin t and sidespin s, Wojcicki, Pucilowski & Kulesza 2010 section
2).  Without wind the physics does not depend on the heading: a launch turned by b lands where the
launch at heading 0 lands, turned by b about the machine.  So the whole reach is two functions of
five settings, the distance rho and the angle phi (to the left of the launch direction) of the
landing seen from the launch point::

    rho(h, v, a, t, s),  phi(h, v, a, t, s)

:class:`ReachMap` holds both as tensor-product Chebyshev interpolants (Trefethen 2013) over the
machine's ranges: ``NODES`` Chebyshev points per setting (in sqrt(h), v, tau, t, s), one compiled batch
flight per node (:func:`tennislab.core.flight.fly_batch`, ~60,000 flights: about a second), the
coefficients by a discrete cosine transform along each axis.  Evaluating it costs no flight.

The elevation enters through tau, the flight time the launch would have in a vacuum (the projectile's
time of flight from a height, Halliday, Resnick & Walker 2014, chapter 4),

    tau(a; h, v) = (v sin a + sqrt(v^2 sin^2 a + 2 g h)) / g,   sin a = (g tau^2 - 2 h) / (2 v tau),

scaled to [-1, 1] over the machine's elevations at that height and speed (both directions in closed
form; tau rises with a).  rho is far from a polynomial in a itself: from a low launch it climbs from
decimetres to metres within a degree or two of a = 0 (below, the ball meets the court after
h / tan|a|; above, gravity brings it down after about sqrt(2 h / g)), a knee that sixteen points over
the elevation range cannot follow (at h = 0.125 m, 131 km/h, 1489 rpm backspin the map in a was off
by 0.9-2 m at every elevation, its guess 0.3 deg).  In tau the knee is the geometry of the fall,
which rho follows nearly linearly (rho ~ v tau cos a), and the nodes gather where rho changes fast.

The inverse map (:meth:`ReachMap.aim`): for a target at distance D and bearing beta from the
machine and given h, v, t, s, the 1-D polynomial rho is evaluated on a fine grid uniform in tau; its
crossings of D on the rising (low) and falling (high) side of its maximum, bracketed there and solved
on the polynomial, give the elevation, and b = beta - phi(a) the heading.  Its error (hundredths of
a degree, more at the edges of the reach: docs/launcher.md) is then removed by one or two Newton steps
on the real kernel (:func:`tennislab.core.shoot.shoot` started there): the map is where a search
starts, never an answer by itself.

A map depends on the physics (aero model and its coefficients, ball, air, spin decay, the flight's
``t_max``) and the machine's ranges, not on its position, the court or the wind (a wind breaks the
symmetry: with wind the map of the still air is the start and the Newton steps do the rest).  It is
built on first use and kept in memory and on disk (:func:`reach_map`): in the user's cache folder,
``$TENNISLAB_CACHE_DIR`` if set (empty: no file at all), else ``$XDG_CACHE_HOME/tennislab`` or
``~/.cache/tennislab``, as ``reach-<key>.npz`` (about 1 MB).  A file that cannot be read or does not
match its key is built again; a folder that cannot be written is no error (the map stays in memory).

References
----------
Halliday, D., Resnick, R. & Walker, J. (2014), Fundamentals of Physics, 10th ed., Wiley, chapter 4
(projectile motion: the time of flight from a height).
Trefethen, L. N. (2013), Approximation Theory and Approximation Practice, SIAM, chapters 2-3
(Chebyshev points and interpolants).
Wojcicki, Pucilowski & Kulesza (2010), Mathematical analysis for a new tennis ball launcher,
Acta Mech. Autom. 4(4) (seed 002: the settings and their ranges).
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import hashlib
import json
import math
import os
import tempfile
import time
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numba as nb
import numpy as np

from tennislab.core import aero as _aero
from tennislab.core._jit import JIT
from tennislab.core.flight import FlightParams, fly_batch
from tennislab.core.launch import launch_states
from tennislab.launcher.machine import MachineSpec
from tennislab.units import DEG, KMH, RPM

#: Version of the map's layout and fit (part of its key: a new version is built anew); 2: the elevation in
#: the vacuum flight time (module docstring)
FORMAT = 2
#: Chebyshev points per setting: height (in sqrt h), speed, elevation (in tau), topspin, sidespin
NODES = (6, 10, 16, 8, 8)
AXES = ("height_m", "speed_kmh", "elevation_deg", "topspin_rpm", "sidespin_rpm")
#: Points (uniform in tau) on which the 1-D curves rho(a) are evaluated to bracket crossings, each then
#: solved on the fitted curve itself (:data:`CROSSING_ITER` steps of regula falsi, Illinois variant)
CURVE_POINTS = 201
CROSSING_ITER = 6


def _cheb_points(n: int) -> np.ndarray:
    """Chebyshev points of the first kind in [-1, 1], ascending (n = 1: the middle)."""
    return -np.cos(np.pi * (np.arange(n) + 0.5) / n)


def _vander(u, n: int) -> np.ndarray:
    """Chebyshev polynomials T_0 .. T_{n-1} at u (..., n): T_k(u) = cos(k arccos u), u clipped to [-1, 1]."""
    theta = np.arccos(np.clip(np.asarray(u, dtype=float), -1.0, 1.0))
    return np.cos(theta[..., None] * np.arange(n))


@nb.njit(**JIT)
def _vacuum_time(a_deg, h, v, g):
    """tau [s]: the flight time of a launch at elevation ``a_deg`` [deg] from height ``h`` [m] at speed ``v``
    [m/s] under gravity ``g`` [m/s^2] without air (module docstring); scalars or arrays.  Without gravity
    (``g`` <= 0: nothing brings a vacuum's ball down) the elevation itself [deg] stands for it."""
    if g <= 0.0:
        return a_deg + 0.0 * (h * v)  # broadcast as the other branch
    vs = v * np.sin(np.radians(a_deg))
    return (vs + np.sqrt(vs * vs + 2.0 * g * h)) / g


@nb.njit(**JIT)
def _vacuum_elevation(tau, h, v, g):
    """The elevation [deg] whose vacuum flight time is ``tau`` [s] (the inverse of :func:`_vacuum_time`)."""
    if g <= 0.0:
        return tau + 0.0 * (h * v)
    return np.degrees(np.arcsin(np.minimum(np.maximum((g * tau * tau - 2.0 * h) / (2.0 * v * tau), -1.0), 1.0)))


@nb.njit(**JIT)
def _vacuum_time_slope(a_deg, h, v, g):
    """d tau / d a [s/deg] of :func:`_vacuum_time` (1 without gravity: the elevation stands for tau)."""
    if g <= 0.0:
        return 1.0
    vs = v * math.sin(math.radians(a_deg))
    return v * math.cos(math.radians(a_deg)) * (1.0 + vs / math.sqrt(vs * vs + 2.0 * g * h)) / g * (math.pi / 180.0)


@nb.njit(**JIT)
def _elevation_at(u, tau0, tau1, h, v, g):
    """The elevation [deg] at ``u`` in [-1, 1] of the elevation's variable, tau from ``tau0`` to ``tau1``."""
    return _vacuum_elevation(0.5 * (u * (tau1 - tau0) + tau0 + tau1), h, v, g)


@nb.njit(**JIT)
def _tau_span(a_lo, a_hi, h, v, g):
    """(tau at ``a_lo``, tau at ``a_hi``): the ends of the elevation's Chebyshev variable at (h [m], v [m/s])."""
    return _vacuum_time(a_lo, h, v, g), _vacuum_time(a_hi, h, v, g)


@dataclass(frozen=True)
class ReachMap:
    """The fitted reach (module docstring): domain ``lo``/``hi`` (5,) in the fitted variables (sqrt of
    the height [m^0.5], speed [km/h], elevation [deg], topspin and sidespin [rpm]), coefficient
    tensors ``rho`` [m] and ``phi`` [rad] of shape :data:`NODES` (the elevation's axis in the vacuum
    flight time, module docstring), ``gravity`` [m/s^2] of that time, the ``key`` of the physics and
    ranges it was built for, and ``build_s`` the time its fit took [s] (NaN when unknown)."""

    lo: np.ndarray
    hi: np.ndarray
    rho: np.ndarray
    phi: np.ndarray
    gravity: float
    key: str
    build_s: float = math.nan

    @functools.cached_property
    def spin_major(self) -> tuple[np.ndarray, np.ndarray]:
        """``rho`` and ``phi`` as (n_t n_s, n_h n_v n_a) arrays, the spin's axes first (:func:`_aim_rows` contracts
        the spin along contiguous memory); made once per map."""
        nh, nv, na, nt, ns = self.rho.shape
        rho_s, phi_s = (np.ascontiguousarray(c.reshape(nh * nv * na, nt * ns).T) for c in (self.rho, self.phi))
        return rho_s, phi_s

    def _u(self, axis: int, x) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        if axis == 0:
            x = np.sqrt(np.maximum(x, 0.0))
        lo, hi = self.lo[axis], self.hi[axis]
        return np.zeros_like(x) if hi <= lo else (2.0 * x - (lo + hi)) / (hi - lo)

    def _reduce(self, h, v, t: float, s: float) -> tuple[np.ndarray, np.ndarray]:
        """Chebyshev coefficients in the elevation (Q, n_a) of rho and phi for Q (h, v) rows of one spin."""
        h, v = (np.asarray(x, dtype=float).reshape(-1) for x in np.broadcast_arrays(h, v))
        nh, nv, na, nt, ns = self.rho.shape
        spin = np.outer(_vander(self._u(3, float(t)), nt), _vander(self._u(4, float(s)), ns)).reshape(-1)
        th, tv = _vander(self._u(0, h), nh), _vander(self._u(1, v), nv)
        out = []
        for c in (self.rho, self.phi):
            spun = (c.reshape(-1, nt * ns) @ spin).reshape(nh, nv * na)  # the spin contracted once for every row
            per_h = (th @ spun).reshape(-1, nv, na)  # (Q, n_v, n_a)
            out.append(np.einsum("qj,qja->qa", tv, per_h))
        return out[0], out[1]

    def _u_elevation(self, a, h, v) -> np.ndarray:
        """The elevation's Chebyshev variable in [-1, 1] of elevations ``a`` [deg] at (h [m], v [km/h])."""
        if self.hi[2] <= self.lo[2]:
            return np.zeros_like(np.asarray(a, dtype=float))
        vm = v * KMH
        t0, t1 = _tau_span(self.lo[2], self.hi[2], h, vm, self.gravity)
        return (2.0 * _vacuum_time(a, h, vm, self.gravity) - (t0 + t1)) / (t1 - t0)

    def landing(self, h, v, a, t: float, s: float) -> tuple[np.ndarray, np.ndarray]:
        """(rho [m], phi [rad]) of launches of one spin (t, s) [rpm] (h [m], v [km/h], a [deg] broadcast)."""
        h, v, a = (np.asarray(x, dtype=float).reshape(-1) for x in np.broadcast_arrays(h, v, a))
        cr, cp = self._reduce(h, v, t, s)
        ta = _vander(self._u_elevation(a, h, v), cr.shape[1])
        return (cr * ta).sum(axis=1), (cp * ta).sum(axis=1)

    def aim(self, distance, h, v, t: float, s: float, branch: str, elevation=None) -> dict:
        """The inverse map: elevation [deg] landing at ``distance`` [m] on ``branch``, for Q rows of
        (distance, h [m], v [km/h]) and one spin (t, s) [rpm].

        Returns a dict of (Q,) arrays: ``elevation_deg`` (NaN where the map finds none),
        ``phi`` [rad] the landing's angle at it, ``split_deg`` the elevation of the longest flight,
        ``reach`` (Q, 2) the shortest and longest distance [m] over ``elevation`` (default: the
        map's range) on the grid of :data:`CURVE_POINTS`, ``slope`` [m/deg] d rho / d a at the solution
        (of the fitted curve).  The crossing is solved on the fitted curve.  One
        compiled pass (:func:`_aim_rows`): tens of microseconds a row.
        """
        return self.aim_both(distance, h, v, t, s, elevation)[0 if branch == "low" else 1]

    def aim_both(self, distance, h, v, t: float, s: float, elevation=None) -> tuple[dict, dict]:
        """:meth:`aim` of both branches in one pass: (low, high)."""
        d, h, v = (np.array(x, dtype=float).reshape(-1) for x in np.broadcast_arrays(distance, h, v))
        g0, g1 = (self.lo[2], self.hi[2]) if elevation is None else (float(elevation[0]), float(elevation[1]))
        out = np.empty((2, d.size, 6))
        rho_s, phi_s = self.spin_major
        _aim_rows(
            rho_s, phi_s, self.rho.shape, self.lo, self.hi, self.gravity, d, h, v, float(t), float(s), g0, g1,
            CURVE_POINTS, CROSSING_ITER, out,
        )  # fmt: skip
        return tuple(  # type: ignore[return-value]
            {
                "elevation_deg": o[:, 0],
                "phi": o[:, 1],
                "split_deg": o[:, 2],
                "reach": o[:, 3:5],
                "slope": o[:, 5],
            }
            for o in out
        )


@nb.njit(**JIT)
def _cheb_into(u: float, out: np.ndarray) -> None:
    """T_0 .. T_{n-1} at u (clipped to [-1, 1]) into ``out`` (the recurrence: the same values as :func:`_vander`)."""
    u = min(max(u, -1.0), 1.0)
    out[0] = 1.0
    if out.size > 1:
        out[1] = u
    for k in range(2, out.size):
        out[k] = 2.0 * u * out[k - 1] - out[k - 2]


@nb.njit(**JIT)
def _scaled(x: float, lo: float, hi: float) -> float:
    return 0.0 if hi <= lo else (2.0 * x - (lo + hi)) / (hi - lo)


@nb.njit(**JIT)
def _cheb_sum(c: np.ndarray, u: float, work: np.ndarray) -> float:
    """sum_k c[k] T_k(u)."""
    _cheb_into(u, work)
    acc = 0.0
    for k in range(c.size):
        acc += c[k] * work[k]
    return acc


@nb.njit(**JIT)
def _cheb_slope(c: np.ndarray, u: float) -> float:
    """d/du sum_k c[k] T_k(u) = sum_k c[k] k U_{k-1}(u) (U the Chebyshev polynomials of the second kind)."""
    u = min(max(u, -1.0), 1.0)
    acc = 0.0
    um2, um1 = 0.0, 1.0  # U_{-1}, U_0
    for k in range(1, c.size):
        acc += c[k] * k * um1
        um2, um1 = um1, 2.0 * u * um1 - um2
    return acc


@nb.njit(**JIT)
def _crossing(c: np.ndarray, d: float, ua: float, ub: float, fa: float, fb: float, iters: int, work) -> float:
    """The u in [ua, ub] where the curve sum_k c[k] T_k(u) meets ``d`` (fa, fb: curve - d at the ends, of
    opposite signs): regula falsi, Illinois variant (a retained end's value halved)."""
    u = ua - fa * (ub - ua) / (fb - fa) if fb != fa else 0.5 * (ua + ub)
    side = 0
    for _ in range(iters):
        f = _cheb_sum(c, u, work) - d
        if f == 0.0:
            return u
        if (f < 0.0) == (fa < 0.0):
            ua, fa = u, f
            if side == -1:
                fb *= 0.5
            side = -1
        else:
            ub, fb = u, f
            if side == 1:
                fa *= 0.5
            side = 1
        u = ua - fa * (ub - ua) / (fb - fa) if fb != fa else 0.5 * (ua + ub)
    return u


@nb.njit(**JIT)
def _aim_rows(rho_s, phi_s, shape, lo, hi, grav, d, h, v, t, s, g0, g1, npts, iters, out):
    """:meth:`ReachMap.aim_both` for Q rows: per row the coefficients in the elevation (spin, height and speed
    contracted), the curve rho on ``npts`` points uniform in the elevation's variable (the vacuum flight time,
    module docstring) between elevations g0 and g1 [deg], on each branch's side of the longest flight the
    crossing of the row's distance (bracketed on the grid, then solved on the fitted curve), phi there and the
    slope.  ``rho_s``, ``phi_s``: the coefficients spin-major (:attr:`ReachMap.spin_major`), ``shape`` their
    :data:`NODES`.  ``out`` (2, Q, 6), low then high: elevation [deg], phi [rad], split [deg], shortest and longest
    distance [m], slope [m/deg]."""
    nh, nv, na, nt, ns = shape
    tt, ts = np.empty(nt), np.empty(ns)
    _cheb_into(_scaled(t, lo[3], hi[3]), tt)
    _cheb_into(_scaled(s, lo[4], hi[4]), ts)
    # the spin contracted once for every row: (nh, nv, na).  Every sum below runs over its terms in the order of
    # the plain loop (from 0.0, index by index), but with the output index innermost, so that the loops take SIMD
    # bodies (a reduction does not without reassociation, which FASTMATH leaves out) and give the same bits.
    nr = nh * nv * na
    sr, sp = np.zeros(nr), np.zeros(nr)
    for m in range(nt):
        for n in range(ns):
            w = tt[m] * ts[n]
            c = m * ns + n
            for r in range(nr):
                sr[r] += rho_s[c, r] * w
            for r in range(nr):
                sp[r] += phi_s[c, r] * w
    th, tv, work = np.empty(nh), np.empty(nv), np.empty(na)
    cr, cp = np.empty(na), np.empty(na)
    full = g0 == lo[2] and g1 == hi[2]  # the grid in u is then the same for every row
    ugrid = np.empty(npts)
    tgrid = np.empty((na, npts))  # T_k at the grid's points, k major
    if full:
        for g in range(npts):
            ugrid[g] = -1.0 + 2.0 * g / (npts - 1)
            _cheb_into(ugrid[g], work)
            tgrid[:, g] = work
    curve = np.empty(npts)
    for q in range(d.size):
        _cheb_into(_scaled(math.sqrt(max(h[q], 0.0)), lo[0], hi[0]), th)
        _cheb_into(_scaled(v[q], lo[1], hi[1]), tv)
        vm = v[q] * KMH
        tau0, tau1 = _tau_span(lo[2], hi[2], h[q], vm, grav)
        if not full:
            u0 = _scaled(_vacuum_time(g0, h[q], vm, grav), tau0, tau1)
            u1 = _scaled(_vacuum_time(g1, h[q], vm, grav), tau0, tau1)
            for g in range(npts):
                ugrid[g] = u0 + (u1 - u0) * g / (npts - 1)
                _cheb_into(ugrid[g], work)
                tgrid[:, g] = work
        cr[:] = 0.0
        cp[:] = 0.0
        for i in range(nh):
            for j in range(nv):
                w = th[i] * tv[j]
                o = (i * nv + j) * na
                for k in range(na):
                    cr[k] += w * sr[o + k]
                for k in range(na):
                    cp[k] += w * sp[o + k]
        curve[:] = 0.0
        for k in range(na):
            for g in range(npts):
                curve[g] += cr[k] * tgrid[k, g]
        k_max = 0
        for g in range(npts):
            if curve[g] > curve[k_max]:
                k_max = g
        for side in range(2):  # 0: low, the first crossing rising; 1: high, the last one falling
            found = -1
            if side == 0:
                for g in range(min(max(k_max, 1), npts - 1)):
                    if curve[g] - d[q] < 0.0 and curve[g + 1] - d[q] >= 0.0:
                        found = g
                        break
            else:
                for g in range(npts - 2, k_max - 1, -1):
                    if curve[g] - d[q] >= 0.0 and curve[g + 1] - d[q] < 0.0:
                        found = g
                        break
            o = out[side, q]
            o[2] = _elevation_at(ugrid[k_max], tau0, tau1, h[q], vm, grav)
            o[3] = curve.min()
            o[4] = curve.max()
            if found < 0:
                o[0] = np.nan
                o[1] = np.nan
                o[5] = np.nan
                continue
            f0, f1 = curve[found] - d[q], curve[found + 1] - d[q]
            u = _crossing(cr, d[q], ugrid[found], ugrid[found + 1], f0, f1, iters, work)
            o[0] = _elevation_at(u, tau0, tau1, h[q], vm, grav)
            o[1] = _cheb_sum(cp, u, work)
            # d rho / d a at the crossing: the fitted curve's slope in u times du / d a
            o[5] = _cheb_slope(cr, u) * 2.0 / (tau1 - tau0) * _vacuum_time_slope(o[0], h[q], vm, grav)


def still_air(params: FlightParams) -> FlightParams:
    """The physics a map is built with: ``params`` without wind and with the net as no obstacle."""
    atm = dataclasses.replace(params.atmosphere, wind=(0.0, 0.0, 0.0))
    return dataclasses.replace(params, atmosphere=atm, net_obstacle=False)


def domain(spec: MachineSpec, params: FlightParams) -> tuple[np.ndarray, np.ndarray]:
    """The fitted box (lo, hi) for a machine's ranges (module docstring)."""
    h_lo = max(spec.height.lo, params.ball.radius * 1.5)
    w = spec.spin.hi
    lo = np.array([math.sqrt(h_lo), spec.speed.lo, spec.elevation.lo, -w, -w])
    hi = np.array([math.sqrt(max(spec.height.hi, h_lo)), spec.speed.hi, spec.elevation.hi, w, w])
    return lo, hi


def map_key(spec: MachineSpec, params: FlightParams) -> str:
    """A hash of everything a map depends on (module docstring): format, physics sources, physics, ranges."""
    lo, hi = domain(spec, params)
    a = params.aero
    doc = {
        "format": FORMAT,
        "core": _aero._DIGEST,
        "nodes": list(NODES),
        "aero": [a.name, [float(x) for x in np.asarray(a.params, dtype=float).ravel()], a.batch_tol],
        "kernel": getattr(getattr(a.kernel, "py_func", a.kernel), "__qualname__", repr(a.kernel)),
        "ball": [params.ball.mass, params.ball.radius],
        "air": [params.atmosphere.density, params.atmosphere.gravity],
        "spin_decay": params.spin_decay,
        "t_max": params.t_max,
        "domain": [list(map(float, lo)), list(map(float, hi))],
    }
    return hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()[:20]


def build(spec: MachineSpec, params: FlightParams) -> ReachMap:
    """Fit the map for a machine and physics: one batch flight per Chebyshev node (module docstring)."""
    t0 = time.perf_counter()
    lo, hi = domain(spec, params)
    pts = []
    for axis, (n, a, b) in enumerate(zip(NODES, lo, hi)):
        u = _cheb_points(n) if b > a else np.zeros(1)
        pts.append(u if axis == 2 else 0.5 * (u * (b - a) + a + b))  # the elevation's nodes stay in u (of tau)
    shape = tuple(len(p) for p in pts)
    g = [x.reshape(-1) for x in np.meshgrid(*pts, indexing="ij")]
    h = g[0] ** 2
    grav = float(params.atmosphere.gravity)
    tau0, tau1 = _tau_span(lo[2], hi[2], h, g[1] * KMH, grav)  # each (h, v)'s elevation nodes (module docstring)
    a = _elevation_at(g[2], tau0, tau1, h, g[1] * KMH, grav)
    st = launch_states(
        np.column_stack([np.zeros_like(h), np.zeros_like(h), h]),
        g[1] * KMH,
        a * DEG,
        0.0,
        g[3] * RPM,
        g[4] * RPM,
    )
    tab = fly_batch(st, still_air(params))
    x, y = tab["land_x"], tab["land_y"]
    rho = np.where(tab.ok, np.hypot(x, y), np.nan).reshape(shape)
    phi = np.where(tab.ok, np.arctan2(y, x), np.nan).reshape(shape)
    coef = [np.ascontiguousarray(_coefficients(_fill(f), shape)) for f in (rho, phi)]
    return ReachMap(lo, hi, coef[0], coef[1], grav, map_key(spec, params), time.perf_counter() - t0)


def _fill(f: np.ndarray) -> np.ndarray:
    """Nodes without a landing (a flight longer than ``t_max``) take the nearest value along the elevation."""
    if np.isfinite(f).all():
        return f
    g = np.moveaxis(f.copy(), 2, -1)
    flat = g.reshape(-1, g.shape[-1])
    idx = np.arange(flat.shape[1])
    for row in flat:
        ok = np.isfinite(row)
        row[:] = np.interp(idx, idx[ok], row[ok]) if ok.any() else 0.0
    return np.moveaxis(flat.reshape(g.shape), -1, 2)


def _coefficients(f: np.ndarray, shape: tuple) -> np.ndarray:
    """Chebyshev coefficients of the interpolant through values at the points of :func:`_cheb_points`."""
    c = f
    for axis, n in enumerate(shape):
        inv = np.linalg.inv(_vander(_cheb_points(n), n)) if n > 1 else np.ones((1, 1))
        c = np.moveaxis(np.tensordot(inv, np.moveaxis(c, axis, 0), axes=(1, 0)), 0, axis)
    return c


#: Environment variable naming the folder of the maps' files (empty: keep them in memory only)
CACHE_ENV = "TENNISLAB_CACHE_DIR"
_MEMORY: dict[str, ReachMap] = {}
_MEMORY_MAX = 8


def cache_dir() -> Path | None:
    """The folder of the maps' files (module docstring), or None when the disk cache is off."""
    env = os.environ.get(CACHE_ENV)
    if env is not None:
        return Path(env).expanduser() if env.strip() else None
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "tennislab"


@dataclass(frozen=True)
class MapUse:
    """A map as one call got it: ``source`` ``built`` (fitted now), ``file`` (read from the cache folder) or
    ``memory`` (kept from an earlier call of this process), and the time the call took [s]."""

    map: ReachMap
    source: str
    seconds: float

    def to_dict(self) -> dict:
        """``source``, ``seconds`` (this call), ``build_s`` (what the map's fit cost when it was built), ``key``."""
        b = self.map.build_s
        return {
            "source": self.source,
            "seconds": self.seconds,
            "build_s": None if math.isnan(b) else b,
            "key": self.map.key,
        }


#: (id(spec), id(params)) -> (spec, params, key): the keys of the machines asked lately (the objects are kept, so
#: their ids stay theirs)
_KEYS: dict = {}


def _key_of(spec: MachineSpec, params: FlightParams) -> str:
    got = _KEYS.get((id(spec), id(params)))
    if got is not None and got[0] is spec and got[1] is params:
        return got[2]
    key = map_key(spec, params)
    if len(_KEYS) >= 4 * _MEMORY_MAX:
        _KEYS.pop(next(iter(_KEYS)))
    _KEYS[(id(spec), id(params))] = (spec, params, key)
    return key


def get_map(spec: MachineSpec, params: FlightParams) -> MapUse:
    """The map of a machine and physics and how it was got (:class:`MapUse`): from memory, from the cache
    folder, or built (and stored there)."""
    t0 = time.perf_counter()
    key = _key_of(spec, params)
    got = _MEMORY.get(key)
    if got is not None:
        return MapUse(got, "memory", time.perf_counter() - t0)
    folder = cache_dir()
    path = None if folder is None else folder / f"reach-{key}.npz"
    got = _load(path, key) if path is not None else None
    source = "file"
    if got is None:
        got, source = build(spec, params), "built"
        if path is not None:
            _save(path, got)
    if len(_MEMORY) >= _MEMORY_MAX:
        _MEMORY.pop(next(iter(_MEMORY)))
    _MEMORY[key] = got
    return MapUse(got, source, time.perf_counter() - t0)


def reach_map(spec: MachineSpec, params: FlightParams) -> ReachMap:
    """The map of a machine and physics: from memory, from the cache folder, or built (and stored there)."""
    return get_map(spec, params).map


def _load(path: Path, key: str) -> ReachMap | None:
    """The map stored at ``path`` if it is a whole map of ``key``; None for anything else (a missing,
    truncated, foreign or damaged file is rebuilt, never an error)."""
    try:
        with np.load(path, allow_pickle=False) as z:
            build_s = float(z["build_s"]) if "build_s" in z.files else math.nan
            m = ReachMap(z["lo"], z["hi"], z["rho"], z["phi"], float(z["gravity"]), str(z["key"]), build_s)
        good = m.key == key and m.rho.shape == m.phi.shape == NODES and m.lo.shape == m.hi.shape == (5,)
        good = good and all(x.dtype == np.float64 and np.isfinite(x).all() for x in (m.lo, m.hi, m.rho, m.phi))
        good = good and math.isfinite(m.gravity) and m.gravity >= 0.0
    except (OSError, ValueError, KeyError, EOFError, TypeError, zipfile.BadZipFile):
        return None
    return m if good else None


def _save(path: Path, m: ReachMap) -> None:
    """Write atomically (a temporary file in the folder, then renamed); any failure leaves no file."""
    tmp = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=".reach-", suffix=".npz", dir=path.parent)
        with os.fdopen(fd, "wb") as f:
            np.savez(
                f, lo=m.lo, hi=m.hi, rho=m.rho, phi=m.phi, gravity=m.gravity, key=np.array(m.key), build_s=m.build_s
            )
        os.replace(tmp, path)
        tmp = None
    except OSError:
        pass
    finally:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)


__all__ = [
    "CACHE_ENV",
    "FORMAT",
    "NODES",
    "ReachMap",
    "build",
    "MapUse",
    "cache_dir",
    "domain",
    "get_map",
    "map_key",
    "reach_map",
    "still_air",
]
