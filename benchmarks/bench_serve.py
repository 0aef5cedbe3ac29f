"""Benchmark of the serve analysis (issue 3).

Targets (not timed tests): the full 91 x 91 window for all three players in < 0.5 s warm on
2 cores; 10^6 Monte Carlo serves in < 5 s.  Baseline, measured in the same run: a
straightforward vectorised NumPy implementation of the seed's model (explicit Euler at the
seed's dt = 1e-4 s for the impact and the flight, all alpha x beta serves of a window as one
array).  Prints times and the ratio baseline / tennislab.

    python benchmarks/bench_serve.py [--quick] [--mc N] [--mem 1e6,1e7] [--against OLD_SRC]

``--mem`` runs ``serve-mc``'s Monte Carlo (pro, alpha 40, beta 19, sd 1 deg / 1 m/s) once per N
in a fresh child process and prints its peak RSS (``ru_maxrss``) next to the RSS after the
imports and a 1000-serve warm-up (the job's share is the difference): memory must be flat in N.

``--against OLD_SRC`` times the three windows and the 10^6-serve Monte Carlo of this source tree and
of another one (e.g. ``git archive <commit> src | tar -x -C /tmp/old``, then ``/tmp/old/src``) in
alternating fresh processes (three rounds each, best kept) and prints the ratio new / old: on a shared
machine only a ratio measured in the same run says whether performance regressed.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import time

import numpy as np

SRC = os.environ.get("TENNISLAB_BENCH_SRC") or os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src")
sys.path.insert(0, SRC)

import tennislab.serve as _serve  # noqa: E402
import tennislab.serve.mc as _mc  # noqa: E402
from tennislab.serve.players import get_player  # noqa: E402
from tennislab.serve.setup import seed_impact_params  # noqa: E402

if hasattr(_serve, "window"):
    serve_window = _serve.window
else:  # trees before the workflow refactoring
    from tennislab.serve.window import serve_window


def run_mc(player, alpha, beta, **kw) -> float:
    """P(success) of a Monte Carlo run with whichever API the source tree has (``--against`` old trees)."""
    if hasattr(_serve, "monte_carlo"):
        return _serve.monte_carlo(player, alpha, beta, **kw).p_success
    return _mc.run_mc(player, alpha, beta, **kw)["p_success"]  # trees before the workflow refactoring


PLAYERS = ("professional", "recreational", "junior")


def numpy_seed_window(player, step=1.0, dt=1e-4):
    """The paper's model, vectorised with NumPy: Euler impact (eqs 7-20) + Euler flight (eqs 1-4)."""
    pl = get_player(player)
    p = seed_impact_params()
    m, r, mk, kk, mu = 0.059, 0.033, 0.2, 50e3, 0.35
    inertia = 2 / 3 * m * r * r
    a = np.radians(np.arange(0, 90 + step / 2, step))
    b = np.radians(np.arange(0, 90 + step / 2, step))
    A, B = np.meshgrid(a, b, indexing="ij")
    A, B = A.ravel(), B.ravel()
    A = np.minimum(A, math.radians(89.999))
    vn0 = pl.racket_speed * np.cos(A)
    kb, cb = p.ball_model.spring_damper(vn0, m)
    tc = p.ball_model.contact_time(vn0)
    ct = -2 * m / tc * np.log(np.minimum(1.04 * p.ball_model.cor(vn0), 0.99))
    kt = 0.5 * kb
    n = A.size
    x1, x2, x3 = np.zeros(n), np.zeros(n), np.zeros(n)
    v1, v2 = vn0.copy(), np.zeros(n)
    y, w1, w2, w3 = np.zeros(n), pl.racket_speed * np.sin(A), np.zeros(n), np.zeros(n)
    active = np.ones(n, bool)
    for _ in range(2000):
        fn = kk * (x1 - x3)
        x3d = v2 + (kk * (x1 - x3) - kb * (x3 - x2)) / cb
        slip = w1 - w2 - r * w3
        ft = np.clip(kt * y + ct * slip, -mu * np.maximum(fn, 0), mu * np.maximum(fn, 0))
        s = active.astype(float)
        x1 += s * dt * v1
        x2 += s * dt * v2
        x3 += s * dt * x3d
        v1 -= s * dt * fn / mk
        v2 += s * dt * fn / m
        y += s * dt * slip
        w1 -= s * dt * ft / mk
        w2 += s * dt * ft / m
        w3 += s * dt * r * ft / inertia
        active &= ~((kk * (x1 - x3) <= 0) & (v2 > 0))
        if not active.any():
            break
    vx = v2 * np.cos(B) + w2 * np.sin(B)
    vz = -v2 * np.sin(B) + w2 * np.cos(B)
    # flight: Euler, Stepanek C_D, C_L, Magnus along omega x v (spin about +y)
    k = 0.5 * 1.22 * math.pi * r * r / m
    x, z = np.full(n, -11.885), np.full(n, pl.impact_height)
    net_z = np.full(n, np.nan)
    land_x = np.full(n, np.nan)
    fly = np.ones(n, bool)
    for _ in range(40000):
        v = np.hypot(vx, vz)
        S = np.maximum(r * np.abs(w3), 1e-9) / v
        cd = 0.55 + 1.0 / (22.5 + 4.2 * S**-2.5) ** 0.4
        cl = 1.0 / (2.0 + 1.0 / S)
        ax = -k * v * (cd * vx - cl * np.sign(w3) * (-vz))
        az = -9.82 - k * v * (cd * vz - cl * np.sign(w3) * vx)
        xn = x + dt * vx
        crossed = fly & (x < 0) & (xn >= 0)
        net_z[crossed] = z[crossed]
        x = np.where(fly, xn, x)
        z = np.where(fly, z + dt * vz, z)
        vx = np.where(fly, vx + dt * ax, vx)
        vz = np.where(fly, vz + dt * az, vz)
        landed = fly & (z <= r)
        land_x[landed] = x[landed]
        fly &= ~landed
        if not fly.any():
            break
    X = land_x + 11.885
    return (net_z > 0.943) & (X <= 18.318) & (land_x > 0)


