"""Seed 002's "+90 rpm (1.5 % / 1.8 %)": what its eq 24 gives with the ball it prints.

    .venv/bin/python examples/seeds/seed002_eq24.py

Eqs 24-25 raise each roller's speed before the throw by sqrt(1/2 I_p omega^2) with I_p = 2/3 m r^2 (eq 21),
the square root of an energy added to an angular speed. Read as rad/s, with the paper's ball (m = 0.058 kg,
"r = 0,333 m", sec. 3), omega = 2000 rpm and its roller speeds of 5800 and 4800 rpm (the text after eq 17),
it gives the paper's figure; with r = 0.0333 m (the typo corrected) it gives a tenth of it.
"""

import math

M = 0.058  # kg, seed 002 sec. 3
OMEGA = 2000 * math.pi / 30  # rad/s, the ball's 2000 rpm
ROLLERS_RPM = (5800, 4800)  # the paper's omega_1, omega_2 at 200 km/h and 2000 rpm


def main():
    for r in (0.333, 0.0333):
        inertia = 2.0 / 3.0 * M * r**2  # eq 21
        rise = math.sqrt(0.5 * inertia * OMEGA**2) * 30 / math.pi  # eq 24, sqrt(J) read as rad/s, in rpm
        shares = " / ".join(f"{100 * rise / w:.2f} %" for w in ROLLERS_RPM)
        print(
            f"r = {r} m: eq 24 adds {rise:.1f} rpm to each roller ({shares} of {ROLLERS_RPM[0]} / {ROLLERS_RPM[1]} rpm)"
        )


if __name__ == "__main__":
    main()
