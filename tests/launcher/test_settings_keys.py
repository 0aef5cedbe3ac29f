"""The aim's settings keys (one per combination of the machine's steps, so that no setting is flown twice): an
int64 in mixed radix, or, for a machine of more than 2^62 step combinations, a bytes-like key of the step
indices.  Both must number the same settings alike and give the same aim."""

import importlib

import numpy as np
import pytest

from tennislab.launcher.aim import aim
from tennislab.launcher.machine import DEFAULT_SPEC, MachineSpec, Range

_select = importlib.import_module("tennislab.launcher._select")

#: a machine of about 10^24 step combinations (0.001 deg angles, 0.01 rpm, 0.1 m height)
FINE = MachineSpec(
    speed=Range(30.0, 200.0, 0.01, "km/h"),
    elevation=Range(-20.0, 80.0, 0.001, "deg"),
    heading=Range(-40.0, 40.0, 0.001, "deg"),
    spin=Range(0.0, 2000.0, 0.01, "rpm"),
    spin_axis=Range(-180.0, 180.0, 0.001, "deg"),
)


@pytest.fixture
def force_bytes_keys(monkeypatch):
    """Call it to give every machine the bytes form of the keys (as one of more than 2^62 settings would)."""
    radix = _select._key_radix

    def force():
        monkeypatch.setattr(_select, "_key_radix", lambda spec: radix(spec)[:3] + (False,))

    return force


def _columns(rng, n):
    """n settings on the default machine's steps, with repeats."""
    h = rng.integers(1, 30, n) * 0.1
    v = rng.integers(30, 200, n) * 1.0
    a = rng.integers(-20, 80, n) * 1.0
    b = rng.integers(-40, 40, n) * 1.0
    w = rng.integers(0, 2000, n) * 1.0
    g = rng.integers(-180, 180, n) * 1.0
    cols = np.stack([h, v, a, b, w, g])
    cols[:, n // 2 :] = cols[:, : n - n // 2]  # the second half repeats the first
    return cols


def test_the_default_machine_fits_an_int64_and_a_fine_one_does_not():
    assert _select._key_radix(DEFAULT_SPEC)[3]
    assert not _select._key_radix(FINE)[3]
    cols = _columns(np.random.default_rng(0), 10)
    assert _select.settings_key(DEFAULT_SPEC, *cols).dtype == np.int64
    assert _select.settings_key(FINE, *cols).dtype.kind == "V"


@pytest.mark.parametrize("seed", range(3))
def test_bytes_keys_number_settings_as_the_int64_keys_do(seed):
    """Equal keys exactly for equal step indices, in either form (on the default machine, forced to bytes)."""
    cols = _columns(np.random.default_rng(seed), 400)
    k64 = _select.settings_key(DEFAULT_SPEC, *cols)
    kb = _select.settings_key(FINE, *cols)
    same64 = k64[:, None] == k64[None, :]
    sameb = np.array([[x.tobytes() == y.tobytes() for y in kb] for x in kb])
    np.testing.assert_array_equal(same64, sameb)
    assert same64.sum() > 400  # the repeats are there


def test_bytes_keys_tell_one_step_apart():
    cols = np.array([[1.0, 1.0], [100.0, 100.0], [10.0, 10.0], [5.0, 5.001], [1000.0, 1000.0], [0.0, 0.0]])
    kb = _select.settings_key(FINE, *cols)
    assert kb[0].tobytes() != kb[1].tobytes()
    cols[3, 1] = 5.0
    kb = _select.settings_key(FINE, *cols)
    assert kb[0].tobytes() == kb[1].tobytes()


TARGETS = [(9.0, 2.0), (6.0, -3.0), (11.0, 0.5)]


def _answer(res) -> dict:
    """The aim's JSON without how it got the reach map (its time and source differ from call to call)."""
    out = res.to_dict()
    out.pop("reach_map")
    return out


@pytest.mark.parametrize("target", TARGETS)
def test_the_aim_is_the_same_with_bytes_keys(target, force_bytes_keys):
    """The search on the default machine with its keys forced to the bytes form answers exactly as with int64."""
    want = _answer(aim(target, speed_kmh=100, spin_rpm=1000))
    force_bytes_keys()
    assert _select.settings_key(DEFAULT_SPEC, *_columns(np.random.default_rng(0), 4)).dtype.kind == "V"
    assert _answer(aim(target, speed_kmh=100, spin_rpm=1000)) == want


def test_a_machine_of_more_than_2_62_settings_aims():
    """Fine steps everywhere: the bytes keys carry the search, which lands nearer than on 1-deg steps."""
    fine = aim((9.0, 2.0), speed_kmh=100, spin_rpm=1000, spec=FINE)
    coarse = aim((9.0, 2.0), speed_kmh=100, spin_rpm=1000)
    assert fine.miss_mm < 2.0
    assert fine.miss_mm <= coarse.miss_mm + 0.1


def test_with_bytes_keys_an_aim_flies_no_setting_twice(force_bytes_keys, flown_settings):
    """The bytes keys deduplicate as the int64 keys do: every flight of the search a different launch."""
    force_bytes_keys()
    aim((9.0, 2.0), speed_kmh=70, spin_rpm=0)  # 19 of its ~930 predicted candidates repeat a setting
    every = np.round(np.concatenate(flown_settings), 9)
    assert len(every) > 150
    assert len(np.unique(every, axis=0)) == len(every)


@pytest.mark.parametrize("seed", range(4))
def test_pool_picks_are_the_same_with_bytes_keys(seed, force_bytes_keys):
    """The candidates chosen to fly, when many predicted candidates share a setting: the same in either form."""
    _search = importlib.import_module("tennislab.launcher._search")
    rng = np.random.default_rng(seed)
    n, k = 50, 6
    entries = {
        "row": np.arange(n),
        "height": rng.integers(5, 15, n) * 0.1,
        "speed": rng.integers(99, 102, n) * 1.0,
        "elevation": rng.integers(5, 8, n) * 1.0,
        "heading": rng.integers(-2, 2, n) * 1.0,
        "info": np.zeros((n, 4)),
    }
    W = rng.integers(900, 905, (n, k)) * 1.0  # few rates and axes: many repeated settings
    G = rng.integers(-2, 2, (n, k)) * 1.0
    pr = _search.Predicted(entries, W, G, rng.uniform(0, 1, (n, k)))
    members = rng.uniform(size=(3, n)) < 0.7
    tops = np.array([20, 8, 12], np.int64)
    cols = ("height", "speed", "elevation", "heading", "rate", "axis")
    pick, keys = _select.pool_picks(DEFAULT_SPEC, pr, members, tops, cols)
    assert keys.dtype == np.int64 and len(set(keys.tolist())) == len(keys)
    force_bytes_keys()
    pick_b, keys_b = _select.pool_picks(DEFAULT_SPEC, pr, members, tops, cols)
    assert keys_b.dtype.kind == "V"
    np.testing.assert_array_equal(pick_b, pick)
