"""Report section: a launcher drill drawn on the court with its settings table.

The drill is the shipped ``baseline_rally`` compiled by the launcher's workflow
(:func:`tennislab.launcher.compile_drill`): the same settings ``tennislab launcher drill
baseline_rally`` prints.
"""

from __future__ import annotations

import tennislab.report.html as H
from tennislab.launcher import PAPER, compile_drill, drill_trajectories, launcher_params, load_drill
from tennislab.plot import plot_drill


def _shots(name: str = "baseline_rally"):
    """A shipped drill compiled by the launcher: (drill, compiled drill, trajectories, distinct shot dicts,
    summary text)."""
    params = launcher_params()
    drill = load_drill(name)
    comp = compile_drill(drill, params)
    trs = drill_trajectories(comp, params)
    shots = []
    for u in comp.unique:
        d = u.solution.to_dict(drill.spec, params)
        d["zone"] = u.shot.zone_label()
        d["label"] = f"{u.label} ({u.shot.type})"
        d["lands"] = "in its zone" if u.ok else (u.problem or "misses")
        shots.append(d)
    summary = (
        f"{len(comp.shots)} shots fired in {comp.duration_s:.0f} s from {len(comp.unique)} distinct "
        f"shots; every shot clears the net and lands in its zone: {'yes' if comp.ok else 'NO'}. "
        f"Run it on the machine with: tennislab launcher drill {drill.key}"
    )
    return drill, comp, trs, shots, summary


def drill(ctx) -> None:
    sec = ctx.section
    d, comp, trs, shots, summary = _shots()
    fl = launcher_params().to_dict()
    name = d.name
    fig = plot_drill(comp, trs, title=f"launcher drill: {name}")
    rows = []
    for i, s in enumerate(shots, 1):
        st = s["settings"]
        rows.append(
            [
                i,
                s.get("label", ""),
                s.get("zone", ""),
                s["lands"],
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
    sec.add(
        H.para(
            f"Drill \u201c{name}\u201d: {len(shots)} distinct shots compiled to the machine's quantised "
            f"settings (1 km/h, 1 deg, 1 rpm steps; {PAPER}, section 2). Each shot is flown with every "
            f"command's default physics (preset standard: {fl['aero']} aero, ball {fl['mass'] * 1e3:g} g, "
            f"air {fl['air_density']:g} kg/m³), as tennislab launcher drill {d.key} flies it (--preset seed002: "
            "the paper's aero, launcher2015); the table gives what to dial on the machine and where the ball lands."
        ),
        H.figure(ctx.save(fig, "launcher_drill.png"), f"Drill \u201c{name}\u201d on the court"),
        H.para(summary),
        H.table(
            [
                "#",
                "shot",
                "zone",
                "lands",
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
            left_cols=4,
        ),
        H.para(
            "Spin axis: 0 = topspin, 180 = backspin (slice), +90 = sidespin curving left. Roller speeds "
            f"from {PAPER}, eqs 14-17 (deformed ball radius in the nip).",
            "note",
        ),
    )
