"""Synthetic ball tracks with known truth (tests, benchmarks, examples).

A shot is integrated through its first bounce with the reference integrator
(:func:`tennislab.core.rally.fly_bounces`, DOP853 at rtol 1e-10), sampled at a
tracker's frame rate, and Gaussian noise of ``sigma`` per axis is added.
:func:`shot_library` gives serves, groundstrokes (top- and backspin, side
spin) and lobs landing near lines.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tennislab.core.flight import FlightParams
from tennislab.core.mark import MarkParams
from tennislab.core.rally import Bounce, fly_bounces
from tennislab.units import RPM


@dataclass(frozen=True)
class SyntheticTrack:
    """Times t (N,) [s], noisy positions xyz (N, 3) [m], the true positions and the true bounce."""

    t: np.ndarray
    xyz: np.ndarray
    truth: np.ndarray
    bounce: Bounce
    sigma: float
    name: str = ""


def synthetic_track(
    position,
    velocity,
    spin=(0.0, 0.0, 0.0),
    params: FlightParams | None = None,
    *,
    surface="hard",
    rate: float = 340.0,
    sigma: float = 3e-3,
    t_start: float = 0.0,
    after: float = 0.25,
    seed=None,
    name: str = "",
    mark_params: MarkParams = MarkParams(),
) -> SyntheticTrack:
    """Sample a shot at ``rate`` [Hz] from ``t_start`` [s] to ``after`` [s] past its bounce.

    A random phase of the frame clock is drawn from ``seed`` so that samples do
    not fall on the bounce.  ``sigma`` [m] is the per-axis noise.
    """
    params = params or FlightParams()
    rng = np.random.default_rng(seed)
    rally = fly_bounces(position, velocity, spin, params, surface=surface, bounces=1, mark_params=mark_params)
    if not rally.bounces:
        raise ValueError("synthetic_track: the shot does not land")
    b = rally.bounces[0]
    t_end = b.t + after
    t = t_start + rng.uniform(0, 1.0 / rate) + np.arange(0.0, t_end - t_start, 1.0 / rate)
    t = t[t <= t_end]
    truth = np.empty((t.size, 3))
    seg0 = rally.segments[0]
    tc = mark_params.contact_time
    for i, ti in enumerate(t):
        if ti <= b.t:
            truth[i] = seg0.sol(ti)[:3]
        elif ti >= b.t + tc or len(rally.segments) < 2:
            seg1 = rally.segments[1] if len(rally.segments) > 1 else seg0
            truth[i] = seg1.sol(ti)[:3]
        else:  # during contact: centre moves along the ground, compressed
            f = (ti - b.t) / tc
            truth[i] = (
                b.x + f * b.mark.displacement[0],
                b.y + f * b.mark.displacement[1],
                params.ball.radius - b.mark.compression * np.sin(np.pi * f),
            )
    xyz = truth + rng.normal(0.0, sigma, truth.shape)
    return SyntheticTrack(t, xyz, truth, b, sigma, name)


def shot_library() -> list[dict]:
    """Named shots (position [m], velocity [m/s], spin [rad/s]) from the near half to the far half."""
    shots = []
    for i, (vy, wz) in enumerate([(0.0, 0.0), (-1.2, -150.0), (1.5, 200.0)]):
        shots.append(
            {
                "name": f"flat-serve-{i}",
                "position": (-11.9, 0.4 + 0.3 * i, 2.85),
                "velocity": (52.0 - 3 * i, vy - 0.5, -4.6 + 0.2 * i),
                "spin": (0.0, 60.0, wz),
            }
        )
    shots.append(
        {
            "name": "kick-serve",
            "position": (-11.9, 0.5, 2.75),
            "velocity": (36.0, -1.8, 0.8),
            "spin": (-150.0, 280.0, 120.0),
        }
    )
    shots.append(
        {
            "name": "slice-serve",
            "position": (-11.9, 0.3, 2.8),
            "velocity": (42.0, -2.3, -2.2),
            "spin": (0.0, 100.0, -250.0),
        }
    )
    shots.append(
        {
            "name": "topspin-forehand",
            "position": (-11.0, -2.0, 1.0),
            "velocity": (30.0, 2.0, 6.0),
            "spin": (0.0, 2500 * RPM, 0.0),
        }
    )
    shots.append(
        {
            "name": "flat-drive",
            "position": (-10.5, 1.0, 0.9),
            "velocity": (34.0, -1.0, 4.0),
            "spin": (0.0, 800 * RPM, 0.0),
        }
    )
    shots.append(
        {
            "name": "backhand-slice",
            "position": (-11.5, 2.0, 0.8),
            "velocity": (24.0, -1.0, 5.5),
            "spin": (0.0, -1800 * RPM, 0.0),
        }
    )
    shots.append(
        {"name": "lob", "position": (-10.0, 0.0, 0.7), "velocity": (14.5, 0.5, 11.0), "spin": (0.0, 1500 * RPM, 0.0)}
    )
    shots.append(
        {
            "name": "defensive-lob",
            "position": (-12.5, 3.0, 0.5),
            "velocity": (13.5, -1.0, 13.0),
            "spin": (0.0, -600 * RPM, 0.0),
        }
    )
    shots.append(
        {
            "name": "sidespin-approach",
            "position": (-6.0, 0.0, 0.9),
            "velocity": (22.0, 3.2, 3.5),
            "spin": (0.0, 600 * RPM, 900 * RPM),
        }
    )
    return shots


#: The example serve of the line-call page and the report: hard and flat down the T, landing
#: about 6.6 mm beyond the far service line's outer edge (x = 6.40 m) with the default aero model: a close call.
SAMPLE_SERVE = {"position": (-11.8, 0.4, 2.85), "velocity": (48.0, -0.9, -4.47), "spin": (0.0, 60.0, 0.0)}


def sample_serve(
    seed: int = 7, sigma: float = 3e-3, rate: float = 340.0, params: FlightParams | None = None
) -> SyntheticTrack:
    """The example serve (:data:`SAMPLE_SERVE`) as a tracker near the line sees it: from 0.35 s before
    its bounce to 0.15 s after, at ``rate`` [Hz] with noise ``sigma`` [m]."""
    s = SAMPLE_SERVE
    tr = synthetic_track(
        s["position"], s["velocity"], s["spin"], params, rate=rate, sigma=sigma, seed=seed, after=0.15, name="serve"
    )
    keep = tr.t >= tr.bounce.t - 0.35
    return SyntheticTrack(tr.t[keep], tr.xyz[keep], tr.truth[keep], tr.bounce, sigma, "sample serve")
