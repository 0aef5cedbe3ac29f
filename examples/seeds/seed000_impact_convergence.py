"""Convergence of the impact model (seed 000 sec. 2.2) at V = 40 m/s, alpha = 36 deg, as docs/impact.md tables it.

    .venv/bin/python examples/seeds/seed000_impact_convergence.py

The compiled RK4 and the paper's explicit Euler at several fixed steps against SciPy's DOP853 (rtol 1e-11)
on the same right-hand side, with the paper's constants and the default impact model
(:func:`tennislab.serve.setup.seed_impact_params`).
"""

import math

from tennislab.core.impact import impact_reference, impact_single, step_size
from tennislab.serve.setup import seed_impact_params

V, ALPHA = 40.0, math.radians(36.0)
RUNS = (("RK4", "rk4", 8e-5), ("RK4", "rk4", 2e-5), ("RK4 (default)", "rk4", 0.0), ("RK4", "rk4", 5e-6))
RUNS += (("Euler (the paper's)", "euler", 1e-4), ("Euler", "euler", 1e-5), ("Euler", "euler", 1e-6))


def main():
    p = seed_impact_params()
    ref = impact_reference(V, ALPHA, p)
    rpm = ref.omega * 30 / math.pi
    print(f"V = 40 m/s, alpha = 36 deg (default model); reference: {ref.speed:.6f} m/s, {rpm:.3f} rpm,")
    print(f"contact {ref.contact_time * 1e3:.4f} ms.")
    print("\n| scheme | step | speed error | spin error |\n|---|---|---|---|")
    for name, method, dt in RUNS:
        r = impact_single(V, ALPHA, p, method=method, dt=dt)
        h = dt or step_size(p.vectors(V * math.cos(ALPHA))[0], 400)
        ds, dw = (f"{abs(a - b) / b:.1e}".replace("e-0", "e-") for a, b in ((r.speed, ref.speed), (r.omega, ref.omega)))
        bold = "**" if method == "euler" and dt == 1e-4 else ""
        print(f"| {name} | {h * 1e6:.3g} us | {bold}{ds}{bold} | {bold}{dw}{bold} |")


if __name__ == "__main__":
    main()
