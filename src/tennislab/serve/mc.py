"""Monte Carlo margin of error of a serve (the seed's "future work", sec. 4).

A nominal serve (player, alpha, beta) is repeated n times with normal scatter
of the impact angle alpha, the face angle beta and the face azimuth psi (sd
``sd_angle``), the racket speed (``sd_speed``) and the impact height
(``sd_height``).  Output: the probability of success (the seed's 2-D criteria,
or a real service box with ``target``), the mean and covariance of the landing
points (court frame, x along, y across [m]) and the 95 % landing ellipse.

Draws come from ``numpy.random.default_rng(seed)`` in a fixed order (alpha,
beta, psi, speed, height), so a run is reproducible for a given seed and n,
whatever the scheduler and chunking.  Impacts are interpolated (bilinear)
from a table on a (V, alpha) grid spanning the drawn values (:func:`impact_table`; 41 x 81
points, interpolation error checked in tests/test_serve_mc.py); flights use
the compiled batch integrator.  :func:`simulate_chunk` is the per-chunk worker
(module level, for ``tennislab.batch.map_chunks``).
"""
from __future__ import annotations

import functools
import math

import numba as nb
import numpy as np

from tennislab.core.flight import FlightParams, fly_batch
from tennislab.core.impact import ImpactParams, impact_batch
from tennislab.errors import check_range
from tennislab.serve.players import get_player
from tennislab.serve.setup import SeedCriteria, seed_flight_params, seed_impact_params
from tennislab.serve.single import judge
from tennislab.serve.window import flight_options

CHI2_95_2DOF = 5.991464547107979  #: chi-square 95 % quantile, 2 degrees of freedom


class _Table:
    def __init__(self, V, A, vals):
        self.V, self.A, self.vals = V, A, vals

    def __call__(self, v, a):
        """Bilinear interpolation of each table at points (v, a)."""
        out = {}
        iv, fv = _locate(self.V, v)
        ia, fa = _locate(self.A, a)
        for k, T in self.vals.items():
            t00 = T[iv, ia]
            t10 = T[np.minimum(iv + 1, T.shape[0] - 1), ia]
            t01 = T[iv, np.minimum(ia + 1, T.shape[1] - 1)]
            t11 = T[np.minimum(iv + 1, T.shape[0] - 1), np.minimum(ia + 1, T.shape[1] - 1)]
            out[k] = (1 - fv) * ((1 - fa) * t00 + fa * t01) + fv * ((1 - fa) * t10 + fa * t11)
        return out


def _locate(grid, x):
    if grid.size == 1:
        return np.zeros(np.shape(x), int), np.zeros(np.shape(x))
    x = np.clip(x, grid[0], grid[-1])
    i = np.clip(np.searchsorted(grid, x, side="right") - 1, 0, grid.size - 2)
    f = (x - grid[i]) / (grid[i + 1] - grid[i])
    return i, f


@nb.njit(cache=True, inline="always")
def _loc(grid, x):
    n = grid.shape[0]
    if n == 1:
        return 0, 0.0
    if x <= grid[0]:
        return 0, 0.0
    if x >= grid[n - 1]:
        return n - 2, 1.0
    d = (grid[n - 1] - grid[0]) / (n - 1)  # uniform grid
    i = min(int((x - grid[0]) / d), n - 2)
    return i, (x - grid[i]) / (grid[i + 1] - grid[i])


@nb.njit(cache=True, parallel=True)
def _launch_kernel(a, b, psi, V, h, Vg, Ag, T, server_x, server_y, out):
    """Bilinear impact lookup + launch (same algebra as :func:`launch_3d`, brush 0), row by row."""
    nV, nA = Vg.shape[0], Ag.shape[0]
    for k in nb.prange(a.shape[0]):
        iv, fv = _loc(Vg, V[k])
        ia, fa = _loc(Ag, a[k])
        iv1 = min(iv + 1, nV - 1)
        ia1 = min(ia + 1, nA - 1)
        w00, w01, w10, w11 = (1 - fv) * (1 - fa), (1 - fv) * fa, fv * (1 - fa), fv * fa
        r0 = w00 * T[0, iv, ia] + w01 * T[0, iv, ia1] + w10 * T[0, iv1, ia] + w11 * T[0, iv1, ia1]
        r1 = w00 * T[1, iv, ia] + w01 * T[1, iv, ia1] + w10 * T[1, iv1, ia] + w11 * T[1, iv1, ia1]
        r2 = w00 * T[2, iv, ia] + w01 * T[2, iv, ia1] + w10 * T[2, iv1, ia] + w11 * T[2, iv1, ia1]
        cb, sb, cp, sp = math.cos(b[k]), math.sin(b[k]), math.cos(psi[k]), math.sin(psi[k])
        # n = (cb cp, cb sp, -sb), t = t_up = (sb cp, sb sp, cb), t x n = (-sp, cp, 0)
        out[k, 0] = server_x
        out[k, 1] = server_y
        out[k, 2] = h[k]
        out[k, 3] = r0 * cb * cp + r1 * sb * cp
        out[k, 4] = r0 * cb * sp + r1 * sb * sp
        out[k, 5] = -r0 * sb + r1 * cb
        out[k, 6] = -r2 * sp
        out[k, 7] = r2 * cp
        out[k, 8] = 0.0


