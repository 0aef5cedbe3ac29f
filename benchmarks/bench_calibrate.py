"""Speed of the serve-validation machinery (issue 13 section 3).

On synthetic CourtVision-like serves (flown by ``cross2014``; :func:`tennislab.calibrate.synthetic_serves`):

* the batch aim through the net points (Newton on elevation and heading, each iteration one
  ``fly_batch`` call of 3 N flights): serves aimed per second, flights per second;
* the baseline measured in the same run: the same serves aimed one at a time with SciPy's
  ``solve_ivp`` reference flight (``core.flight.fly``) and ``scipy.optimize.root``;
* one calibration (cd and the serve families' spin axes, fitted on half the serves).

    .venv/bin/python benchmarks/bench_calibrate.py [--n 13000] [--baseline 40]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.optimize import root

from tennislab.calibrate import SpinAxis, calibrate_serves, predict_bounces, synthetic_serves
from tennislab.calibrate.aim import aim_through_net, serve_states
from tennislab.core.flight import FlightParams, fly_dense


def main(argv=None) -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=13000, help="serves (the real set has 13,092 usable)")
    ap.add_argument("--baseline", type=int, default=40, help="serves aimed one at a time with SciPy")
    args = ap.parse_args(argv)
    truth = FlightParams.from_options(aero="cross2014", cd=0.62, cl=0.45)
    axis = SpinAxis.angle(60.0)
    s = synthetic_serves(args.n, truth, axis, seed=1)
    params = FlightParams()  # the default model: a realistic misfit, as on real serves
    ft, fs = axis.fractions(s.family)
    aim_through_net(s.impact[:10], s.speed[:10], s.spin[:10], s.net[:10], params, f_top=ft[:10], f_side=fs[:10])
    t0 = time.perf_counter()
    aim = aim_through_net(s.impact, s.speed, s.spin, s.net, params, f_top=ft, f_side=fs)
    dt = time.perf_counter() - t0
    print(
        f"batch aim: {len(s)} serves in {dt:.2f} s = {len(s) / dt:,.0f} serves/s ({aim.flights / dt:,.0f} flights/s, "
        f"{aim.iterations} Newton iterations, {aim.converged.mean():.2%} converged)"
    )
    k = min(args.baseline, len(s))
    t0 = time.perf_counter()
    for i in range(k):

        def f(x, i=i):
            st = serve_states(
                s.impact[i : i + 1], s.speed[i : i + 1], s.spin[i : i + 1], [x[0]], [x[1]], ft[i : i + 1], fs[i : i + 1]
            )[0]
            tr = fly_dense(st[:3], st[3:6], st[6:9], params, rtol=1e-8, atol=1e-10)
            return [tr.net.y - s.net[i, 0], tr.net.z - s.net[i, 1]]

        root(f, [aim.elevation[i] + 0.01, aim.heading[i] + 0.01], tol=1e-8)
    db = (time.perf_counter() - t0) / k
    print(
        f"baseline (SciPy fly + root, one serve at a time): {1 / db:,.1f} serves/s; "
        f"batch / baseline = {db * len(s) / dt:,.0f}x"
    )
    t0 = time.perf_counter()
    pred = predict_bounces(s, params, axis)
    print(
        f"predict_bounces: {time.perf_counter() - t0:.2f} s; "
        f"median miss of the default model {np.median(pred.miss):.3f} m"
    )
    t0 = time.perf_counter()
    r = calibrate_serves(s, fit="cd", cl=0.45, spin_axis="fitted", split="parity")
    print(
        f"calibrate_serves (cd + the families' axis fractions, {r.to_dict()['n_fit']} serves): "
        f"{time.perf_counter() - t0:.1f} s, "
        f"{r.evaluations} evaluations; cd = {r.values['cd']:.4f} (truth 0.62)"
    )


if __name__ == "__main__":
    main()
