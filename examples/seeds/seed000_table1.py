"""Seed 000's Table 1 beside tennislab's serve windows under each reading of the paper, as docs/serve.md tables it.

    .venv/bin/python examples/seeds/seed000_table1.py

One table per player (the paper's row from its Table 1 and figs 5-9, then ``tennislab serve-window --json``
with the paper's constants (``--preset seed000``): the default, converged impact model, then each of the
paper's readings changed one at a time, then together), and the counts over the three players.
"""

import contextlib
import io
import json

from tennislab.cli import main as tennislab

RUNS = (  # (label, serve-window flags)
    ("default (converged)", []),
    ("+ damper `ball`", ["--tangential-damping", "ball"]),
    ("+ `seed-clamp`", ["--friction-model", "seed-clamp"]),
    ("+ gap 0.02 m", ["--approach-gap", "0.02"]),
    ("+ Euler 1e-4 s", ["--integrator", "euler", "--dt", "1e-4"]),
    ("`seed-clamp` + gap", ["--friction-model", "seed-clamp", "--approach-gap", "0.02"]),
    ("seed-literal, RK4", ["--impact-scheme", "seed-literal", "--integrator", "rk4"]),
    ("**seed-literal**", ["--impact-scheme", "seed-literal"]),
)
PLAYERS = ("professional", "recreational", "junior")
HEAD = (
    "| run | flat n | flat alpha | flat v | topspin n | topspin alpha | topspin beta | peak rpm | peak alpha "
    "| topspin v max | optimum topspin (alpha, beta) |"
)


def windows(flags: list[str]) -> dict:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        rc = tennislab(["serve-window", "--player", "all", "--preset", "seed000", "--json", "--no-progress", *flags])
    if rc != 0:
        raise SystemExit(f"serve-window {' '.join(flags)} exited {rc}")
    return json.loads(out.getvalue())["players"]


def span(lo_hi, fmt: str) -> str:
    return "-".join(fmt.format(v) for v in lo_hi)


def row(label: str, summary: dict, peak_alpha, optimum: dict) -> str:
    f, t = summary["flat"], summary["topspin"]
    cells = [
        label,
        str(f["n"]),
        span(f["alpha"], "{:.0f}"),
        span(f["speed"], "{:.1f}"),
        str(t["n"]),
        span(t["alpha"], "{:.0f}"),
        span(t["beta"], "{:.0f}"),
        f"{t['spin_rpm'][1]:.0f}",
        f"{peak_alpha:.0f}",
        f"{t['speed'][1]:.1f}",
        f"{optimum['topspin']['alpha']:.0f}, {optimum['topspin']['beta']:.0f}",
    ]
    return "| " + " | ".join(cells) + " |"


def main():
    results = [(label, windows(flags)) for label, flags in RUNS]
    totals = []
    for k, name in enumerate(PLAYERS):
        if k:
            print()
        print(f"**{name}**\n")
        print(HEAD)
        print("|---" * 11 + "|")
        pub = results[0][1][name]["published"]
        print(row("**paper**", pub["summary"], pub["peak_spin_alpha"], pub["optimum"]))
        for label, players in results:
            w = players[name]
            print(row(label, w["summary"], w["peak_spin_alpha"], w["optimum"]))
    print("\n| run | flat n (3 players) | topspin n |\n|---|---|---|")
    pubs = [results[0][1][p]["published"]["summary"] for p in PLAYERS]
    totals.append(("**paper**", pubs))
    totals += [(label, [players[p]["summary"] for p in PLAYERS]) for label, players in results]
    for label, sums in totals:
        print(f"| {label} | {sum(s['flat']['n'] for s in sums)} | {sum(s['topspin']['n'] for s in sums)} |")


if __name__ == "__main__":
    main()
