"""Print the Markdown tables of docs/validation.md from the JSON files of ``study.sh``.

python examples/calibration/tables.py out/validation
"""

import json
import sys
from pathlib import Path


def cm(x) -> str:
    return "—" if x is None else f"{100 * x:+.1f}"


def m(x) -> str:
    return "—" if x is None else f"{x:.3f}"


def row(label: str, s: dict) -> str:
    if not s or not s.get("n"):
        return f"| {label} | 0 | | | | |"
    return (
        f"| {label} | {s['n']} | {m(s['miss_median_m'])} | {m(s['miss_p90_m'])} | {cm(s['length_median_m'])} | "
        f"{cm(s['width_median_m'])} |"
    )


HEAD = "| | n | median miss [m] | p90 [m] | length bias [cm] | width bias [cm] |\n|---|---|---|---|---|---|"


def main(out: str) -> None:
    d = Path(out)
    print("## Models as published, by spin-axis assumption (all usable serves; fitted: held-out half)\n")
    print(HEAD)
    for ax in ("none", "topspin", "90", "fitted"):
        f = d / f"validate_{ax}.json"
        if not f.exists():
            continue
        v = json.loads(f.read_text())
        for mod in v["models"]:
            s = mod["held_out"] if ax == "fitted" else mod["overall"]
            print(row(f"{mod['model']}, {ax}", s))
    for ax in ("topspin", "fitted"):
        f = d / f"validate_{ax}.json"
        if not f.exists():
            continue
        v = json.loads(f.read_text())
        for grouping in ("serve_type", "tour", "event"):
            print(f"\n### {ax}: by {grouping} (all serves)\n")
            print(HEAD)
            for mod in v["models"]:
                for label, s in mod["groups"][grouping].items():
                    print(row(f"{mod['model']}: {label}", s))
    print("\n## Calibrations (after; fit part / held-out part)\n")
    print("| run | values ± sd | before held-out | after fit | after held-out |")
    print("|---|---|---|---|---|")
    for f in sorted(d.glob("serves_*.json")):
        if f.stat().st_size == 0:  # still being written
            continue
        c = json.loads(f.read_text())
        vals = ", ".join(
            f"{k} {c['values'][k]:.3f}" + (f" ± {c['sd'][k]:.3f}" if k in c["sd"] else "")
            for k in ("cd", "cl", "cd_s", "speed_scale")
        )

        def short(s):
            return f"{m(s['miss_median_m'])} / {m(s['miss_p90_m'])} / {cm(s['length_median_m'])}"

        print(
            f"| {f.stem} | {vals} | {short(c['before']['held_out'])} | {short(c['after']['fit'])} | "
            f"{short(c['after']['held_out'])} |"
        )
    for name in ("sensitivity.json", "sensitivity_speed.json"):
        f = d / name
        if not f.exists():
            continue
        g = json.loads(f.read_text())
        print(f"\n## {name} (held-out part)\n")
        print("| cd | cl | axis | speed × | median miss | p90 | length bias [cm] | width bias [cm] |")
        print("|---|---|---|---|---|---|---|---|")
        for p in g["grid"]:
            s = p["held_out"]
            print(
                f"| {p['cd']:g} | {p['cl']:g} | {p['spin_axis']} | {p['speed_scale']:g} | {m(s['miss_median_m'])} | "
                f"{m(s['miss_p90_m'])} | {cm(s['length_median_m'])} | {cm(s['width_median_m'])} |"
            )


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/validation")
