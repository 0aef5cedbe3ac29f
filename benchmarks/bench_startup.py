"""Benchmark: start-up of the ``tennislab`` command (target: ``--help`` and ``--version`` under 0.5 s).

Every command used to load pyplot, SciPy and every Numba kernel before parsing its flags
(``tennislab --version``: 3.7-4.7 s and 245 MB).  Now the top-level parser names the commands from a
table (``cli/_commands.py``: ``--help`` and ``--version`` load no NumPy), a command line builds only
the group of the command it runs, a help text lists names kept as plain data (``core.names``: no
aero kernel compiled to show them), and a command without a flight (``launcher rollers``, ``launcher
power``) builds only the ball.

This times whole processes (start-up included): ``--version``, ``--help``, every command's ``--help``,
``launcher rollers`` and ``launcher power`` (and one ``fly`` for scale), each against two baselines
measured in the same run, interleaved run by run so that a loaded machine moves them all alike:
``python -c pass`` (the interpreter) and ``python -c "import numpy"``.  It prints the median wall and
CPU time of each, its CPU time as a multiple of each baseline's, and which of the heavy libraries
(NumPy, SciPy, Numba, Matplotlib, pandas) it imported (read from ``python -X importtime``).

Usage:  python benchmarks/bench_startup.py [--runs 5] [--only TEXT]
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
HEAVY = ("numpy", "scipy", "numba", "matplotlib", "pandas")
BASELINES = {"python -c pass": [PY, "-c", "pass"], "import numpy": [PY, "-c", "import numpy"]}
#: commands that run without a flight (their arguments), and one flight for scale
RUNS = (
    ("launcher", "rollers", "--speed-kmh", "80"),
    ("launcher", "power", "--speed-kmh", "80"),
    ("fly", "--speed-kmh", "120", "--elevation-deg", "6"),
)
ENV = {**os.environ, "MPLBACKEND": "Agg"}


def command_paths() -> list[list[str]]:
    """Every command and sub-command of the full parser (``["launcher", "rollers"]``, ...), in its order."""
    from tennislab.cli import build_parser

    def walk(parser, path):
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for name, sub in dict(action.choices).items():
                    yield path + [name]
                    yield from walk(sub, path + [name])

    return list(walk(build_parser(), []))


def commands() -> dict[str, list[str]]:
    """{label: argv} of every timed command."""
    out = {"--version": ["--version"], "--help": ["--help"]}
    out.update({" ".join(p) + " --help": [*p, "--help"] for p in command_paths()})
    out.update({" ".join(r): list(r) for r in RUNS})
    return {f"tennislab {k}": [PY, "-m", "tennislab", *v] for k, v in out.items()}


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
    ap.add_argument("--runs", type=int, default=5, help="timed runs of each command (default 5)")
    ap.add_argument("--only", metavar="TEXT", help="time only the commands whose label contains TEXT")
    args = ap.parse_args(argv)
    timed = {k: v for k, v in commands().items() if args.only is None or args.only in k}
    every = {**BASELINES, **timed}
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
    print(f"{'command':47s} {'wall s':>7s} {'cpu s':>6s} {'cpu/pass':>8s} {'cpu/numpy':>9s}  imports")
    for name, (w, c) in med.items():
        heavy = ", ".join(heavy_imports(every[name])) if name in timed else ""
        print(f"{name:47s} {w:7.2f} {c:6.2f} {c / base_c:8.1f} {c / np_c:9.2f}  {heavy or '-'}")
    print(f"(baselines in this run: python -c pass {base_w:.2f} s wall, import numpy {np_w:.2f} s wall)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
