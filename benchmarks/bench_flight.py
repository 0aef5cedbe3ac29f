"""Flight engine throughput: Numba batch path vs SciPy solve_ivp (RK45, events, rtol 1e-8).

Target (issue 2): batch landing-point throughput >= 2000x the SciPy path on 2 cores.
Prints both figures measured in this run and their ratio, plus the batch path's
landing error against the SciPy DOP853 reference at rtol 1e-10.
"""
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from _shots import mixed_shots  # noqa: E402

from tennislab.core.flight import FlightParams, fly, fly_batch  # noqa: E402


def _ratio_for_model(name: str, S, n_scipy: int) -> tuple[float, float]:
    """(batch traj/s, SciPy RK45 traj/s) for one aero model on the same shots."""
    from tennislab.core.aero import get_aero_model
    p = FlightParams(aero=get_aero_model(name))
    fly_batch(S[:1000], p)
    t0 = time.perf_counter()
    fly_batch(S, p)
    rb = len(S) / (time.perf_counter() - t0)
    t0 = time.perf_counter()
    for i in range(n_scipy):
        fly(S[i, :3], S[i, 3:6], S[i, 6:], p, method="RK45", rtol=1e-8, atol=1e-8)
    return rb, n_scipy / (time.perf_counter() - t0)


def main(n_batch: int = 1_000_000, n_scipy: int = 150) -> dict:
    import numba
    p = FlightParams()
    S = mixed_shots(n_batch, seed=3)
    fly_batch(S[:1000], p)                       # warm (JIT cache load)
    t0 = time.perf_counter()
    tb = fly_batch(S, p)
    t_batch = time.perf_counter() - t0
    rate_batch = n_batch / t_batch

    t0 = time.perf_counter()
    for i in range(n_scipy):
        fly(S[i, :3], S[i, 3:6], S[i, 6:], p, method="RK45", rtol=1e-8, atol=1e-8)
    t_scipy = time.perf_counter() - t0
    rate_scipy = n_scipy / t_scipy

    errs = []
    for i in range(60):
        tr = fly(S[i, :3], S[i, 3:6], S[i, 6:], p)
        errs.append(math.hypot(tr.landing.x - tb["land_x"][i], tr.landing.y - tb["land_y"][i]))
    res = {
        "threads": numba.get_num_threads(),
        "batch_traj_per_s": rate_batch,
        "scipy_rk45_traj_per_s": rate_scipy,
        "ratio": rate_batch / rate_scipy,
        "max_landing_error_mm": max(errs) * 1e3,
        "mean_steps": float(np.mean(tb["n_steps"])),
    }
    print(f"flight: batch {rate_batch:,.0f} traj/s on {res['threads']} threads "
          f"({n_batch:,} mixed shots, {res['mean_steps']:.1f} steps each)")
    print(f"flight: SciPy RK45 rtol 1e-8 with events {rate_scipy:,.1f} traj/s "
          f"({1e3 / rate_scipy:.2f} ms each)")
    print(f"flight: ratio batch/SciPy = {res['ratio']:,.0f}x (target >= 2000x)")
    print(f"flight: max landing error vs DOP853 rtol 1e-10 reference = {res['max_landing_error_mm']:.5f} mm "
          f"(target 0.01 mm)")
    for name in ("launcher2015", "constant"):
        rb, rs = _ratio_for_model(name, S[:300_000], n_scipy // 2)
        res[f"ratio_{name}"] = rb / rs
        print(f"flight [{name}]: batch {rb:,.0f} traj/s, SciPy {rs:,.1f} traj/s, ratio {rb / rs:,.0f}x")
    return res


if __name__ == "__main__":
    main()