def impact_table(v_range, a_range, params: ImpactParams, nv: int = 41, na: int = 81, **impact_kw) -> _Table:
    """Impact results (v_n, v_t, omega) on a grid of racket speed [m/s] x impact angle [rad]."""
    V = np.linspace(*v_range, nv) if v_range[1] > v_range[0] else np.array([float(v_range[0])])
    A = np.linspace(*a_range, na) if a_range[1] > a_range[0] else np.array([float(a_range[0])])
    impact_kw = {"steps": 200, **impact_kw}
    VV, AA = np.meshgrid(V, A, indexing="ij")
    r = impact_batch(VV, AA, params, **impact_kw)
    return _Table(V, A, {k: r[k] for k in ("v_n", "v_t", "omega")})


def simulate_chunk(inputs: dict, *, flight: dict | None = None, target: str | None = None,
                   net_top: float = 0.943, service_line: float = 18.318, server_x: float = -11.885,
                   rtol: float = 1e-6) -> dict:
    """Per-chunk worker: fly launched serves and judge them.

    inputs: ``x, y, z`` [m], ``vx, vy, vz`` [m/s], ``wx, wy, wz`` [rad/s] (equal-length arrays).
    ``rtol``: flight tolerance (rtol = atol; 1e-6 keeps landing points within ~1e-3 mm of the
    reference, far below any scatter studied).  Returns ``land_x``, ``land_y`` (court frame [m]), ``landing_x`` (from the impact point),
    ``net_height`` [m], ``success`` (bool), ``landed`` (bool).
    """
    params = FlightParams.from_options(**(flight or {}))
    keys = ("x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz")
    states = np.empty((len(inputs["x"]), 9))
    for i, k in enumerate(keys):
        states[:, i] = inputs[k]
    table = fly_batch(states, params, rtol=rtol, atol=rtol)
    crit = SeedCriteria(net_top=net_top, service_line=service_line, server_x=server_x)
    j = judge(table, crit, target)
    return {"land_x": table["land_x"], "land_y": table["land_y"], "landing_x": j["landing_x"],
            "net_height": j["net_height"], "success": j["success"], "landed": table.ok}


def draw_serves(player, alpha_deg, beta_deg, *, n: int, seed: int, sd_angle: float, sd_speed: float,
                sd_height: float, sd_azimuth: float | None, azimuth_deg: float = 0.0,
                impact_params: ImpactParams, server_x: float, server_y: float, impact_kw=None) -> dict:
    """The launched states of n scattered serves (inputs of :func:`simulate_chunk`)."""
    rng = np.random.default_rng(seed)
    sd_az = sd_angle if sd_azimuth is None else sd_azimuth
    a = np.radians(alpha_deg + sd_angle * rng.standard_normal(n))
    b = np.radians(beta_deg + sd_angle * rng.standard_normal(n))
    psi = np.radians(azimuth_deg + sd_az * rng.standard_normal(n))
    V = player.racket_speed + sd_speed * rng.standard_normal(n)
    h = player.impact_height + sd_height * rng.standard_normal(n)
    V = np.clip(V, 1.0, None)
    a = np.clip(a, -math.radians(89.0), math.radians(89.0))
    tab = impact_table((V.min(), V.max()), (a.min(), a.max()), impact_params, **(impact_kw or {}))
    T = np.ascontiguousarray(np.stack([tab.vals[k] for k in ("v_n", "v_t", "omega")]))
    S = np.empty((n, 9))
    _launch_kernel(a, b, psi, V, h, tab.V, tab.A, T, float(server_x), float(server_y), S)
    return {k: S[:, i] for i, k in enumerate(("x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz"))}


