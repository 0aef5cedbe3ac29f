"""Report section: the flight engine's registered aero models on the same shots.

Every flight is the flight use case :func:`tennislab.trajectory.fly` (the one behind ``tennislab fly``
and the app's Flight page), so the numbers here are the ones those give for the same launch.
"""

from __future__ import annotations

from collections import Counter

import tennislab.report.html as H
from tennislab.core.aero import DEFAULT_AERO
from tennislab.core.court import ITF_COURT
from tennislab.core.flight import FlightParams
from tennislab.plot import plot_trajectories
from tennislab.trajectory import FlightResult, fly

#: (label, position [m], launch keywords of :func:`tennislab.trajectory.fly`, the court area it is meant for)
SHOTS: list[tuple[str, tuple[float, float, float], dict, str]] = [
    (
        "topspin groundstroke 100 km/h, 2500 rpm",
        (-11.885, 0.0, 1.0),
        {"velocity": (27.0, 0.0, 7.0), "spin_rpm": 2500.0, "spin_axis": "topspin"},
        "singles",
    ),
    ("flat serve 180 km/h (to the ad box)", (-11.885, 0.5, 2.8), {"velocity": (49.5, -1.5, -4.5)}, "ad-box"),
]
#: the default model first (:data:`tennislab.core.aero.DEFAULT_AERO`), then the seeds' and the others
MODELS = [DEFAULT_AERO] + [m for m in ("stepanek1988", "cross2014", "launcher2015", "constant") if m != DEFAULT_AERO]

HEADER = [
    "shot",
    "aero model",
    "lands",
    "speed [km/h]",
    "landing x [m]",
    "landing y [m]",
    "apex [m]",
    "net",
    "net clearance [m]",
    "flight time [s]",
]


def lands(d: dict, target: str) -> str:
    """Where a flight (``FlightResult.to_dict()``) ends against the area it is meant for: ``net``, or
    :meth:`~tennislab.core.court.Court.judge` of its landing (in, long, wide, short), with the area."""
    if d["net_contact"] is not None or d["net"]["result"] == "net":
        return "net"
    land = d["landing"]
    if land is None:
        return "–"
    return ITF_COURT.judge(target, land["x"], land["y"])


def _row(label: str, model: str, res: FlightResult, target: str) -> list:
    d = res.to_dict()
    land, net = d["landing"], d["net"]
    return [
        label,
        model,
        lands(d, target),
        H.num(d["launch"]["speed_kmh"], 0),
        H.num(land["x"], 2),
        H.num(land["y"], 2),
        H.num(d["apex"]["z"], 2),
        net["result"],
        H.num(net["clearance"], 3),
        H.num(land["t"], 3),
    ]


def flight(ctx) -> None:
    """Trajectories of the same launches under each aero model; landing, apex and net table."""
    sec = ctx.section
    rows: list[list] = []
    flights: list[FlightResult] = []
    labels: list[str] = []
    notes: list[str] = []
    for label, position, launch, target in SHOTS:
        for m in MODELS:
            res = fly(position, **launch, params=FlightParams.from_options(aero=m))
            rows.append(_row(label, m, res, target))
            notes.extend(f"{label}, {m}: {c}" for c in res.caveats)
            if label.startswith("topspin"):
                flights.append(res)
                labels.append(m)
    first = SHOTS[0][0]
    fig = plot_trajectories(flights, labels=labels, title=f"{first}: {len(flights)} aero models")
    outcomes = "; ".join(
        f"the {label}: " + ", ".join(f"{k} under {v}" for k, v in Counter(r[2] for r in rows if r[0] == label).items())
        for label, *_ in SHOTS
    )
    sec.add(
        H.para(
            "The same launch flown with each registered aerodynamic model. The default, choppin2018 (drag "
            "coefficient 0.60 of match balls measured on 9,224 Hawk-Eye serves, Choppin et al. 2018), is the "
            "one real tracked balls support (docs/validation.md); Štěpánek (1988) is the model of Grosen, "
            "Kousted & Treichel (2021); Cross & Lindsey (2014) and the launcher model of Wójcicki, Pucilowski & "
            "Kulesza use a lower drag coefficient measured on a launcher. Where the models disagree, the landing "
            "point moves by metres: the choice of model matters more than the integrator."
        ),
        H.figure(ctx.save(fig, "flight_models.png"), f"The {first} under {len(flights)} aero models"),
        H.table(HEADER, rows, left_cols=3),
        H.para(
            "“lands”: where the ball lands against the area the shot is meant for (lines included): the far "
            f"singles court, the serve's ad service box. Of the {len(MODELS)} models: {outcomes}.",
            "note",
        ),
    )
    ctx.caveats(
        [
            "Štěpánek's fit covers 13-27 m/s and 800-3250 rpm; the serve at 50 m/s is an extrapolation of it.",
            "Spin is held constant in flight (spin decay off, the default; --spin-decay sets a rate).",
            *notes,
        ]
    )