def best_of(fn, repeat=3):
    ts = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t)
    return min(ts)


def _rss_mb() -> float:
    """Current resident set size [MB] (Linux /proc; NaN elsewhere)."""
    try:
        with open("/proc/self/status") as fh:
            return next(int(l.split()[1]) for l in fh if l.startswith("VmRSS:")) / 1024
    except (OSError, StopIteration):
        return float("nan")


def _mem_child(n: int) -> None:
    import resource

    run_mc("pro", 40, 19, n=1000, seed=0)  # imports, compilation, caches
    base = _rss_mb()
    t = time.perf_counter()
    p = run_mc("pro", 40, 19, n=n, seed=0)
    dt = time.perf_counter() - t
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # kB on Linux
    print(f"{n} {dt:.1f} {base:.0f} {peak:.0f} {p:.5f}")


def _time_child(n_mc: int) -> None:
    """Warm windows (best of 3) and one Monte Carlo run of n_mc serves: prints the two times [s]."""
    for p in PLAYERS:
        serve_window(p, step=10)
    t_win = best_of(lambda: [serve_window(p) for p in PLAYERS])
    run_mc("pro", 40, 19, n=1000, seed=0)
    t = time.perf_counter()
    run_mc("pro", 40, 19, n=n_mc, seed=0)
    print(f"{t_win:.4f} {time.perf_counter() - t:.3f}")


