"""Report section: the flight engine's registered aero models on the same shots."""

from __future__ import annotations

import numpy as np

from tennislab.core.aero import get_aero_model
from tennislab.core.flight import FlightParams, fly
from tennislab.report import html as H
from tennislab.units import KMH, RPM

#: (label, position [m], velocity [m/s], spin [rad/s]) - a topspin groundstroke and a kick-free serve
SHOTS = [
    ("topspin groundstroke 100 km/h, 2500 rpm", (-11.885, 0.0, 1.0), (27.0, 0.0, 7.0), (0.0, 2500 * RPM, 0.0)),
    ("flat serve 180 km/h", (-11.885, 0.5, 2.8), (49.5, -1.5, -4.5), (0.0, 0.0, 0.0)),
]
MODELS = ["stepanek1988", "cross2014", "launcher2015", "constant"]


def flight(ctx) -> None:
    """Trajectories of the same launches under each aero model; landing, apex and net table."""
    from tennislab.plot.trajectory import plot_trajectories

    sec = ctx.section
    rows, trs, labels = [], [], []
    for label, p, v, w in SHOTS:
        for m in MODELS:
            params = FlightParams(aero=get_aero_model(m))
            tr = fly(p, v, w, params)
            land = tr.landing
            rows.append(
                [
                    label,
                    m,
                    H.num(np.linalg.norm(v) / KMH, 0),
                    H.num(land.x, 2),
                    H.num(land.y, 2),
                    H.num(tr.apex.z, 2),
                    tr.net.result,
                    H.num(tr.net.clearance, 3),
                    H.num(land.t, 3),
                ]
            )
            if label.startswith("topspin"):
                trs.append(tr)
                labels.append(m)
    fig = plot_trajectories(trs, labels=labels, title="topspin groundstroke, 100 km/h, 2500 rpm: aero models")
    sec.add(
        H.para(
            "The same launch flown with each registered aerodynamic model. Štěpánek (1988) is the "
            "seed-000 model; Cross & Lindsey (2014) and the launcher model (seed 002) use a lower "
            "drag coefficient measured in flight. Where the models disagree, the landing point moves by "
            "metres: the choice of model matters more than the integrator."
        ),
        H.figure(ctx.save(fig, "flight_models.png"), "A topspin groundstroke under four aero models"),
        H.table(
            [
                "shot",
                "aero model",
                "speed [km/h]",
                "landing x [m]",
                "landing y [m]",
                "apex [m]",
                "net",
                "net clearance [m]",
                "flight time [s]",
            ],
            rows,
            left_cols=2,
        ),
    )
