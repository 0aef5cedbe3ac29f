"""Monte Carlo margin of error of a serve (the paper's "future work", sec. 4).

:func:`monte_carlo` is the workflow behind ``tennislab serve-mc`` (its :class:`MonteCarloResult`
``to_dict()`` is the ``--json``).

A nominal serve (player, alpha, beta) is repeated n times with normal scatter
of the impact angle alpha, the face angle beta and the face azimuth psi (sd
``sd_angle``), the racket speed (``sd_speed``) and the impact height
(``sd_height``).  Output: the probability of success (the seed's 2-D criteria,
or a real service box with ``target``), the mean and covariance of the landing
points (court frame, x along, y across [m]) and the 95 % landing ellipse.

Memory is bounded for any n (up to 10^8): the serves are simulated in blocks
(:func:`block_size`, at most 65536 serves) by :func:`mc_blocks`, which keeps
only per-block sufficient statistics (counts, means, centred co-moments of the
landing points); :func:`combine_blocks` merges them in block order.  Each draw
is a pure function of (seed, stream, row) (:mod:`tennislab.batch.rng`, streams
:data:`STREAMS`), so a run is reproducible for a given seed and n and
bit-identical whatever the scheduler and chunking.  Impacts are interpolated
(bilinear) from one 81 x 161 table on a (V, alpha) grid spanning every value
the draws can take (nominal +- :data:`Z_MAX` sd; :func:`scatter_table`,
interpolation error checked in tests/serve/test_mc.py); flights use the
compiled batch integrator.  :func:`mc_blocks` is the batch worker (module
level, for ``tennislab.batch.map_chunks`` over a ``RowRange`` of blocks).

References
----------
.. [1] Grosen, Kousted & Treichel (2021), 2-dimensional tennis serves show similar successful mechanical
    parameter across physiological differences, Aalborg University (seed 000), sec. 4 (future work)
.. [2] Chan, Golub & LeVeque (1979), Updating formulae and a pairwise algorithm for computing sample
    variances, Stanford University, report STAN-CS-79-773
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass, field
from typing import Any

import numba as nb
import numpy as np

from tennislab.batch import rng
from tennislab.batch.sources import RowRange, default_chunk_size
from tennislab.core.flight import FlightParams
from tennislab.core.impact import ImpactParams, impact_batch
from tennislab.errors import InputError, check_range
from tennislab.results import Table, jsonable
from tennislab.serve.pipeline import REASON_CODES, Setup, flights, make_setup
from tennislab.serve.players import PlayerProfile
from tennislab.serve.setup import SeedCriteria

__all__ = ["MonteCarloResult", "monte_carlo", "mc_blocks", "combine_blocks", "block_size", "landing_stats"]

CHI2_95_2DOF = 5.991464547107979  #: chi-square 95 % quantile, 2 degrees of freedom
TABLE_STEPS = 200  #: impact steps per half period of the tabulated impacts (interpolation error: tests)


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
def _lookup_kernel(a, V, Vg, Ag, T, out):
    """Stage 1 by table: bilinear (V, alpha) interpolation of the impact results (v_n, v_t, omega), row by row."""
    nV, nA = Vg.shape[0], Ag.shape[0]
    for k in nb.prange(a.shape[0]):
        iv, fv = _loc(Vg, V[k])
        ia, fa = _loc(Ag, a[k])
        iv1 = min(iv + 1, nV - 1)
        ia1 = min(ia + 1, nA - 1)
        w00, w01, w10, w11 = (1 - fv) * (1 - fa), (1 - fv) * fa, fv * (1 - fa), fv * fa
        for c in range(3):
            out[k, c] = w00 * T[c, iv, ia] + w01 * T[c, iv, ia1] + w10 * T[c, iv1, ia] + w11 * T[c, iv1, ia1]


def lookup(table: dict, speed, alpha) -> dict[str, np.ndarray]:
    """Impact results ``v_n``, ``v_t`` [m/s], ``omega`` [rad/s] interpolated from a :func:`scatter_table`
    at racket speeds [m/s] and impact angles [rad] (equal-length arrays)."""
    a = np.ascontiguousarray(alpha, np.float64)
    out = np.empty((a.size, 3))
    _lookup_kernel(a, np.ascontiguousarray(speed, np.float64), table["V"], table["A"], table["T"], out)
    return {"v_n": out[:, 0], "v_t": out[:, 1], "omega": out[:, 2]}


def impact_table(v_range, a_range, params: ImpactParams, nv: int = 41, na: int = 81, **impact_kw) -> _Table:
    """Impact results (v_n, v_t, omega) on a grid of racket speed [m/s] x impact angle [rad]."""
    v0, v1 = float(v_range[0]), float(v_range[1])
    a0, a1 = float(a_range[0]), float(a_range[1])
    V = np.linspace(v0, v1, nv) if v1 > v0 else np.array([v0])
    A = np.linspace(a0, a1, na) if a1 > a0 else np.array([a0])
    impact_kw = {"steps": TABLE_STEPS, **impact_kw}
    VV, AA = np.meshgrid(V, A, indexing="ij")
    r = impact_batch(VV, AA, params, **impact_kw)
    return _Table(V, A, {k: r[k] for k in ("v_n", "v_t", "omega")})


#: Largest |z| a normal of :mod:`tennislab.batch.rng` can take: Box-Muller with u1 >= 2^-54
#: (53-bit uniforms offset by half a step), sqrt(-2 ln 2^-54) = 8.652.  The impact table spans
#: nominal +- Z_MAX sd, so no draw is ever outside it (no clamping), whatever n and seed.
Z_MAX = math.sqrt(-2.0 * math.log(2.0**-54))
#: rng streams of the five scattered quantities (tennislab.batch.rng, keyed by (seed, stream, row))
STREAMS = {"alpha": 0, "beta": 1, "psi": 2, "speed": 3, "height": 4}
_A_LIM = math.radians(89.0)


def block_size(n: int) -> int:
    """Serves per statistics block: the batch layer's default chunk for n rows (clip(n/64, 1024, 65536)).

    Depends on n only, so the per-block statistics -- and their fixed-order
    combination -- never depend on the scheduler or ``--chunk-size``.
    """
    return default_chunk_size(n)


def scatter_table(setup: Setup, alpha_deg, sd_angle, sd_speed, nv=81, na=161) -> dict:
    """Impact table over every (V, alpha) the draws can take (nominal +- Z_MAX sd, clipped as the draws),
    with the setup's impact parameters and integration."""
    V0, a0 = setup.player.racket_speed, math.radians(alpha_deg)
    v_lo, v_hi = max(1.0, V0 - Z_MAX * sd_speed), max(1.0, V0 + Z_MAX * sd_speed)
    da = math.radians(Z_MAX * sd_angle)
    a_lo, a_hi = (min(max(a0 - da, -_A_LIM), _A_LIM), min(max(a0 + da, -_A_LIM), _A_LIM))
    kw = {"steps": setup.steps, "dt": setup.dt, "method": setup.method}
    tab = impact_table((v_lo, v_hi), (a_lo, a_hi), setup.impact_params, nv=nv, na=na, **kw)
    T = np.ascontiguousarray(np.stack([tab.vals[k] for k in ("v_n", "v_t", "omega")]))
    return {"V": tab.V, "A": tab.A, "T": T}