def against(old_src: str, n_mc: int) -> None:
    """This tree vs ``old_src``: alternating fresh processes, three rounds, best times, ratio new / old."""
    trees = {"new": os.path.abspath(SRC), "old": os.path.abspath(old_src)}
    best = {k: [math.inf, math.inf] for k in trees}
    for _ in range(3):
        for k, src in trees.items():
            env = dict(os.environ, TENNISLAB_BENCH_SRC=src)
            out = subprocess.run(
                [sys.executable, os.path.abspath(__file__), "--time-child", str(n_mc)],
                capture_output=True,
                text=True,
                check=True,
                env=env,
            ).stdout.split()
            best[k] = [min(b, float(v)) for b, v in zip(best[k], out[-2:])]
    for i, task in enumerate(("three 91 x 91 windows", f"Monte Carlo {n_mc:.0e} serves")):
        n, o = best["new"][i], best["old"][i]
        print(f"{task}: new {n:.3f} s, old {o:.3f} s, ratio new/old {n / o:.2f}")


def memory(ns) -> None:
    """Peak RSS of the Monte Carlo for each n, each in a fresh process."""
    print("Monte Carlo memory (fresh process per N; RSS after warm-up -> peak RSS):")
    for n in ns:
        out = subprocess.run(
            [sys.executable, __file__, "--mem-child", str(n)], capture_output=True, text=True, check=True
        ).stdout.split()
        n_, dt, base, peak, p = out[-5:]
        print(
            f"  N = {int(n_):.0e}: {float(dt):7.1f} s, RSS {base} MB -> peak {peak} MB "
            f"(+{int(peak) - int(base)} MB), P(success) = {p}"
        )


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="baseline on one player only (x3 extrapolated)")
    ap.add_argument("--mc", type=int, default=1_000_000, help="Monte Carlo serves (default 10^6)")
    ap.add_argument("--mem", metavar="N1,N2", help="only the memory check: peak RSS per N (e.g. 1e6,1e7)")
    ap.add_argument("--against", metavar="OLD_SRC", help="ratio against another source tree (see the docstring)")
    ap.add_argument("--mem-child", type=int, help=argparse.SUPPRESS)
    ap.add_argument("--time-child", type=int, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.mem_child:
        _mem_child(args.mem_child)
        return 0
    if args.time_child:
        _time_child(args.time_child)
        return 0
    if args.against:
        against(args.against, args.mc)
        return 0
    if args.mem:
        memory([int(float(v)) for v in args.mem.split(",")])
        return 0

    for p in PLAYERS:  # warm-up (compile / load caches)
        serve_window(p, step=10)
    t_win = best_of(lambda: [serve_window(p) for p in PLAYERS])
    print(f"serve window 91 x 91, three players (warm, best of 3): {t_win:.3f} s  (target < 0.5 s)")

    players = PLAYERS[:1] if args.quick else PLAYERS
    t = time.perf_counter()
    with np.errstate(all="ignore"):  # the seed's Euler step overflows for a few grazing impacts
        n_ok = sum(int(numpy_seed_window(p).sum()) for p in players)
    t_base = (time.perf_counter() - t) * (3 if args.quick else 1)
    print(
        f"NumPy baseline (seed's Euler model, vectorised){' x3 extrapolated' if args.quick else ''}: "
        f"{t_base:.2f} s  ({n_ok} successes)"
    )
    print(f"ratio baseline / tennislab: {t_base / t_win:.0f}x")

    run_mc("pro", 40, 19, n=1000, seed=0)  # warm-up
    t, c = time.perf_counter(), time.process_time()
    p_ok = run_mc("pro", 40, 19, n=args.mc, seed=0)
    t_mc, c_mc = time.perf_counter() - t, time.process_time() - c
    print(
        f"Monte Carlo {args.mc:.0e} serves: {t_mc:.2f} s wall, {c_mc:.2f} s CPU (target < 5 s for 10^6), "
        f"{args.mc / t_mc:,.0f} serves/s, P(success) = {p_ok:.4f}"
    )
    if hasattr(os, "getloadavg"):
        print(
            f"load average during the run: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores "
            f"(other jobs on a shared machine inflate wall times)"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
