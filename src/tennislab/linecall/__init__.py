"""Line calling: where did the ball bounce, and was it in?

Workflows (each returns a :class:`~tennislab.results.Result`; ``to_dict()`` is the ``--json`` output):

* :func:`call_track` - one shot's 3-D track: net check, robust fit through the first bounce, the ball
  mark, the call (in / out / net / let / review) with its probability (``tennislab call --track``);
* :func:`call_rally` - every shot of tracker points (Hawk-Eye-style point JSON read by
  :func:`tennislab.io.hawkeye.read_points`), cut hit to hit and called against the right area
  (``tennislab call --rally``);
* :func:`call_state` - a state flown to its landing (``tennislab call --position``);
* :func:`call_detections` - 2-D detections of calibrated cameras, triangulated then called
  (``tennislab call --cameras``);
* :func:`check_rally` - a rally's calls against real tracker output: the bounce against an
  independent estimate (:func:`independent_bounces`), residuals, sigma coverage, spin.

Pieces: :mod:`.model` (compiled track models), :mod:`.fit` (robust fits), :mod:`.free_flight`, :mod:`.net`,
:mod:`.detect` (hits, bounces, noise), :mod:`.decide` (a mark against lines and areas),
:mod:`.cameras`, :mod:`.closed_form` (seed 001), :mod:`.synth` (synthetic tracks and points).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from tennislab._lazy import attach_stub

if TYPE_CHECKING:
    from tennislab.linecall.answer import CALLS, BounceEstimate, TrackCall
    from tennislab.linecall.calls import call_detections, call_state, call_track
    from tennislab.linecall.detect import find_bounces, find_hits
    from tennislab.linecall.rally import RallyCall, call_rally, split_point
    from tennislab.linecall.synth import sample_serve
    from tennislab.linecall.tracker_check import TrackerCheck, check_rally, independent_bounces

__all__ = [
    "BounceEstimate",
    "CALLS",
    "RallyCall",
    "TrackerCheck",
    "TrackCall",
    "call_detections",
    "call_rally",
    "call_state",
    "call_track",
    "check_rally",
    "find_bounces",
    "find_hits",
    "independent_bounces",
    "sample_serve",
    "split_point",
]
__getattr__, __dir__ = attach_stub(__name__, __file__)