def draw_rows(rows, *, seed: int, nominal: dict, table: dict) -> dict:
    """The serves at global row indices ``rows``: their impacts (stage 1, from ``table``) and faces,
    the inputs of :func:`tennislab.serve.pipeline.flights` (``v_n``, ``v_t``, ``omega``, ``beta``,
    ``azimuth``, ``height``).

    Each draw is a pure function of (seed, stream, row) (:mod:`tennislab.batch.rng`), so a serve is
    the same whichever block, chunk or worker computes it.  ``nominal``: alpha, beta, azimuth [deg],
    speed [m/s], height [m] and their sd ``sd_angle``, ``sd_azimuth`` [deg], ``sd_speed``, ``sd_height``.
    """
    rows = np.asarray(rows, dtype=np.int64)
    nm = nominal
    a = np.radians(nm["alpha"] + nm["sd_angle"] * rng.normal(seed, rows, STREAMS["alpha"]))
    b = np.radians(nm["beta"] + nm["sd_angle"] * rng.normal(seed, rows, STREAMS["beta"]))
    psi = np.radians(nm["azimuth"] + nm["sd_azimuth"] * rng.normal(seed, rows, STREAMS["psi"]))
    V = np.clip(nm["speed"] + nm["sd_speed"] * rng.normal(seed, rows, STREAMS["speed"]), 1.0, None)
    h = nm["height"] + nm["sd_height"] * rng.normal(seed, rows, STREAMS["height"])
    a = np.clip(a, -_A_LIM, _A_LIM)
    return {**lookup(table, V, a), "beta": b, "azimuth": psi, "height": h}


