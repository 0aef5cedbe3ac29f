"""Regenerate the example tracks of this folder (synthetic, known truth).

    .venv/bin/python examples/tracks/make_examples.py

serve_t_line.csv    flat serve to the far deuce box whose mark reaches 3 mm over the service line (in),
                    340 Hz, sigma 3 mm, with two gross outliers (rows noted in its header)
lob_baseline.csv    topspin lob whose mark misses the far baseline by 4 mm (out)
rig.json + rig_detections.csv   the same serve seen by an 8-camera synthetic rig (0.5 px noise)
"""

from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from tennislab.core.rally import fly_bounces
from tennislab.io.cameras import cameras_to_json, detections_to_csv
from tennislab.io.track import track_to_csv
from tennislab.linecall.cameras import synthetic_detections, synthetic_rig
from tennislab.linecall.decide import call_mark
from tennislab.linecall.synth import synthetic_track
from tennislab.units import RPM

HERE = Path(__file__).parent


def aim(position, velocity, spin, target, want_mm):
    """Scale the speed so that the mark reaches ``want_mm`` into ``target`` (examples near a line)."""

    def f(s):
        b = fly_bounces(position, np.array(velocity) * s, spin, bounces=1).bounces[0]
        return call_mark(b.mark, target=target)["distance_mm"] - want_mm

    s = brentq(f, 0.9, 1.1, xtol=1e-9)
    return tuple(np.array(velocity) * s)


def main():
    sv = ((-11.9, 0.4, 2.85), (49.0, 1.35, -4.2), (0.0, 60.0, 50.0))
    v = aim(*sv, "deuce-box", 3.0)
    serve = synthetic_track(sv[0], v, sv[2], seed=1, name="serve")
    xyz = serve.xyz.copy()
    bad = [40, 120]
    xyz[bad[0]] += (0.0, 0.0, 0.25)
    xyz[bad[1]] += (0.3, -0.2, 0.0)
    b = serve.bounce
    note = (
        f"synthetic flat serve, 340 Hz, sigma 3 mm, outliers at data rows {bad}\n"
        f"true first contact x = {b.x:.5f} m, y = {b.y:.5f} m, t = {b.t:.5f} s"
    )
    (HERE / "serve_t_line.csv").write_text(track_to_csv(serve.t, xyz, None, note))
    lb = ((-10.0, 0.0, 0.7), (15.1, 0.4, 11.0), (0.0, 1500 * RPM, 0.0))
    v = aim(*lb, "singles", -4.0)
    lob = synthetic_track(lb[0], v, lb[2], seed=2, name="lob")
    b = lob.bounce
    note = (
        f"synthetic topspin lob, 340 Hz, sigma 3 mm\n"
        f"true first contact x = {b.x:.5f} m, y = {b.y:.5f} m, t = {b.t:.5f} s"
    )
    (HERE / "lob_baseline.csv").write_text(track_to_csv(lob.t, lob.xyz, np.full(lob.t.size, 3e-3), note))
    cams = synthetic_rig(8)
    det = synthetic_detections(cams, serve.t, serve.truth, 0.5, seed=3)
    (HERE / "rig.json").write_text(cameras_to_json(cams))
    (HERE / "rig_detections.csv").write_text(detections_to_csv(det, cams))


if __name__ == "__main__":
    main()
