"""Calibration and validation against real balls (issue 13, section 3).

Workflows (plain parameters in, a frozen :class:`~tennislab.results.Result` out):

* :func:`validate_serves` - measured serves (Hawk-Eye CourtVision) flown from impact with their
  speed and spin through their net point by every aero model; bounce misses by model, serve type,
  tour and tournament (:class:`ValidationResult`).
* :func:`calibrate_serves` - the aero coefficients (drag, lift against the spin ratio) fitted to
  the serves of one part of a split, reported on the held-out part; the model as an aero table
  (:class:`CalibrationResult`).
* :func:`sensitivity_serves` - the misses over a grid of coefficients and spin-axis assumptions
  (:class:`SensitivityResult`).
* :func:`calibrate_tracks` - a ball's aerodynamic curves (C_D against speed and spin, C_L against
  the spin parameter, spin decay) identified from timed tracks and tracker points, with every flight's
  launch state and spin, reported on held-out flights (:class:`TrackCalibrationResult`); or the
  family's coefficients on tracks of a known spin.
* :func:`calibrate_surface` - the court's restitution and friction fitted to measured bounces
  (:class:`SurfaceCalibrationResult`; its surface file is what ``--surface FILE.toml`` reads).

:func:`synthetic_serves` draws serves flown by a known model (for tests and examples).

The study and its numbers: docs/validation.md.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from tennislab._lazy import attach_stub

if TYPE_CHECKING:
    from tennislab.calibrate.calibration import (
        CalibrationResult,
        SensitivityResult,
        calibrate_serves,
        sensitivity_serves,
    )
    from tennislab.calibrate.family import aero_table_csv, family_coefficients, family_model, family_table
    from tennislab.calibrate.flights import Flight, flights_from_points, flights_from_tracks
    from tennislab.calibrate.identify import Curves
    from tennislab.calibrate.predict import Prediction, SpinAxis, predict_bounces
    from tennislab.calibrate.serves import (
        FAMILIES,
        REASONS,
        Serves,
        check_serves,
        load_serves,
        serves_from_columns,
        split_serves,
    )
    from tennislab.calibrate.surface import SurfaceCalibrationResult, calibrate_surface, measured_bounces
    from tennislab.calibrate.synth import serves_csv, synthetic_serves
    from tennislab.calibrate.tracks import TrackCalibrationResult, calibrate_tracks
    from tennislab.calibrate.validate import ModelValidation, ValidationResult, registered_models, validate_serves

__all__ = [
    "FAMILIES",
    "REASONS",
    "CalibrationResult",
    "Curves",
    "Flight",
    "ModelValidation",
    "Prediction",
    "SensitivityResult",
    "SurfaceCalibrationResult",
    "Serves",
    "SpinAxis",
    "TrackCalibrationResult",
    "ValidationResult",
    "aero_table_csv",
    "calibrate_serves",
    "calibrate_surface",
    "measured_bounces",
    "calibrate_tracks",
    "check_serves",
    "family_coefficients",
    "family_model",
    "family_table",
    "flights_from_points",
    "flights_from_tracks",
    "load_serves",
    "predict_bounces",
    "registered_models",
    "sensitivity_serves",
    "serves_csv",
    "serves_from_columns",
    "split_serves",
    "synthetic_serves",
    "validate_serves",
]
__getattr__, __dir__ = attach_stub(__name__, __file__)
