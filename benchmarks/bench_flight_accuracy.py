"""Landing accuracy of the batch path against the SciPy reference, per aero model and tolerance.

Target (issue 2): landing point within 0.01 mm of the reference (DOP853, rtol 1e-10) for serves,
groundstrokes and lobs with up to 6000 rpm about any axis.  The shots are those of
tests/core/test_flight_accuracy.py (serves 30-60 m/s, groundstrokes 15-40 m/s, lobs 12-25 m/s at 25-60 deg,
spin 0-6000 rpm about uniformly random axes), many more of them.  Prints, per model and tolerance, the
maximum, 99th percentile and mean landing difference and the mean number of accepted steps.

Usage:  python benchmarks/bench_flight_accuracy.py [--shots 3000] [--seeds 23 29 31] [--tol 2e-7 5e-7]
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "core"))
from test_flight_accuracy import shot_states

from tennislab.core.aero import get_aero_model
from tennislab.core.flight import FlightParams, fly_batch, fly_dense

MODELS = tuple(os.environ.get("BENCH_MODELS", "choppin2018 stepanek1988 launcher2015 cross2014").split())


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--shots", type=int, default=3000)
    ap.add_argument("--seeds", type=int, nargs="+", default=[23])
    ap.add_argument("--tol", type=float, nargs="+", default=[0.0], help="rtol = atol; 0: the model's batch_tol")
    args = ap.parse_args([] if argv is None else argv)  # run_all.py calls main() without arguments
    worst = {}
    for model in MODELS:
        p = FlightParams(aero=get_aero_model(model))
        tols = [t if t > 0 else p.aero.batch_tol for t in args.tol]
        errs: dict = {tol: [] for tol in tols}
        steps: dict = {tol: [] for tol in tols}
        for seed in args.seeds:
            S = shot_states(args.shots, seed=seed)
            ref = np.array([[tr.landing.x, tr.landing.y] for tr in (fly_dense(s[:3], s[3:6], s[6:], p) for s in S)])
            for tol in tols:
                tb = fly_batch(S, p, rtol=tol, atol=tol)
                errs[tol].append(np.hypot(ref[:, 0] - tb["land_x"], ref[:, 1] - tb["land_y"]) * 1e3)
                steps[tol].append(tb["n_steps"])
        for tol in tols:
            e, n = np.concatenate(errs[tol]), np.concatenate(steps[tol])
            worst[(model, tol)] = float(e.max())
            print(
                f"accuracy [{model:13s}] tol {tol:.0e}: landing difference max {e.max():.4f} mm, "
                f"p99 {np.percentile(e, 99):.4f} mm, mean {e.mean():.5f} mm over {e.size:,} shots; "
                f"{n.mean():.2f} steps (target max < 0.01 mm: {'PASS' if e.max() < 0.01 else 'FAIL'})"
            )
    return worst


if __name__ == "__main__":
    main(sys.argv[1:])
