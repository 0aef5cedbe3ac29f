"""Launcher benchmarks (issue 5): aiming cost, launch-state throughput, quantisation error.

1. ``launch_states`` (vectorised NumPy) vs a per-shot Python loop building the same
   states with ``math`` (baseline measured in this run): states/s and speed-up.
2. ``aim`` (scan + Newton + quantised neighbours, both solutions) per target vs one
   reference flight with ``fly`` (SciPy DOP853, rtol 1e-10) of the same shot, measured
   in this run: "an aim costs X reference flights".
3. Aiming on the machine's steps (issue 15): over a grid of targets in the far court, for every
   drill shot type, the miss of ``aim``'s answer [mm] (median, 95th percentile) with exact
   tolerances (only the angles searched: the old behaviour), 3 km/h and 100 rpm as a spin vector, the
   default tolerances (the same, and the axis may turn by 10 deg) and 20 deg; time per aim.
4. Drill compilation time of every shipped drill.

Run: ``python benchmarks/bench_launcher.py [--quick]``.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np


def _loop_states(spec, h, v, a, b, w, g):
    out = np.empty((len(h), 9))
    for i in range(len(h)):
        ar, br, gr = math.radians(a[i]), math.radians(b[i]), math.radians(g[i])
        d = (math.cos(ar) * math.cos(br), math.cos(ar) * math.sin(br), math.sin(ar))
        hh = (-math.sin(br), math.cos(br), 0.0)
        uu = (-math.sin(ar) * math.cos(br), -math.sin(ar) * math.sin(br), math.cos(ar))
        vv, ww = v[i] / 3.6, w[i] * math.pi / 30
        out[i] = (
            spec.position[0],
            spec.position[1],
            h[i],
            *(vv * c for c in d),
            *(ww * (math.cos(gr) * hh[k] + math.sin(gr) * uu[k]) for k in range(3)),
        )
    return out


def bench_states(n):
    from tennislab.launcher.machine import DEFAULT_SPEC, launch_states

    rng = np.random.default_rng(1)
    cols = [
        rng.uniform(0.1, 3, n),
        rng.uniform(30, 200, n),
        rng.uniform(-20, 80, n),
        rng.uniform(-40, 40, n),
        rng.uniform(0, 2000, n),
        rng.uniform(-180, 180, n),
    ]
    t_vec = math.inf
    for _ in range(3):  # best of 3 (the first call pays for page faults of the fresh arrays)
        t0 = time.perf_counter()
        s = launch_states(DEFAULT_SPEC, *cols)
        t_vec = min(t_vec, time.perf_counter() - t0)
    m = min(n, 20_000)
    t0 = time.perf_counter()
    ref = _loop_states(DEFAULT_SPEC, *(c[:m] for c in cols))
    t_loop = (time.perf_counter() - t0) * n / m
    err = np.abs(s[:m] - ref).max()
    print(
        f"launch_states: {n / t_vec:,.0f} states/s vectorised vs {n / t_loop:,.0f} states/s Python loop "
        f"(baseline, this run): x{t_loop / t_vec:.0f}; max |difference| {err:.1e}"
    )


def bench_aim(n_targets):
    from tennislab.core.flight import fly_dense
    from tennislab.errors import InputError
    from tennislab.launcher.aim import aim_all, launcher_params
    from tennislab.launcher.machine import DEFAULT_SPEC, launch_states

    params = launcher_params()
    aim_all((8.0, 0.0), 80, 1000, 0)  # compile / warm up
    rng = np.random.default_rng(2)
    targets = np.column_stack([rng.uniform(6, 11.5, n_targets), rng.uniform(-4, 4, n_targets)])
    speeds = rng.integers(70, 120, n_targets)
    spins = rng.integers(0, 2000, n_targets)
    axes = rng.choice([0, 180, 45, -45], n_targets)
    t_aim, t_fly, n_ok = 0.0, 0.0, 0
    for (x, y), v, w, g in zip(targets, speeds, spins, axes):
        t0 = time.perf_counter()
        try:
            sols, _ = aim_all((x, y), v, w, g)
        except InputError:
            continue
        t_aim += time.perf_counter() - t0
        s = next(iter(sols.values())).settings
        st = launch_states(DEFAULT_SPEC, s.height_m, s.speed_kmh, s.elevation_deg, s.heading_deg, w, g)[0]
        t0 = time.perf_counter()
        fly_dense(st[0:3], st[3:6], st[6:9], params)
        t_fly += time.perf_counter() - t0
        n_ok += 1
    print(
        f"aim (both solutions): {1e3 * t_aim / n_ok:.1f} ms per target vs {1e3 * t_fly / n_ok:.1f} ms for one "
        f"reference fly() (baseline, this run): an aim costs {t_aim / t_fly:.1f} reference flights "
        f"({n_ok} targets)"
    )


def bench_aiming_grid(step: float, variants=("exact", "vector only", "default", "axis 20 deg")):
    """Miss of ``aim`` over a grid of targets in the far court for every shot type (issue 15).

    Targets: x from 1.5 to 11.5 m and y from -4.5 to 4.5 m in steps of ``step``; shots: the drill
    shot types (speed, spin, axis, trajectory of :data:`tennislab.launcher.drills.SHOT_TYPES`,
    serve-return from 3 m into the service boxes only), launched from the default position.
    "Reachable" = aim answers; targets where the net keeps the ball from landing nearer
    (``net_limited``) are counted apart.  Variants: ``exact`` (tolerances 0: only the angles are
    searched, as before), ``vector only`` (3 km/h, 100 rpm as a spin vector, the axis turning only
    within it), ``default`` (the same, and the axis may turn by 10 deg), ``axis 20 deg``.
    """
    from tennislab.errors import InputError
    from tennislab.launcher.aim import aim
    from tennislab.launcher.drills import SHOT_TYPES

    kw = {
        "exact": dict(speed_tolerance_kmh=0, spin_tolerance_rpm=0, spin_axis_tolerance_deg=0),
        "vector only": dict(spin_axis_tolerance_deg=0),
        "default": {},
        "axis 20 deg": dict(spin_axis_tolerance_deg=20),
    }
    xs = np.arange(1.5, 11.5 + 1e-9, step)
    ys = np.arange(-4.5, 4.5 + 1e-9, step)
    aim((9.0, 2.0), 80, 1500)  # compile / warm up
    for name in variants:
        rows = {}
        t_all, n_all, limited = 0.0, 0, 0
        for t in SHOT_TYPES.values():
            height = t.height_m or 1.0
            miss = []
            for x in xs:
                for y in ys:
                    if t.name == "serve-return" and not (x <= 6.4 and abs(y) <= 4.115):
                        continue
                    t0 = time.perf_counter()
                    try:
                        r = aim(
                            (x, y),
                            t.speed_kmh,
                            t.spin_rpm,
                            t.spin_axis_deg,
                            height,
                            trajectory=t.trajectory,
                            **kw[name],
                        )
                    except InputError:
                        continue
                    t_all += time.perf_counter() - t0
                    n_all += 1
                    if r.solution.net_limited:
                        limited += 1
                        continue
                    miss.append(r.miss_mm)
            rows[t.name] = np.array(miss)
        allm = np.concatenate([m for m in rows.values() if m.size])
        print(
            f"aim [{name}] over {allm.size} reachable targets (+{limited} net-limited, apart): miss median "
            f"{np.median(allm):.1f} mm, p95 {np.percentile(allm, 95):.1f} mm; share < 20 mm "
            f"{np.mean(allm < 20):.0%}; {1e3 * t_all / max(1, n_all):.0f} ms per aim"
        )
        for tname, m in rows.items():
            if m.size:
                print(
                    f"    {tname:<13} {m.size:4d} targets: median {np.median(m):6.1f} mm, "
                    f"p95 {np.percentile(m, 95):6.1f} mm, max {m.max():6.1f} mm"
                )


def bench_drills():
    from tennislab.launcher.drill_schema import load_drill, shipped_drills
    from tennislab.launcher.drills import compile_drill

    for name in shipped_drills():
        t0 = time.perf_counter()
        c = compile_drill(load_drill(name))
        print(
            f"drill {name}: {len(c.shots)} shots, {len(c.unique)} aimed, ok={c.ok}, "
            f"{1e3 * (time.perf_counter() - t0):.0f} ms"
        )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer targets")
    args = ap.parse_args(argv if argv is not None else [])
    bench_states(200_000 if args.quick else 1_000_000)
    bench_aim(10 if args.quick else 40)
    bench_aiming_grid(2.0 if args.quick else 1.0)
    bench_drills()


if __name__ == "__main__":
    import sys

    main(sys.argv[1:])
