"""Benchmark: start-up of the ``tennislab`` command (target: ``--help`` and ``--version`` under 0.5 s).

Every command used to load pyplot, SciPy and every Numba kernel before parsing its flags
(``tennislab --version``: 3.7-4.7 s and 245 MB).  Now building the parser loads no physics: each
command imports what it uses when it runs.  This times whole processes (start-up included), each
command against two baselines measured in the same run, interleaved run by run so that a loaded
machine moves both: ``python -c pass`` (the interpreter) and ``python -c "import numpy"`` (the one
library the parser's modules load).  It prints the median CPU and wall time of each and their ratios,
and which of the heavy libraries (SciPy, Numba, Matplotlib, pandas) each command loaded
(``-X importtime``): ``--help`` and ``--version`` load none, ``fly`` no Matplotlib, SciPy-free
commands no SciPy.

Usage:  python benchmarks/bench_startup.py [--runs 7]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import time

PY = sys.executable
HEAVY = ("scipy", "numba", "matplotlib", "pandas")
BASELINES = {"python -c pass": [PY, "-c", "pass"], "import numpy": [PY, "-c", "import numpy"]}
COMMANDS = {
    "tennislab --version": [PY, "-m", "tennislab", "--version"],
    "tennislab --help": [PY, "-m", "tennislab", "--help"],
    "tennislab fly --help": [PY, "-m", "tennislab", "fly", "--help"],
    "tennislab launcher rollers": [PY, "-m", "tennislab", "launcher", "rollers", "--speed-kmh", "80"],
    "tennislab fly": [PY, "-m", "tennislab", "fly", "--speed-kmh", "120", "--elevation-deg", "6"],
}
ENV = {**os.environ, "MPLBACKEND": "Agg"}


def _run(cmd: list[str]) -> tuple[float, float]:
    """(wall [s], cpu [s]) of one run of ``cmd`` (its children's user + system time)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=ENV)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def heavy_imports(cmd: list[str]) -> list[str]:
    """The heavy libraries ``cmd`` imports (read from ``python -X importtime``)."""
    out = subprocess.run([cmd[0], "-X", "importtime", *cmd[1:]], capture_output=True, text=True, env=ENV)
    names = {line.rsplit("|", 1)[-1].strip().split(".")[0] for line in out.stderr.splitlines() if "|" in line}
    return [h for h in HEAVY if h in names]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=7)
    args = ap.parse_args(argv)
    every = {**BASELINES, **COMMANDS}
    for cmd in every.values():  # warm the file cache and Numba's on-disk cache
        _run(cmd)
    times: dict[str, list[tuple[float, float]]] = {k: [] for k in every}
    for _ in range(args.runs):  # interleaved: a drift in the machine's load moves every command alike
        for name, cmd in every.items():
            times[name].append(_run(cmd))
    med = {k: (statistics.median(w for w, _ in v), statistics.median(c for _, c in v)) for k, v in times.items()}
    base_w, base_c = med["python -c pass"]
    np_w, np_c = med["import numpy"]
    print(f"start-up, median of {args.runs} runs (load average {os.getloadavg()[0]:.1f})")
    print(f"{'command':28s} {'wall s':>8s} {'cpu s':>7s} {'cpu/pass':>9s} {'cpu/numpy':>10s}  heavy imports")
    for name, (w, c) in med.items():
        heavy = ", ".join(heavy_imports(every[name])) if name in COMMANDS else ""
        print(f"{name:28s} {w:8.3f} {c:7.3f} {c / base_c:9.1f} {c / np_c:10.2f}  {heavy or '-'}")
    print(f"(baselines: python -c pass {base_w:.3f} s wall, import numpy {np_w:.3f} s wall)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
