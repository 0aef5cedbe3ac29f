"""Monte Carlo margin of error: reproducible, consistent with the deterministic serve, chunk-invariant."""
import math

import numpy as np
import pytest

from tennislab.core.impact import impact_batch
from tennislab.errors import InputError
from tennislab.serve import seed_impact_params
from tennislab.serve.mc import impact_table, landing_stats, run_mc, simulate_chunk
from tennislab.serve.single import simulate_serve


def test_reproducible_and_seeded():
    a = run_mc("pro", 40, 19, n=2000, seed=7)
    b = run_mc("pro", 40, 19, n=2000, seed=7)
    c = run_mc("pro", 40, 19, n=2000, seed=8)
    assert a == b
    assert a["p_success"] != c["p_success"] or a["landing"]["mean"] != c["landing"]["mean"]
    assert 0.0 < a["p_success"] < 1.0


def test_zero_scatter_is_the_nominal_serve():
    for alpha, beta in ((3, 8), (3, 12)):
        nominal = simulate_serve("pro", alpha, beta)
        r = run_mc("pro", alpha, beta, n=50, sd_angle=0.0, sd_speed=0.0, sd_height=0.0)
        assert r["p_success"] == (1.0 if nominal["success"] else 0.0)
        # table impacts at 200 steps and flights at rtol 1e-6: within 0.01 mm of the reference serve
        assert r["landing"]["mean"][0] == pytest.approx(nominal["landing"]["x"], abs=1e-5)


def test_flat_serve_has_smaller_margin_than_topspin():
    """The seed's discussion: flat serves have a smaller margin of error than topspin serves."""
    flat = run_mc("pro", 4, 9, n=3000, seed=1)
    top = run_mc("pro", 40, 19, n=3000, seed=1)
    assert flat["p_success"] < top["p_success"]


def test_impact_table_interpolation_error():
    """Bilinear interpolation on the 41 x 81 (V, alpha) table vs direct impacts: < 0.3 % in spin and
    < 0.01 % in the normal speed over +-3 m/s and +-4 deg (the kink at the roll/slide transition
    is the worst case)."""
    p = seed_impact_params()
    tab = impact_table((37.0, 43.0), (math.radians(36), math.radians(44)), p)
    rng = np.random.default_rng(3)
    V = rng.uniform(37, 43, 300)
    A = np.radians(rng.uniform(36, 44, 300))
    got = tab(V, A)
    ref = impact_batch(V, A, p)
    assert np.max(np.abs(got["omega"] / ref["omega"] - 1)) < 3e-3
    assert np.max(np.abs(got["v_n"] / ref["v_n"] - 1)) < 1e-4


def test_chunking_does_not_change_results():
    def chunked(fn, inputs):
        n = len(next(iter(inputs.values())))
        parts = [fn({k: v[i:i + 333] for k, v in inputs.items()}) for i in range(0, n, 333)]
        return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    a = run_mc("rec", 40, 15, n=1000, seed=3)
    b = run_mc("rec", 40, 15, n=1000, seed=3, mapper=chunked)
    assert a == b


def test_batch_layer_if_present():
    batch = pytest.importorskip("tennislab.batch")
    import functools
    a = run_mc("junior", 45, 10, n=1500, seed=5)
    b = run_mc("junior", 45, 10, n=1500, seed=5,
               mapper=functools.partial(batch.map_chunks, scheduler="local", chunk_size=500, progress=False))
    assert a == b


def test_simulate_chunk_shape():
    inputs = {"x": np.full(3, -11.885), "y": np.zeros(3), "z": np.full(3, 3.0), "vx": np.array([50.0, 55, 30]),
              "vy": np.zeros(3), "vz": np.array([-5.0, -6, -1]), "wx": np.zeros(3), "wy": np.full(3, 100.0),
              "wz": np.zeros(3)}
    out = simulate_chunk(inputs, flight={"mass": 0.059, "radius": 0.033})
    assert set(out) >= {"land_x", "land_y", "success", "net_height", "landing_x"}
    assert all(len(v) == 3 for v in out.values())


def test_landing_stats_ellipse():
    rng = np.random.default_rng(0)
    x = 5 + 2.0 * rng.standard_normal(20000)
    y = 1 + 0.5 * rng.standard_normal(20000)
    s = landing_stats(x, y)
    assert s["mean"] == pytest.approx([5, 1], abs=0.05)
    assert s["ellipse_95"]["semi_axes"] == pytest.approx([2.0 * 2.4477, 0.5 * 2.4477], rel=0.03)
    assert abs(s["ellipse_95"]["angle_deg"]) < 3 and -90 < s["ellipse_95"]["angle_deg"] <= 90


def test_bad_input():
    with pytest.raises(InputError, match="n"):
        run_mc("pro", 10, 10, n=0)
    with pytest.raises(InputError, match="sd_angle"):
        run_mc("pro", 10, 10, n=10, sd_angle=-1)
