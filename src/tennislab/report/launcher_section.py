"""Report section: a launcher drill drawn on the court with its settings table.

The drill is the shipped ``baseline_rally`` compiled by the launcher's workflow
(:func:`tennislab.launcher.compile_drill`): the same settings ``tennislab launcher drill
baseline_rally`` prints.
"""

from __future__ import annotations

import numpy as np

from tennislab.launcher import PAPER, compile_drill, launcher_params, load_drill
from tennislab.launcher.aim import solution_dict
from tennislab.launcher.drills import drill_trajectories
from tennislab.report import html as H


def _shots(name: str = "baseline_rally"):
    """A shipped drill compiled by the launcher: (title, distinct shot dicts, summary text)."""
    params = launcher_params()
    drill = load_drill(name)
    comp = compile_drill(drill, params)
    shots = []
    for u, tr in zip(comp.unique, drill_trajectories(comp, params)):
        d = solution_dict(u.solution, drill.spec, params)
        d["trajectory"] = tr
        d["zone"] = u.shot.zone_label()
        d["label"] = f"{u.label} ({u.shot.type})"
        d["ok"] = u.ok
        shots.append(d)
    summary = (
        f"{len(comp.shots)} shots fired in {comp.duration_s:.0f} s from {len(comp.unique)} distinct "
        f"shots; every shot clears the net and lands in its zone: {'yes' if comp.ok else 'NO'}. "
        f"Run it on the machine with: tennislab launcher drill {drill.key}"
    )
    return drill.name, shots, summary


def drill(ctx) -> None:
    import matplotlib.pyplot as plt  # the report's figures: matplotlib is loaded only when a report is built

    from tennislab.plot.court import draw_court_side, draw_court_top, frame_views

    sec = ctx.section
    name, shots, summary = _shots()
    fig, (ax_side, ax_top) = plt.subplots(2, 1, figsize=(10, 8.5), height_ratios=[1, 1.25])
    draw_court_side(ax_side)
    draw_court_top(ax_top)
    drawn = []
    rows = []
    for i, s in enumerate(shots, 1):
        _, ys = s["trajectory"].sample(300)
        (line,) = ax_side.plot(ys[:, 0], ys[:, 2], lw=1.6, label=f"{i}: {s.get('label', 'shot')}")
        ax_top.plot(ys[:, 0], ys[:, 1], lw=1.6, color=line.get_color())
        lx, ly = s["landing"]["x"], s["landing"]["y"]
        ax_top.plot(lx, ly, "o", ms=6, color=line.get_color(), mec="k")
        ax_top.annotate(str(i), (lx, ly), xytext=(5, 5), textcoords="offset points", color="white", fontweight="bold")
        drawn.append(ys[:, 0:3])
        st = s["settings"]
        rows.append(
            [
                i,
                s.get("label", ""),
                s.get("zone", ""),
                f"{H.num(s['target']['x'], 2)}, {H.num(s['target']['y'], 2)}",
                H.num(st["height_m"], 1),
                H.num(st["speed_kmh"], 0),
                H.num(st["elevation_deg"], 0),
                H.num(st["heading_deg"], 0),
                H.num(st["spin_rpm"], 0),
                H.num(st["spin_axis_deg"], 0),
                H.num(s["rollers"]["rpm1"], 0),
                H.num(s["rollers"]["rpm2"], 0),
                f"{H.num(s['landing']['x'], 2)}, {H.num(s['landing']['y'], 2)}",
                H.num(s["miss_mm"], 0),
                H.num(s["net_clearance_m"], 2),
            ]
        )
    frame_views(ax_side, ax_top, np.vstack(drawn), margin=1.0, pad=0.5)
    ax_side.legend(loc="upper right", fontsize=8)
    fig.suptitle(f"launcher drill: {name}")
    sec.add(
        H.para(
            f"Drill \u201c{name}\u201d: {len(shots)} distinct shots compiled to the machine's quantised "
            f"settings (1 km/h, 1 deg, 1 rpm steps; {PAPER}, section 2). Each shot is flown with the "
            "launcher's aero model; the table gives what to dial on the machine and where the ball lands."
        ),
        H.figure(ctx.save(fig, "launcher_drill.png"), f"Drill \u201c{name}\u201d on the court"),
        H.para(summary),
        H.table(
            [
                "#",
                "shot",
                "zone",
                "target x, y [m]",
                "height [m]",
                "speed [km/h]",
                "elevation [deg]",
                "heading [deg]",
                "spin [rpm]",
                "spin axis [deg]",
                "roller 1 [rpm]",
                "roller 2 [rpm]",
                "landing x, y [m]",
                "miss [mm]",
                "net clearance [m]",
            ],
            rows,
            left_cols=3,
        ),
        H.para(
            "Spin axis: 0 = topspin, 180 = backspin (slice), +90 = sidespin curving left. Roller speeds "
            f"from {PAPER}, eqs 14-17 (deformed ball radius in the nip).",
            "note",
        ),
    )
