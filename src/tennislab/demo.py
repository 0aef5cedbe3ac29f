"""``make demo``: the main job.

Runs ``tennislab report`` when the report module is available (the full
coach-facing report); otherwise a few ``tennislab fly`` examples and a
trajectory figure.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import sys

from tennislab.cli import main as cli_main


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="tennislab.demo")
    ap.add_argument("--out", default="out/demo")
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    if importlib.util.find_spec("tennislab.report.build") is not None:
        return cli_main(["report", "--out", args.out])
    examples = [
        ("flat serve, 50 m/s", ["--position", "-11.885", "0.5", "2.8", "--velocity", "49.5", "-1.5", "-4.5"]),
        (
            "topspin serve, 2500 rpm",
            [
                "--position",
                "-11.885",
                "0.5",
                "2.8",
                "--velocity",
                "38",
                "-1.2",
                "0.5",
                "--spin-rpm",
                "2500",
                "--spin-axis",
                "0",
                "1",
                "0",
            ],
        ),
        (
            "topspin groundstroke",
            [
                "--position",
                "-11.885",
                "0",
                "1.0",
                "--velocity",
                "27",
                "0",
                "7",
                "--spin-rpm",
                "2500",
                "--spin-axis",
                "0",
                "1",
                "0",
            ],
        ),
        (
            "lob",
            [
                "--position",
                "-10",
                "0",
                "0.8",
                "--velocity",
                "14",
                "0",
                "14",
                "--spin-rpm",
                "1000",
                "--spin-axis",
                "0",
                "1",
                "0",
            ],
        ),
    ]
    for name, a in examples:
        print(f"== {name}: tennislab fly {' '.join(a)}")
        rc = cli_main(["fly", *a])
        if rc:
            return rc
    from tennislab.cli import build_parser
    from tennislab.cli.common import save_figure
    from tennislab.cli.fly import spin_from_args
    from tennislab.core.flight import fly
    from tennislab.plot.trajectory import plot_trajectories

    trs = []
    for _name, a in examples:
        ns = build_parser().parse_args(["fly", *a])
        trs.append(fly(ns.position, ns.velocity, spin_from_args(ns)))
    path = os.path.join(args.out, "trajectories.png")
    save_figure(plot_trajectories(trs, labels=[n for n, _ in examples], title="tennislab demo"), path)
    print(f"figure: {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
