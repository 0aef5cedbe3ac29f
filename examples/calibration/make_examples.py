"""Write the small synthetic example files of this folder (no real data: see ../shared/realdata/README.md).

    python examples/calibration/make_examples.py

* ``synthetic_serves.csv``: 200 serves in the CourtVision form flown by ``cross2014`` with
  C_D = 0.62, C_L = 0.45 S, the spin axis 60 deg from topspin toward sidespin (curving left);
* ``track_1.csv`` ... ``track_3.csv``: three launcher shots (2,000 rpm topspin, same model),
  sampled at 100 Hz with 3 mm noise.
"""

from pathlib import Path

import numpy as np

from tennislab.calibrate import SpinAxis, serves_csv, synthetic_serves
from tennislab.core.flight import FlightParams, fly_dense
from tennislab.core.launch import launch_spin, launch_velocity
from tennislab.io.track import track_to_csv
from tennislab.units import RPM

HERE = Path(__file__).resolve().parent
TRUTH = FlightParams.from_options(aero="cross2014", cd=0.62, cl=0.45)


def main() -> None:
    s = synthetic_serves(200, TRUTH, SpinAxis.angle(60.0), seed=2026)
    (HERE / "synthetic_serves.csv").write_text(serves_csv(s))
    rng = np.random.default_rng(7)
    for i, (speed, elev) in enumerate(((25.0, 8.0), (32.0, 5.0), (38.0, 3.0)), start=1):
        a, b = np.radians(elev), 0.0
        tr = fly_dense((-12.0, 0.0, 1.0), launch_velocity(speed, a, b), launch_spin(2000 * RPM, a, b, 0.0), TRUTH)
        t = np.arange(0.0, 0.95 * tr.landing.t, 0.01)
        xyz = tr.sol(t).T[:, :3] + rng.normal(0.0, 0.003, (t.size, 3))
        text = track_to_csv(t, xyz, np.full(t.size, 0.003), f"synthetic launcher shot {i}: cross2014 cd 0.62 cl 0.45")
        (HERE / f"track_{i}.csv").write_text(text)


if __name__ == "__main__":
    main()
