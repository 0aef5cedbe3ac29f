"""The command groups as ``tennislab --help`` lists them: each command, the module of this package
that registers it and its one-line help, as plain data.

With this table the top-level parser names every command without importing the modules that build
them (``tennislab --help`` and ``--version`` load no NumPy), and a command line builds only the
group of the command it runs (:func:`tennislab.cli._main.build_parser`).  A module that registers
a command must be listed here, with the help its ``register`` gives: ``tests/test_architecture.py``
checks that the table and the modules agree.
"""

from __future__ import annotations

#: {command: (module of tennislab.cli that registers it, its help)}, in the order of ``tennislab --help``
COMMANDS: dict[str, tuple[str, str]] = {
    "app": ("app", "run the local web app (serve explorer, launcher planner, line-call replay, flight)"),
    "calibrate": ("calibrate", "validate and calibrate the flight model on real balls (CourtVision serves, tracks)"),
    "call": ("call", "bounce point, ball mark and line call from a track, a rally of tracker output or a state"),
    "fly": ("fly", "one flight from a launch: landing, net clearance, apex (and bounces)"),
    "impact": ("impact", "one racket-ball impact: ball speed, spin, contact time"),
    "launcher": (
        "launcher",
        "two-roller ball launcher (Wójcicki, Puciłowski & Kulesza 2010): aim, rollers, power, drills, database",
    ),
    "material": (
        "material",
        "Young's modulus and friction coefficient from test tables (Wójcicki, Puciłowski & Kulesza 2010)",
    ),
    "report": ("report", "write the coach-facing HTML report (serve windows, line call, drill)"),
    "serve": ("serve", "one serve: impact, flight, in or fault and why (Grosen, Kousted & Treichel 2021)"),
    "serve-window": ("serve", "all (alpha, beta) serves of a player: Table 1 of Grosen, Kousted & Treichel 2021"),
    "serve-mc": ("serve", "Monte Carlo margin of error of a serve"),
}
