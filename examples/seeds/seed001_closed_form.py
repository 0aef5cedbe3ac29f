"""Seed 001's corrected closed-form drop point against tennislab's numerical flight, as docs/linecall.md tables it.

    .venv/bin/python examples/seeds/seed001_closed_form.py

Shots from the near baseline, 1 m up, toward +x, without spin and with 150 rad/s about the vertical axis
(:func:`tennislab.linecall.closed_form.closed_form_study`, the default physics for both): the error of the
closed form's drop point [m], "no spin / spin", per launch speed and elevation.
"""

from tennislab.linecall.closed_form import closed_form_study

SPEEDS = (10.0, 15.0, 20.0, 30.0, 45.0)
ANGLES = (-6.0, 0.0, 5.0, 15.0, 30.0)


def main():
    rows = closed_form_study(speeds=SPEEDS, angles_deg=ANGLES, spins=(0.0, 150.0))
    err = {(r["speed"], r["angle_deg"], r["spin_z"]): r["error"] for r in rows}
    print(
        "| speed \\ elevation | " + " | ".join(f"{a:+.0f}°".replace("+0", "0").replace("-", "−") for a in ANGLES) + " |"
    )
    print("|---|" + "---|" * len(ANGLES))
    for v in SPEEDS:
        cells = [f"{err[(v, a, 0.0)]:.2f} / {err[(v, a, 150.0)]:.2f}" for a in ANGLES]
        print(f"| {v:.0f} m/s | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