def landing_stats(x, y) -> dict:
    """Mean, covariance and 95 % ellipse (semi-axes [m], angle of the major axis to x [deg])."""
    if x.size < 2:
        return {"mean": [float(np.mean(x)) if x.size else None, float(np.mean(y)) if y.size else None],
                "cov": None, "ellipse_95": None}
    P = np.stack([x, y])
    cov = np.cov(P)
    w, v = np.linalg.eigh(cov)
    w = np.clip(w, 0.0, None)
    major = v[:, 1]
    ang = math.degrees(math.atan2(major[1], major[0]))
    ang = ang - 180.0 if ang > 90.0 else (ang + 180.0 if ang <= -90.0 else ang)  # axis: (-90, 90]
    return {"mean": [float(x.mean()), float(y.mean())], "cov": cov.tolist(),
            "ellipse_95": {"semi_axes": [float(math.sqrt(CHI2_95_2DOF * w[1])), float(math.sqrt(CHI2_95_2DOF * w[0]))],
                           "angle_deg": ang}}


def run_mc(player, alpha_deg: float, beta_deg: float, *, n: int = 10000, seed: int = 0, sd_angle: float = 1.0,
           sd_speed: float = 1.0, sd_height: float = 0.0, sd_azimuth: float | None = None,
           target: str | None = None, azimuth_deg: float = 0.0, server_y: float = 0.0,
           flight: FlightParams | None = None, impact_params: ImpactParams | None = None,
           criteria: SeedCriteria | None = None, mapper=None, return_samples: bool = False, dt: float = 0.0,
           method: str = "rk4") -> dict:
    """Monte Carlo of a nominal serve; returns the ``tennislab serve-mc`` JSON object.

    Angles and their sd in degrees, speeds [m/s], heights [m].  ``sd_azimuth``
    defaults to ``sd_angle``.  ``mapper(fn, inputs)`` runs :func:`simulate_chunk`
    (default in process; e.g. ``functools.partial(map_chunks, scheduler="processes")``).
    """
    player = get_player(player)
    n = int(check_range("n", n, 1, 1e8))
    for nm, v in (("sd_angle", sd_angle), ("sd_speed", sd_speed), ("sd_height", sd_height)):
        check_range(nm, v, 0.0, 45.0)
    flight = flight or seed_flight_params()
    impact_params = impact_params or seed_impact_params(ball=flight.ball)
    crit = criteria or SeedCriteria()
    inputs = draw_serves(player, alpha_deg, beta_deg, n=n, seed=seed, sd_angle=sd_angle, sd_speed=sd_speed,
                         sd_height=sd_height, sd_azimuth=sd_azimuth, azimuth_deg=azimuth_deg,
                         impact_params=impact_params, server_x=crit.server_x, server_y=server_y,
                         impact_kw={"dt": dt, "method": method})
    fn = functools.partial(simulate_chunk, flight=flight_options(flight), target=target, net_top=crit.net_top,
                           service_line=crit.service_line, server_x=crit.server_x)
    out = fn(inputs) if mapper is None else mapper(fn, inputs)
    success = np.asarray(out["success"], bool)
    landed = np.asarray(out["landed"], bool)
    lx, ly = np.asarray(out["land_x"])[landed], np.asarray(out["land_y"])[landed]
    p = float(success.mean())
    res = {"player": player.name, "nominal": {"alpha": alpha_deg, "beta": beta_deg, "azimuth": azimuth_deg},
           "scatter": {"sd_angle": sd_angle, "sd_speed": sd_speed, "sd_height": sd_height,
                       "sd_azimuth": sd_angle if sd_azimuth is None else sd_azimuth},
           "n": n, "seed": seed, "criteria": "seed-2d" if target is None else f"{target}-box",
           "p_success": p, "p_success_se": math.sqrt(max(p * (1 - p), 0.0) / n),
           "landing": landing_stats(lx, ly),
           "landing_x": {"mean": float(np.mean(np.asarray(out["landing_x"])[landed])) if landed.any() else None},
           "n_landed": int(landed.sum())}
    if return_samples:
        res["_samples"] = {"land_x": np.asarray(out["land_x"]), "land_y": np.asarray(out["land_y"]),
                           "success": success}
    return res
