"""Line calling on real 50 Hz tracker output: a whole match's calls, checked against the tracker.

Reads Hawk-Eye-style point JSON (default: set 1 of the match in ``../shared/realdata/match50hz-set1``;
give another folder to measure another set), calls every shot with ``call_rally`` on 1 and on 2 worker
processes, and prints (:func:`tennislab.linecall.check_rally`):

* calls per answer and the agreement with the tracker's in/out;
* the bounce against the independent estimate (a quadratic through the last six on-grid samples
  before each bounce event crossing z = 0.033 m: the data's README), median / p90 [mm], serves and
  rally shots; targets: median <= 3 mm, p90 <= 8 mm;
* the coverage of the reported 1-sigma / 2-sigma bounce ellipses (expected 68.3 / 95.4 %);
* the whole-flight fit residual (hit to bounce) [mm];
* the spin: rally shots' fitted rate against the tracker's (median ratio; target within 10 %), serves'
  rank correlation and how many serves' rates the fit tells apart from zero;
* calls per second on 2 workers (target >= 50), the ratio against 1 worker measured in the same run,
  and the CPU time per call (what 2 idle cores give: 2 / CPU s per call), with the machine's load.

    .venv/bin/python benchmarks/bench_realtracks.py [FOLDER] [--json]

(about 1 minute on 2 idle cores for set 1's 284 shots; skipped with a note when the data are absent.)
"""

from __future__ import annotations

import argparse
import glob
import json
import os
import time
from pathlib import Path

from tennislab.io.hawkeye import read_points
from tennislab.linecall import call_rally, check_rally

TARGET_CALLS_PER_S = 50.0


def default_folder() -> Path | None:
    """../shared/realdata/match50hz-set1 beside the project (searched upward), or None."""
    here = Path(__file__).resolve().parent
    for up in (here, *here.parents):
        cand = up / "shared" / "realdata" / "match50hz-set1"
        if cand.is_dir():
            return cand
    return None


def run(folder: Path) -> dict:
    points = [p for f in sorted(glob.glob(str(folder / "*.json"))) for p in read_points(f)]
    call_rally(points[:1])  # compile outside the timing
    c0 = time.process_time()
    t0 = time.perf_counter()
    one = call_rally(points, workers=1)
    wall1 = time.perf_counter() - t0
    cpu1 = time.process_time() - c0
    t0 = time.perf_counter()
    two = call_rally(points, workers=2)
    wall2 = time.perf_counter() - t0
    check = check_rally(two, points).summary
    n = len(two.shots)
    check["speed"] = {
        "shots": n,
        "calls_per_s_1_worker": n / wall1,
        "calls_per_s_2_workers": n / wall2,
        "ratio_2_to_1": wall1 / wall2,
        "cpu_ms_per_call": 1000.0 * cpu1 / max(len(one.shots), 1),
        "calls_per_s_2_idle_cores": 2.0 * len(one.shots) / cpu1,
        "target_calls_per_s": TARGET_CALLS_PER_S,
        "ratio_to_target": (n / wall2) / TARGET_CALLS_PER_S,
        "load_average": os.getloadavg()[0],
    }
    check["same_calls_1_and_2_workers"] = [s["call"] for s in one.shots] == [s["call"] for s in two.shots]
    return check


def _line(label: str, st: dict) -> str:
    if not st["n"]:
        return f"  {label:<7} -"
    return (
        f"  {label:<7} median {st['median']:5.2f} mm  p90 {st['p90']:6.2f} mm  mean {st['mean']:5.2f} mm"
        f"  ({st['n']} shots)"
    )


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder", nargs="?", help="folder of point JSON (default: set 1 of the 50 Hz match)")
    ap.add_argument("--json", action="store_true", help="print the summary as JSON")
    args = ap.parse_args([] if argv is None else argv)
    folder = Path(args.folder) if args.folder else default_folder()
    if folder is None or not folder.is_dir():
        print("bench_realtracks: skipped (no real tracker data: ../shared/realdata/match50hz-set1 is absent)")
        return
    s = run(folder)
    if args.json:
        print(json.dumps(s, indent=1))
        return
    sp, cov, speed = s["spin"], s["coverage"], s["speed"]
    print(f"real tracks: {folder}")
    calls = ", ".join(f"{k} {v}" for k, v in s["calls"].items() if v)
    agree = f"{s['tracker_calls_agree']}/{s['tracker_calls_compared']}"
    print(f"{s['n_shots']} shots: {calls}; agree with the tracker {agree}")
    print("bounce vs the independent estimate (target: median <= 3 mm, p90 <= 8 mm):")
    for label in ("all", "serve", "rally"):
        print(_line(label, s[f"bounce_error_mm_{label}"]))
    print(
        f"bounce sigma coverage: 1-sigma {100 * cov['1sigma']:.1f} % (expected 68.3), "
        f"2-sigma {100 * cov['2sigma']:.1f} % (expected 95.4) over {cov['n']} bounces"
    )
    print("whole-flight fit residual (hit to bounce):")
    for label in ("all", "serve", "rally"):
        print(_line(label, s[f"flight_rms_mm_{label}"]))
    print(
        f"spin: rally shots' fitted rate / tracker's median {sp['rally_median_ratio']:.3f} "
        f"(Spearman {sp['rally_spearman']:.2f}, {sp['rally_n']} shots; target within 10 %); serves: Spearman "
        f"{sp['serve_spearman']:.2f}, median sigma {sp['serve_median_sigma_rpm']:.0f} rpm, "
        f"{sp['serve_told_apart_from_zero']}/{sp['serve_n']} told apart from zero"
    )
    print(
        f"speed: {speed['calls_per_s_2_workers']:.1f} calls/s on 2 workers (ratio to the 50 calls/s target "
        f"{speed['ratio_to_target']:.2f}; {speed['ratio_2_to_1']:.2f}x 1 worker's "
        f"{speed['calls_per_s_1_worker']:.1f}); {speed['cpu_ms_per_call']:.1f} ms CPU per call = "
        f"{speed['calls_per_s_2_idle_cores']:.0f} calls/s on 2 idle cores; load {speed['load_average']:.1f}"
    )
    print(f"same calls on 1 and 2 workers: {s['same_calls_1_and_2_workers']}")


if __name__ == "__main__":
    import sys

    main(sys.argv[1:])
