"""Fixtures of the launcher tests."""

import importlib

import numpy as np
import pytest


@pytest.fixture
def flown_settings(monkeypatch):
    """Every batch of settings the aim's search flies (``Shooter`` calls), as (n, 6) arrays appended to the
    returned list: height, speed, elevation, heading, spin rate, spin axis."""
    search = importlib.import_module("tennislab.launcher._search")
    flown: list = []
    real = search.Shooter.__call__

    def spy(self, h, v, a, b, w, g, **kw):
        flown.append(np.column_stack(np.broadcast_arrays(h, v, a, b, w, g)).astype(float))
        return real(self, h, v, a, b, w, g, **kw)

    monkeypatch.setattr(search.Shooter, "__call__", spy)
    return flown
