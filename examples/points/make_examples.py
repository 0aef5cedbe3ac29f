"""Regenerate the example point file of this folder (SYNTHETIC tracker output, known truth).

    .venv/bin/python examples/points/make_examples.py

synthetic_points.json   three points in the Hawk-Eye-style point JSON that `tennislab call --rally` reads
                        (50 Hz, 3 mm noise, dropouts, an outlier per point; truth flown with cross2014
                        C_D 0.6, C_L 0.6 S, not tennislab's default model):
                        a rally, a serve that clips the tape (let or fault) and a serve into the net.
                        NOT real data: `match.tournament_id` is "SYNTHETIC".
"""

import json
from pathlib import Path

import numpy as np

from tennislab.linecall.synth_points import sample_point, synthetic_point

HERE = Path(__file__).parent


def main():
    rng = np.random.default_rng(99)
    docs, notes = [], []
    for i, (kind, rally) in enumerate((("normal", 4), ("let", 0), ("net-fault", 0))):
        shots = synthetic_point(rng, server_near=True, deuce=i % 2 == 0, rally_len=rally, kind=kind)
        seq = {"set": 1, "game": 1, "point": i + 1, "serve": 1, "rally": 1}
        doc = sample_point(shots, rng, rate=50.0, sigma=3e-3, sequences=seq, t_offset=100.0 + 30.0 * i)
        doc["match"]["tournament_id"] = "SYNTHETIC"
        doc["_comment"] = (
            "SYNTHETIC example made by examples/points/make_examples.py (tennislab), not real tracker data; "
            "true calls: " + ", ".join(s.call for s in shots)
        )
        docs.append(doc)
        notes.append([s.call for s in shots])
    (HERE / "synthetic_points.json").write_text(json.dumps(docs, indent=1) + "\n")
    print("true calls per point:", notes)


if __name__ == "__main__":
    main()