def mc_blocks(chunk: dict, *, n: int, block: int, seed: int, nominal: dict, table: dict, setup: Setup) -> dict:
    """Batch worker: sufficient statistics of whole blocks of serves (one output row per block).

    ``chunk["block"]``: block indices; block b = serves [b*block, min(n, (b+1)*block)).  Only one
    block of serves is in memory at a time.  Per block: ``n`` (serves), ``n_success``, ``n_landed``,
    the landed serves' means ``mean_x``, ``mean_y`` (court frame [m]), ``mean_landing_x`` (from the
    impact point [m]) and centred sums of products ``m2_xx``, ``m2_xy``, ``m2_yy`` [m^2] (NaN
    where nothing landed); :func:`combine_blocks` merges them.
    """
    blocks = np.asarray(chunk["block"], dtype=np.int64)
    cols = ("n", "n_success", "n_landed", "mean_x", "mean_y", "mean_landing_x", "m2_xx", "m2_xy", "m2_yy")
    out = {k: np.zeros(blocks.size, np.int64 if k.startswith("n") else np.float64) for k in cols}
    for j, b in enumerate(blocks):
        rows = np.arange(int(b) * block, min(n, (int(b) + 1) * block), dtype=np.int64)
        r = flights(draw_rows(rows, seed=seed, nominal=nominal, table=table), setup=setup)
        landed = np.asarray(r["landed"], bool)
        x, y, lx = r["land_x"][landed], r["land_y"][landed], r["landing_x"][landed]
        out["n"][j], out["n_success"][j], out["n_landed"][j] = rows.size, int(r["success"].sum()), x.size
        if x.size:
            mx, my = x.mean(), y.mean()
            dx, dy = x - mx, y - my
            out["mean_x"][j], out["mean_y"][j], out["mean_landing_x"][j] = mx, my, lx.mean()
            # plain numpy sums, not BLAS dot: deterministic, and no BLAS threads spinning against numba's
            out["m2_xx"][j], out["m2_xy"][j], out["m2_yy"][j] = np.sum(dx * dx), np.sum(dx * dy), np.sum(dy * dy)
        else:
            for k in cols[3:]:
                out[k][j] = np.nan
    return out


def combine_blocks(stats: dict) -> dict:
    """Merge per-block statistics in block order (Chan, Golub & LeVeque 1979, pairwise update of
    means and centred co-moments; stable where raw sums of squares would cancel).

    Returns ``n``, ``n_success``, ``n_landed``, ``mean`` [x, y], ``m2`` (2 x 2), ``mean_landing_x``.
    """
    n = int(np.sum(stats["n"]))
    ns = int(np.sum(stats["n_success"]))
    N, mx, my, ml, sxx, sxy, syy = 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    for i in range(len(stats["n"])):
        nb = int(stats["n_landed"][i])
        if nb == 0:
            continue
        bx, by, bl = float(stats["mean_x"][i]), float(stats["mean_y"][i]), float(stats["mean_landing_x"][i])
        tot = N + nb
        dx, dy, f = bx - mx, by - my, nb / tot
        sxx += float(stats["m2_xx"][i]) + dx * dx * N * f
        sxy += float(stats["m2_xy"][i]) + dx * dy * N * f
        syy += float(stats["m2_yy"][i]) + dy * dy * N * f
        mx, my, ml = mx + dx * f, my + dy * f, ml + (bl - ml) * f
        N = tot
    return {
        "n": n,
        "n_success": ns,
        "n_landed": N,
        "mean": [mx, my] if N else [None, None],
        "m2": [[sxx, sxy], [sxy, syy]],
        "mean_landing_x": ml if N else None,
    }


