"""The validation study on the real CourtVision serves (skipped when ../shared/realdata is absent).

Numbers: docs/validation.md.  These tests measure the physics against real balls; the synthetic
tests beside them prove the code.
"""

import os
from pathlib import Path

import numpy as np
import pytest

from tennislab.calibrate import calibrate_serves, load_serves, validate_serves


def _realdata() -> Path:
    """The real data (``$TENNISLAB_REALDATA``, set by tests/conftest.py)."""
    return Path(os.environ["TENNISLAB_REALDATA"])


SERVES = _realdata() / "courtvision_serves.csv"
pytestmark = pytest.mark.skipif(not SERVES.is_file(), reason="../shared/realdata is absent")


@pytest.fixture(scope="module")
def serves():
    return load_serves(SERVES)


def test_published_models_with_pure_topspin(serves):
    """Issue 13: the default model, spin as pure topspin, lands 0.50 m short (0.55 m median miss) and
    every model lands ~0.16 m to the right (no sidespin)."""
    r = validate_serves(serves, spin_axis="topspin")
    assert r.n_used > 13000 and set(r.excluded) <= {
        "impact",
        "same_side",
        "net_contact",
        "off_path",
        "below_chord",
        "duplicate",
        "speed",
        "spin",
    }
    by = {m.model: m.overall for m in r.models}
    assert by["stepanek1988"]["length_median_m"] == pytest.approx(-0.50, abs=0.03)
    assert by["stepanek1988"]["miss_median_m"] == pytest.approx(0.55, abs=0.03)
    for o in by.values():
        assert o["width_median_m"] == pytest.approx(-0.165, abs=0.02)


@pytest.mark.slow
def test_calibrated_model_has_no_length_bias_on_held_out_serves(serves):
    """Done-when of issue 13: calibrated on odd matches, the even ones land with |median length| < 5 cm."""
    r = calibrate_serves(serves, split="parity")
    held = r.after["held_out"]
    assert held["n"] > 6000
    assert abs(held["length_median_m"]) < 0.05
    assert held["miss_median_m"] < 0.25
    assert held["miss_median_m"] < r.before["held_out"]["miss_median_m"] + 0.01
    assert np.isfinite(r.sd["cd"]) and r.sd["cd"] > 0
