"""Line-calling accuracy and speed on synthetic shots with known truth (issue 4).

Shots: serves (flat, slice, kick), groundstrokes (top- and backspin, side
spin) and lobs, each aimed so that its true mark lands a random distance in
[-30, +30] mm from a line (service line or singles sideline for serves,
baseline or sideline for rally balls), integrated with the reference
integrator, sampled at 340 Hz with 3-D noise sigma = 3 mm (and, for the camera
rig, projected into 8 synthetic cameras with 0.5 px noise and triangulated),
then called by the track fit.

Printed: mean and 95th-percentile bounce-point error, the call accuracy for
marks more than 5 mm from the line (target: all correct) and for all, the time
per call, and ratios against baselines measured in the same run:

* accuracy baseline: quadratic extrapolation of the last 0.1 s before the
  lowest point to z = r (what a tracker without a physical model does);
* speed baseline: one reference flight, ``fly`` (SciPy DOP853, rtol 1e-10).

Also printed: the same tracks fitted with a free contact travel
(``contact_prior=0.3 ms``), and fitted as clay (the wrong surface: the truth is
a hard court) with and without it.

Targets (issue 4): mean error < 2 mm at sigma = 3 mm; calls correct whenever
the mark is > 5 mm from the line; a call in < 50 ms.

    .venv/bin/python benchmarks/bench_linecall.py [--n 40] [--seed 1] [--no-cameras]

(about 2-3 minutes for the default 40 shots on 2 busy cores: each shot is aimed by
root-finding, then fitted four times and triangulated once.)
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.optimize import brentq

from tennislab.core.flight import FlightParams, fly
from tennislab.core.mark import ball_mark
from tennislab.core.rally import fly_bounces
from tennislab.linecall.cameras import synthetic_detections, synthetic_rig, triangulate_detections
from tennislab.linecall.decide import call_mark
from tennislab.linecall.fit import fit_track
from tennislab.linecall.synth import synthetic_track
from tennislab.units import RPM

SIGMA = 3e-3


def random_shot(rng):
    """(kind, position, velocity, spin, target, line) of a random shot toward the far half."""
    kind = rng.choice(["serve", "rally", "lob"], p=[0.4, 0.4, 0.2])
    if kind == "serve":
        side = rng.choice([-1.0, 1.0])
        pos = (-11.9, side * rng.uniform(0.2, 1.0), rng.uniform(2.6, 2.95))
        sub = rng.choice(["flat", "slice", "kick"])
        if sub == "flat":
            v = (rng.uniform(45, 58), 0.0, rng.uniform(-5.5, -3.5))
            w = (0.0, rng.uniform(0, 100), rng.uniform(-80, 80))
        elif sub == "slice":
            v = (rng.uniform(38, 46), 0.0, rng.uniform(-3.0, -1.5))
            w = (0.0, rng.uniform(50, 150), -side * rng.uniform(150, 300))
        else:
            v = (rng.uniform(32, 38), 0.0, rng.uniform(0.3, 1.2))
            w = (side * rng.uniform(50, 150), rng.uniform(200, 320), side * rng.uniform(50, 150))
        target = "ad-box" if side > 0 else "deuce-box"  # serve crosses court
        box = {"deuce-box": (0.0, 6.4, -0.025, 4.115), "ad-box": (0.0, 6.4, -4.115, 0.025)}[target]
        line = rng.choice(["service", "side"])
        aim = (6.4 - 0.3, 0.5 * (box[2] + box[3])) if line == "service" else (4.8, box[3] if side < 0 else box[2])
    else:
        pos = (rng.uniform(-12.5, -9.5), rng.uniform(-3, 3), rng.uniform(0.6, 1.1))
        if kind == "rally":
            v = (rng.uniform(24, 36), 0.0, rng.uniform(3.0, 6.5))
            w = (0.0, rng.choice([-1, 1, 1]) * rng.uniform(500, 3000) * RPM, rng.uniform(-600, 600) * RPM)
        else:
            v = (rng.uniform(12, 16), 0.0, rng.uniform(9.5, 13.0))
            w = (0.0, rng.uniform(-800, 2000) * RPM, 0.0)
        target = "singles"
        line = rng.choice(["baseline", "side"])
        ys = rng.choice([-1, 1]) * 4.115
        aim = (11.885 - 0.5, rng.uniform(-3, 3)) if line == "baseline" else (rng.uniform(7, 11), ys)
    # point the horizontal velocity at the aim point
    d = np.array(aim) - np.array(pos[:2])
    sp = np.hypot(v[0], v[1])
    v = (sp * d[0] / np.hypot(*d), sp * d[1] / np.hypot(*d), v[2])
    return kind, pos, v, w, target


def aim_distance(pos, v, w, target, want_mm, params):
    """Scale the speed so that the true mark reaches want_mm into the target (None if impossible)."""

    def dist(s):
        r = fly_bounces(pos, np.array(v) * s, w, params, bounces=1, rtol=1e-9, atol=1e-11)
        if not r.bounces:
            return np.nan
        return call_mark(r.bounces[0].mark, target=target)["distance_mm"] - want_mm

    try:
        lo, hi = 0.85, 1.15
        if not (dist(lo) * dist(hi) < 0):
            return None
        return brentq(dist, lo, hi, xtol=1e-10)
    except (ValueError, RuntimeError):
        return None


def poly_baseline(t, xyz, r):
    """Quadratic extrapolation of the last 0.1 s before the lowest point to z = r."""
    i = int(np.argmin(xyz[:, 2]))
    sel = (t <= t[i]) & (t >= t[i] - 0.1)
    tt = t[sel] - t[i]
    cz = np.polyfit(tt, xyz[sel, 2], 2)
    roots = np.roots(cz - [0, 0, r])
    roots = np.real(roots[np.isreal(roots)])
    tau = roots[np.argmin(np.abs(roots))]
    return np.polyval(np.polyfit(tt, xyz[sel, 0], 2), tau), np.polyval(np.polyfit(tt, xyz[sel, 1], 2), tau)


def run(n: int, seed: int, cameras: bool) -> dict:
    params = FlightParams()
    rng = np.random.default_rng(seed)
    rig = synthetic_rig(8) if cameras else None
    rows = []
    tries = 0
    while len(rows) < n and tries < 6 * n:
        tries += 1
        kind, pos, v, w, target = random_shot(rng)
        want = rng.uniform(-30, 30)
        s = aim_distance(pos, v, w, target, want, params)
        if s is None:
            continue
        v = tuple(np.array(v) * s)
        tr = synthetic_track(pos, v, w, params, seed=int(rng.integers(1 << 30)), sigma=SIGMA)
        true_d = call_mark(tr.bounce.mark, target=target)["distance_mm"]
        row = {"kind": kind, "true_mm": true_d}
        cpu0, t0 = time.process_time(), time.perf_counter()
        f = fit_track(tr.t, tr.xyz, None, params, "hard")
        mk = ball_mark(f.bounce_xy, f.velocity_in, f.velocity_out, f.spin_in, "hard", params.ball)
        dec = call_mark(mk, target=target, bounce_cov=f.bounce_cov)
        row["wall_ms"] = (time.perf_counter() - t0) * 1000
        row["cpu_ms"] = (time.process_time() - cpu0) * 1000
        row["err_mm"] = float(np.hypot(f.p[0] - tr.bounce.x, f.p[1] - tr.bounce.y) * 1000)
        row["correct"] = (dec["call"] == "in") == (true_d >= 0)
        row["p_in"] = dec["p_in"]
        f0 = fit_track(tr.t, tr.xyz, None, params, "hard", contact_prior=0.3e-3)
        row["exact_contact_err_mm"] = float(np.hypot(f0.p[0] - tr.bounce.x, f0.p[1] - tr.bounce.y) * 1000)
        fc_ = fit_track(tr.t, tr.xyz, None, params, "clay")
        row["clay_err_mm"] = float(np.hypot(fc_.p[0] - tr.bounce.x, fc_.p[1] - tr.bounce.y) * 1000)
        f0c = fit_track(tr.t, tr.xyz, None, params, "clay", contact_prior=0.3e-3)
        row["clay_exact_err_mm"] = float(np.hypot(f0c.p[0] - tr.bounce.x, f0c.p[1] - tr.bounce.y) * 1000)
        bx, by = poly_baseline(tr.t, tr.xyz, params.ball.radius)
        row["poly_err_mm"] = float(np.hypot(bx - tr.bounce.x, by - tr.bounce.y) * 1000)
        if rig is not None:
            det = synthetic_detections(rig, tr.t, tr.truth, 0.5, seed=int(rng.integers(1 << 30)))
            tc, xc, sc = triangulate_detections(rig, det)
            fc = fit_track(tc, xc, sc, params, "hard")
            mkc = ball_mark(fc.bounce_xy, fc.velocity_in, fc.velocity_out, fc.spin_in, "hard", params.ball)
            decc = call_mark(mkc, target=target, bounce_cov=fc.bounce_cov)
            row["cam_err_mm"] = float(np.hypot(fc.p[0] - tr.bounce.x, fc.p[1] - tr.bounce.y) * 1000)
            row["cam_correct"] = (decc["call"] == "in") == (true_d >= 0)
        rows.append(row)
    return {"rows": rows, "params": params}


def summarize(res: dict, cameras: bool) -> None:
    rows = res["rows"]
    err = np.array([r["err_mm"] for r in rows])
    perr = np.array([r["poly_err_mm"] for r in rows])
    far = np.array([abs(r["true_mm"]) > 5 for r in rows])
    ok = np.array([r["correct"] for r in rows])
    wall = np.array([r["wall_ms"] for r in rows])
    cpu = np.array([r["cpu_ms"] for r in rows])
    t0 = time.perf_counter()
    for _ in range(20):
        fly((-11.9, 0.4, 2.85), (50, 1, -4.4), (0, 60, 80), res["params"])
    fly_ms = (time.perf_counter() - t0) / 20 * 1000
    kinds = ", ".join(f"{k} {sum(r['kind'] == k for r in rows)}" for k in ("serve", "rally", "lob"))
    print(f"shots: {len(rows)} ({kinds}), 3-D noise sigma = {SIGMA * 1000:.0f} mm at 340 Hz")
    print(
        f"bounce-point error: mean {err.mean():.2f} mm, p95 {np.percentile(err, 95):.2f} mm, max {err.max():.2f} mm "
        f"(target mean < 2 mm)"
    )
    for k in ("serve", "rally", "lob"):
        e = np.array([r["err_mm"] for r in rows if r["kind"] == k])
        if e.size:
            print(f"  {k:6s}: mean {e.mean():.2f} mm, p95 {np.percentile(e, 95):.2f} mm")
    for key, what in (
        ("exact_contact_err_mm", "contact time free (--contact-sigma 0.3)"),
        ("clay_err_mm", "fitted as clay (wrong surface)"),
        ("clay_exact_err_mm", "fitted as clay, contact time free"),
    ):
        e = np.array([r[key] for r in rows])
        print(f"  {what}: mean {e.mean():.2f} mm, p95 {np.percentile(e, 95):.2f} mm, max {e.max():.2f} mm")
    print(
        f"baseline (quadratic extrapolation): mean {perr.mean():.1f} mm, p95 {np.percentile(perr, 95):.1f} mm; "
        f"ratio fit/baseline = {err.mean() / perr.mean():.3f}"
    )
    print(
        f"calls correct, mark > 5 mm from the line: {ok[far].sum()}/{far.sum()} (target: all); "
        f"all marks: {ok.sum()}/{ok.size}"
    )
    print(
        f"time per call: median {np.median(wall):.1f} ms wall, {np.median(cpu):.1f} ms CPU, p95 wall "
        f"{np.percentile(wall, 95):.1f} ms (target < 50 ms); one reference fly(): {fly_ms:.1f} ms; "
        f"ratio call/fly = {np.median(wall) / fly_ms:.2f}"
    )
    if cameras:
        ce = np.array([r["cam_err_mm"] for r in rows])
        cok = np.array([r["cam_correct"] for r in rows])
        print(
            f"camera rig (8 cameras, 0.5 px): mean {ce.mean():.2f} mm, p95 {np.percentile(ce, 95):.2f} mm; "
            f"calls correct > 5 mm: {cok[far].sum()}/{far.sum()}, all: {cok.sum()}/{cok.size}"
        )


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=40)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--no-cameras", action="store_true")
    a = ap.parse_args([] if argv is None else argv)  # run_all.py calls main() with its own argv
    res = run(a.n, a.seed, not a.no_cameras)
    summarize(res, not a.no_cameras)


if __name__ == "__main__":
    import sys

    main(sys.argv[1:])