def landing_stats_from_moments(n: int, mean, m2) -> dict:
    """Mean, covariance (ddof 1) and 95 % ellipse (semi-axes [m], major axis angle to x [deg])."""
    if n < 2:
        return {"mean": [float(m) if m is not None else None for m in mean], "cov": None, "ellipse_95": None}
    cov = np.asarray(m2, float) / (n - 1)
    w, v = np.linalg.eigh(cov)
    w = np.clip(w, 0.0, None)
    major = v[:, 1]
    ang = math.degrees(math.atan2(major[1], major[0]))
    ang = ang - 180.0 if ang > 90.0 else (ang + 180.0 if ang <= -90.0 else ang)  # axis: (-90, 90]
    return {
        "mean": [float(mean[0]), float(mean[1])],
        "cov": cov.tolist(),
        "ellipse_95": {
            "semi_axes": [float(math.sqrt(CHI2_95_2DOF * w[1])), float(math.sqrt(CHI2_95_2DOF * w[0]))],
            "angle_deg": ang,
        },
    }


def landing_stats(x, y) -> dict:
    """Mean, covariance and 95 % ellipse of landing points given as arrays (see :func:`landing_stats_from_moments`)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    if x.size == 0:
        return landing_stats_from_moments(0, [None, None], None)
    mx, my = x.mean(), y.mean()
    dx, dy = x - mx, y - my
    sxy = np.sum(dx * dy)
    return landing_stats_from_moments(x.size, [mx, my], [[np.sum(dx * dx), sxy], [sxy, np.sum(dy * dy)]])


def _in_process(fn, source):
    """Default mapper: the blocks one after another in this process (same numbers as any scheduler)."""
    return fn(source.chunk(0, max(source.n_rows, 1)))


@dataclass(frozen=True)
class MonteCarloResult(Table):
    """Monte Carlo of a nominal serve (angles [deg], SI otherwise).  ``to_dict()`` is
    ``tennislab serve-mc --json``; ``rows()``/``to_frame()`` give the landing samples (only when the
    run kept them, ``samples=...``)."""

    player: PlayerProfile
    nominal: dict  #: alpha, beta, azimuth [deg]
    scatter: dict  #: sd_angle, sd_speed, sd_height, sd_azimuth
    n: int
    seed: int
    criteria: str
    p_success: float
    p_success_se: float
    landing: dict  #: mean [x, y], cov (2 x 2) [m, m^2], ellipse_95 (court frame)
    landing_x: dict  #: mean distance from the impact point [m]
    n_landed: int
    caveats: tuple[str, ...] = ()
    samples: dict | None = field(default=None, repr=False)  #: land_x, land_y, success, landed, reason arrays

    COLUMNS = ("land_x", "land_y", "success", "landed", "reason")
    FRAME_COLUMNS = {"land_x": "land_x_m", "land_y": "land_y_m"}

    def to_dict(self) -> dict:
        return jsonable(
            {
                "player": self.player.name,
                "nominal": self.nominal,
                "scatter": self.scatter,
                "n": self.n,
                "seed": self.seed,
                "criteria": self.criteria,
                "p_success": self.p_success,
                "p_success_se": self.p_success_se,
                "landing": self.landing,
                "landing_x": self.landing_x,
                "n_landed": self.n_landed,
                "caveats": list(self.caveats),
            }
        )

    def rows(self) -> list[dict]:
        if self.samples is None:
            raise InputError("samples: this run kept no landing samples (pass samples=True)")
        s = self.samples
        reasons = s.get("reason", np.zeros(len(s["land_x"]), np.int8))
        return [
            {"land_x": float(x), "land_y": float(y), "success": bool(ok), "landed": bool(ld), "reason": REASON_CODES[r]}
            for x, y, ok, ld, r in zip(s["land_x"], s["land_y"], s["success"], s["landed"], reasons)
        ]


def monte_carlo(
    player,
    impact_angle: float,
    face_angle: float,
    *,
    n: int = 10000,
    seed: int = 0,
    sd_angle: float = 1.0,
    sd_speed: float = 1.0,
    sd_height: float = 0.0,
    sd_azimuth: float | None = None,
    target: str | None = None,
    azimuth_deg: float = 0.0,
    brush_deg: float = 0.0,
    server_y: float = 0.0,
    flight: FlightParams | None = None,
    preset: str | None = None,
    impact_params: ImpactParams | None = None,
    criteria: SeedCriteria | None = None,
    mapper=None,
    samples: bool | int = False,
    dt: float = 0.0,
    method: str = "rk4",
) -> MonteCarloResult:
    """Monte Carlo of the nominal serve (``impact_angle``, ``face_angle`` [deg]) of ``player``.

    Angles and their sd in degrees, speeds [m/s], heights [m].  ``sd_azimuth``
    defaults to ``sd_angle``.  Memory is bounded whatever n: the serves are
    simulated in blocks of :func:`block_size` ``(n)`` by :func:`mc_blocks`, which
    keeps only per-block sufficient statistics, merged in block order by
    :func:`combine_blocks`.  ``mapper(fn, source)`` runs ``fn`` over the
    :class:`~tennislab.batch.RowRange` of block indices ``source`` (key ``"block"``)
    and returns its outputs (default: in process; e.g.
    ``functools.partial(map_chunks, scheduler="processes", chunk_size=1)`` --
    chunk sizes there count blocks).  The result is identical for any mapper and chunking.
    ``samples``: True (20000) or a count m: also keep the landing points of the first
    min(n, m) serves (the same serves as in the statistics) in ``samples``.
    ``flight`` defaults to the ``standard`` physics of every command (``preset="seed000"``: the paper's).
    """
    n = int(check_range("n", n, 1, 1e8))
    for nm, v in (("sd_angle", sd_angle), ("sd_speed", sd_speed), ("sd_height", sd_height)):
        check_range(nm, v, 0.0, 45.0)
    if sd_azimuth is not None:
        check_range("sd_azimuth", sd_azimuth, 0.0, 45.0)
    check_range("impact_angle", impact_angle, -89.0, 89.0, "deg")
    check_range("face_angle", face_angle, -90.0, 90.0, "deg")
    setup = make_setup(
        player,
        flight=flight,
        preset=preset,
        impact_params=impact_params,
        criteria=criteria,
        target=target,
        azimuth_deg=azimuth_deg,
        brush_deg=brush_deg,
        server_y=server_y,
        dt=dt,
        method=method,
        steps=TABLE_STEPS,
    )
    # flights at 5 x the aero model's batch tolerance (1e-6 for the registered models, 1e-7 for curves and
    # tables with kinks) and impacts from the table: a serve without scatter lands 0.005-0.07 mm from the
    # single serve's (tests/serve/test_mc.py holds 0.1 mm; the table's grip kink dominates at small alpha),
    # far below any scatter studied
    setup = dataclasses.replace(setup, rtol=5.0 * setup.flight.aero.batch_tol)
    player = setup.player
    sd_az = sd_angle if sd_azimuth is None else sd_azimuth
    nominal = {
        "alpha": float(impact_angle),
        "beta": float(face_angle),
        "azimuth": float(azimuth_deg),
        "speed": float(player.racket_speed),
        "height": float(player.impact_height),
        "sd_angle": float(sd_angle),
        "sd_azimuth": float(sd_az),
        "sd_speed": float(sd_speed),
        "sd_height": float(sd_height),
    }
    table = scatter_table(setup, impact_angle, sd_angle, sd_speed)
    common: dict[str, Any] = dict(seed=int(seed), nominal=nominal, table=table)
    block = block_size(n)
    fn = functools.partial(mc_blocks, n=n, block=block, setup=setup, **common)
    source = RowRange(-(-n // block), key="block")
    stats = (mapper or _in_process)(fn, source)
    tot = combine_blocks(stats)
    p = tot["n_success"] / n
    kept = None
    if samples:
        m = min(n, 20000 if samples is True else int(samples))
        r = flights(draw_rows(np.arange(m, dtype=np.int64), **common), setup=setup)
        kept = {
            "land_x": np.asarray(r["land_x"]),
            "land_y": np.asarray(r["land_y"]),
            "success": np.asarray(r["success"], bool),
            "landed": np.asarray(r["landed"], bool),
            "reason": np.asarray(r["reason"], np.int8),
        }
    return MonteCarloResult(
        player=player,
        nominal={"alpha": float(impact_angle), "beta": float(face_angle), "azimuth": float(azimuth_deg)},
        scatter={"sd_angle": sd_angle, "sd_speed": sd_speed, "sd_height": sd_height, "sd_azimuth": sd_az},
        n=n,
        seed=int(seed),
        criteria=setup.mode,
        p_success=p,
        p_success_se=math.sqrt(max(p * (1 - p), 0.0) / n),
        landing=landing_stats_from_moments(tot["n_landed"], tot["mean"], tot["m2"]),
        landing_x={"mean": tot["mean_landing_x"]},
        n_landed=tot["n_landed"],
        caveats=setup.caveats(),
        samples=kept,
    )
