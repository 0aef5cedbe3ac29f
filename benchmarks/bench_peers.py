"""fly_batch against the batch ODE tools an expert would pick instead, on the same shots and physics.

20,000 mixed shots (serves, groundstrokes, lobs; spin up to 6000 rpm about random axes), two physics:
constant C_D 0.55 / C_L 0.25, and the default aero model.  Each solver's landing is compared with a
SciPy DOP853 rtol 1e-11 reference on the first ``--ref`` shots; rates are best of ``--repeats`` timed
runs after a warm-up (JIT compilation excluded), all measured in this run:

* ``fly_batch``: by default, and with each kernel (lockstep, per-shot), at the model's tolerance;
* diffrax (JAX on CPU, float64): ``vmap``ped Tsit5 with a PID step-size controller and a landing
  ``Event`` located by Newton's method, ``jit``-compiled, at rtol = atol 1e-6 and 1e-8;
* SciPy ``solve_ivp`` RK45 rtol 1e-8 (through ``fly_dense``) on a subsample, its rate scaled;
* CyRK ``nbsolve_ivp`` (no event) if installed.

JAX and diffrax are the optional ``bench`` extra (``pip install -e .[bench]``); without them that part
is skipped with a note.  Prints traj/s, the largest landing difference, and fly_batch's ratio to each.

Usage:  python benchmarks/bench_peers.py [--shots 20000] [--ref 300] [--repeats 3]
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _shots import mixed_shots

from tennislab.core.aero import _CAP_BLEND, get_aero_model
from tennislab.core.flight import FlightParams, fly_batch, fly_dense

T_MAX = 20.0


def _best(fn, n: int, repeats: int) -> float:
    """Best rate n / time [1/s] over ``repeats`` timed calls of ``fn`` (after one warm-up call)."""
    fn()
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return n / best


def _reference(S, p: FlightParams) -> np.ndarray:
    """Landing (x, y) [m] of each state by SciPy DOP853 at rtol 1e-11."""
    out = []
    for s in S:
        tr = fly_dense(s[:3], s[3:6], s[6:], p, rtol=1e-11, atol=1e-13)
        out.append([tr.landing.x, tr.landing.y])
    return np.array(out)


def _miss_mm(xy: np.ndarray, ref: np.ndarray) -> float:
    return float(np.nanmax(np.hypot(xy[:, 0] - ref[:, 0], xy[:, 1] - ref[:, 1]))) * 1e3


def _diffrax_solver(p: FlightParams, rtol: float):
    """A jit-compiled function (N, 9) states -> (N, 2) landings with diffrax, or ``None`` if absent."""
    try:
        import diffrax
        import jax
        import jax.numpy as jnp
        import optimistix as optx
    except ImportError:
        return None
    jax.config.update("jax_enable_x64", True)
    k, g, r = p.k, p.atmosphere.gravity, p.ball.radius
    cd0, slope, cap = (float(x) for x in (list(p.aero.params) + [math.inf, math.inf])[:3])
    if p.aero.name == "constant":
        slope = None
    e2 = _CAP_BLEND * _CAP_BLEND

    def coefficients(u, w):
        if slope is None:
            return cd0, float(p.aero.params[1])
        lin = slope * r * w / u
        d = cap - lin
        return cd0, 0.5 * (lin + cap - jnp.sqrt(d * d + e2)) + 0.5 * (math.sqrt(cap * cap + e2) - cap)

    def rhs(t, y, args):
        v, w = y[3:6], y[6:9]
        u = jnp.sqrt(v @ v)
        wn = jnp.sqrt(w @ w)
        cd, cl = coefficients(u, wn)
        lift = jnp.where(wn > 0, k * cl * u / jnp.where(wn > 0, wn, 1.0), 0.0)
        a = -k * cd * u * v + lift * jnp.cross(w, v) - jnp.array([0.0, 0.0, g])
        return jnp.concatenate([v, a, jnp.zeros(3)])

    def landed(t, y, args, **kwargs):
        return y[2] - r

    event = diffrax.Event(landed, root_finder=optx.Newton(rtol=1e-12, atol=1e-12))

    def one(y0):
        sol = diffrax.diffeqsolve(
            diffrax.ODETerm(rhs),
            diffrax.Tsit5(),
            t0=0.0,
            t1=T_MAX,
            dt0=0.01,
            y0=y0,
            stepsize_controller=diffrax.PIDController(rtol=rtol, atol=rtol),
            event=event,
            saveat=diffrax.SaveAt(t1=True),
            max_steps=4096,
        )
        return sol.ys[-1, :2]

    f = jax.jit(jax.vmap(one))
    return lambda S: np.asarray(f(jnp.asarray(S)))


def _cyrk_rate(S, p: FlightParams, n: int):
    """CyRK nbsolve_ivp per shot (RK45, rtol 1e-8, to the constant model's flight time, no event)."""
    try:
        import numba as nb
        from CyRK import nbsolve_ivp
    except ImportError:
        return None
    k, g = p.k, p.atmosphere.gravity
    cd, cl = (float(x) for x in p.aero.params[:2])

    @nb.njit
    def f(t, y):
        out = np.zeros(9)
        u = math.sqrt(y[3] ** 2 + y[4] ** 2 + y[5] ** 2)
        w = math.sqrt(y[6] ** 2 + y[7] ** 2 + y[8] ** 2)
        lf = k * cl * u / w if w > 0 else 0.0
        out[0:3] = y[3:6]
        out[3] = -k * cd * u * y[3] + lf * (y[7] * y[5] - y[8] * y[4])
        out[4] = -k * cd * u * y[4] + lf * (y[8] * y[3] - y[6] * y[5])
        out[5] = -k * cd * u * y[5] + lf * (y[6] * y[4] - y[7] * y[3]) - g
        return out

    def run():
        for s in S[:n]:
            nbsolve_ivp(f, (0.0, 1.5), s, rk_method=1, rtol=1e-8, atol=1e-8)

    return _best(run, n, 1)


def _physics(name: str, S, args, rows: list) -> dict:
    model = get_aero_model("constant", cd=0.55, cl=0.25) if name == "constant" else get_aero_model(name)
    p = FlightParams(aero=model)
    n = len(S)
    R = S[: args.ref]
    ref = _reference(R, p)
    res: dict = {}
    for kern in ("auto", "lockstep", "per-shot"):
        rate = _best(lambda kern=kern: fly_batch(S, p, kernel=kern), n, args.repeats)
        tb = fly_batch(R, p, kernel=kern)
        err = _miss_mm(np.column_stack([tb["land_x"], tb["land_y"]]), ref)
        res[kern] = (rate, err)
        what = "default" if kern == "auto" else f"kernel={kern!r}"
        rows.append((name, f"fly_batch, {what} (tol {p.aero.batch_tol:.0e})", rate, err))
    for rtol in (1e-6, 1e-8):
        solve = _diffrax_solver(p, rtol)
        if solve is None:
            print("peers: diffrax/JAX not installed (pip install -e .[bench]): skipped")
            break
        solve(S)  # compile
        rate = _best(lambda solve=solve: solve(S), n, args.repeats)
        err = _miss_mm(solve(R), ref)
        res[f"diffrax {rtol:.0e}"] = (rate, err)
        rows.append((name, f"diffrax Tsit5 + PID + Event, vmap, jit, rtol {rtol:.0e}", rate, err))
    m = args.scipy
    t0 = time.perf_counter()
    xy = np.array(
        [
            [tr.landing.x, tr.landing.y]
            for tr in (fly_dense(s[:3], s[3:6], s[6:], p, method="RK45", rtol=1e-8, atol=1e-8) for s in S[:m])
        ]
    )
    rate = m / (time.perf_counter() - t0)
    err = _miss_mm(xy[: min(m, args.ref)], ref[: min(m, args.ref)])
    res["scipy"] = (rate, err)
    rows.append((name, f"SciPy solve_ivp RK45 rtol 1e-8 ({m} shots, scaled)", rate, err))
    if name == "constant":
        cy = _cyrk_rate(S, p, 200)
        if cy is None:
            print("peers: CyRK not installed: skipped")
        else:
            res["cyrk"] = (cy, math.nan)
            rows.append((name, "CyRK nbsolve_ivp RK45 rtol 1e-8 per shot (no event)", cy, math.nan))
    return res


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--shots", type=int, default=20_000)
    ap.add_argument("--ref", type=int, default=300, help="shots compared with the DOP853 reference")
    ap.add_argument("--scipy", type=int, default=100, help="shots flown by SciPy (its rate scaled)")
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args([] if argv is None else argv)
    import numba

    S = mixed_shots(args.shots, seed=11)
    print(
        f"peers: {args.shots:,} mixed shots, {numba.get_num_threads()} threads, load {os.getloadavg()[0]:.1f}; "
        f"landing vs DOP853 rtol 1e-11 on {args.ref} of them"
    )
    rows: list = []
    out = {}
    for name in ("constant", "choppin2018"):
        res = _physics(name, S, args, rows)
        out[name] = res
        best, err = res["auto"]
        for key, (rate, e) in res.items():
            if key != "auto":
                acc = f"landing {err:.5f} vs {e:.5f} mm"
                print(f"peers [{name}]: fly_batch (default) / {key} = {best / rate:,.2f}x ({acc})")
    print("| physics | solver | traj/s | landing error (max) |")
    print("|---|---|---|---|")
    for name, what, rate, err in rows:
        e = "–" if math.isnan(err) else f"{err:.5f} mm"
        print(f"| {name} | {what} | {rate:,.0f} | {e} |")
    d = out["choppin2018"]
    print(
        f"peers: default model {d['auto'][0]:,.0f} traj/s (target >= 1,000,000), landing {d['auto'][1]:.5f} mm "
        "(target < 0.01 mm)"
    )
    return out


if __name__ == "__main__":
    main(sys.argv[1:])
