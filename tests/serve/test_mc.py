"""Monte Carlo margin of error: reproducible, consistent with the deterministic serve, chunk-invariant,
bounded memory (per-block statistics)."""

import functools
import math

import numpy as np
import pytest

from tennislab.core.impact import impact_batch
from tennislab.errors import InputError
from tennislab.serve import seed_impact_params
from tennislab.serve.mc import (
    TABLE_STEPS,
    Z_MAX,
    block_size,
    combine_blocks,
    impact_table,
    landing_stats,
    lookup,
    monte_carlo,
    scatter_table,
)
from tennislab.serve.pipeline import flights, make_setup
from tennislab.serve.setup import seed_flight_params
from tennislab.serve.single import simulate


def run_mc(*args, **kw) -> dict:
    """The ``serve-mc --json`` object of a Monte Carlo run."""
    return monte_carlo(*args, **kw).to_dict()


def test_reproducible_and_seeded():
    a = run_mc("pro", 40, 19, n=2000, seed=7)
    b = run_mc("pro", 40, 19, n=2000, seed=7)
    c = run_mc("pro", 40, 19, n=2000, seed=8)
    assert a == b
    assert a["p_success"] != c["p_success"] or a["landing"]["mean"] != c["landing"]["mean"]
    assert 0.0 < a["p_success"] < 1.0


def test_zero_scatter_is_the_nominal_serve():
    for alpha, beta in ((3, 8), (3, 12)):
        nominal = simulate("pro", alpha, beta, advice=False)
        r = run_mc("pro", alpha, beta, n=50, sd_angle=0.0, sd_speed=0.0, sd_height=0.0)
        assert r["p_success"] == (1.0 if nominal.success else 0.0)
        # table impacts at 200 steps and flights at rtol 1e-6: within 0.1 mm of the reference serve (at small
        # alpha the grip kink leaves 1e-4 of the spin at 200 steps per half period: 0.04 mm at alpha 3)
        assert r["landing"]["mean"][0] == pytest.approx(nominal.landing["x"], abs=1e-4)


def test_flat_serve_has_smaller_margin_than_topspin():
    """The paper's discussion: flat serves have a smaller margin of error than topspin serves."""
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


def test_scatter_table_covers_every_draw_and_interpolates():
    """The table spans nominal +- Z_MAX sd (Box-Muller bound of tennislab.batch.rng); on the 81 x 161 grid
    the interpolation stays < 0.1 % in spin and < 1e-5 in the normal speed over draws of sd 1 m/s, 1 deg."""
    from tennislab.batch import rng

    assert Z_MAX == pytest.approx(8.652, abs=1e-3)
    z = rng.normal(1, np.arange(10**6), stream=0)
    assert np.abs(z).max() < Z_MAX
    setup = make_setup("pro", flight=seed_flight_params(), steps=TABLE_STEPS)
    p = setup.impact_params
    for alpha in (4.0, 40.0):
        t = scatter_table(setup, alpha, 1.0, 1.0)
        assert t["V"][0] == pytest.approx(40 - Z_MAX) and t["A"][-1] == pytest.approx(math.radians(alpha + Z_MAX))
        g = np.random.default_rng(4)
        V, A = 40 + g.standard_normal(300), np.radians(alpha + g.standard_normal(300))
        ref = impact_batch(V, A, p, steps=200)
        got = lookup(t, V, A)
        assert np.max(np.abs(got["omega"] / ref["omega"] - 1)) < 1e-3
        assert np.max(np.abs(got["v_n"] / ref["v_n"] - 1)) < 1e-5


def test_chunk_size_and_mapper_do_not_change_results():
    batch = pytest.importorskip("tennislab.batch")
    n = 2500
    assert block_size(n) == 1024  # three blocks, the last one partial
    a = run_mc("rec", 40, 15, n=n, seed=3)
    for cs in (1, 2, 5):
        b = run_mc(
            "rec",
            40,
            15,
            n=n,
            seed=3,
            mapper=functools.partial(batch.map_chunks, scheduler="local", chunk_size=cs, progress=False),
        )
        assert a == b

    def one_by_one(fn, source):  # every block in its own call, in reverse order
        parts = [fn(source.chunk(i, 1)) for i in reversed(range(source.n_rows))][::-1]
        return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}

    assert run_mc("rec", 40, 15, n=n, seed=3, mapper=one_by_one) == a


def test_processes_scheduler_is_bit_identical():
    batch = pytest.importorskip("tennislab.batch")
    pytest.importorskip("distributed")
    a = run_mc("junior", 45, 10, n=2100, seed=5)
    b = run_mc(
        "junior",
        45,
        10,
        n=2100,
        seed=5,
        mapper=functools.partial(batch.map_chunks, scheduler="processes", n_workers=1, chunk_size=1, progress=False),
    )
    assert a == b


def test_statistics_equal_numpy_on_the_samples():
    """Per-block statistics merged in block order = numpy on all the serves (small n, samples collected)."""
    res = monte_carlo("pro", 40, 19, n=3000, seed=11, samples=3000)
    s, r = res.samples, res.to_dict()
    assert s["land_x"].size == 3000 and r["n_landed"] == int(s["landed"].sum())
    assert r["p_success"] == s["success"].mean()
    lx, ly = s["land_x"][s["landed"]], s["land_y"][s["landed"]]
    assert r["landing"]["mean"] == pytest.approx([lx.mean(), ly.mean()], rel=1e-12, abs=1e-12)
    np.testing.assert_allclose(r["landing"]["cov"], np.cov(np.stack([lx, ly])), rtol=1e-10, atol=1e-14)
    # the samples are the first serves of the same run: a longer run starts with the same serves
    s2 = monte_carlo("pro", 40, 19, n=5000, seed=11, samples=3000).samples
    np.testing.assert_array_equal(s2["land_x"], s["land_x"])
    # to_frame(): one row per kept serve
    rows = res.rows()
    assert len(rows) == 3000 and rows[0]["land_x"] == s["land_x"][0]
    with pytest.raises(InputError, match="samples"):
        monte_carlo("pro", 40, 19, n=100).rows()


def test_combine_blocks_is_exact_merge():
    g = np.random.default_rng(2)
    x, y = 5 + g.standard_normal(1000), 0.3 * g.standard_normal(1000) + 0.1 * g.standard_normal(1000)
    cuts = [0, 1, 300, 301, 1000]
    st = {
        k: [] for k in ("n", "n_success", "n_landed", "mean_x", "mean_y", "mean_landing_x", "m2_xx", "m2_xy", "m2_yy")
    }
    for lo, hi in zip(cuts[:-1], cuts[1:]):
        bx, by = x[lo:hi], y[lo:hi]
        dx, dy = bx - bx.mean(), by - by.mean()
        for k, v in (
            ("n", hi - lo),
            ("n_success", hi - lo),
            ("n_landed", hi - lo),
            ("mean_x", bx.mean()),
            ("mean_y", by.mean()),
            ("mean_landing_x", bx.mean() + 11.885),
            ("m2_xx", dx @ dx),
            ("m2_xy", dx @ dy),
            ("m2_yy", dy @ dy),
        ):
            st[k].append(v)
    tot = combine_blocks({k: np.array(v) for k, v in st.items()})
    assert tot["mean"] == pytest.approx([x.mean(), y.mean()], rel=1e-13)
    np.testing.assert_allclose(np.array(tot["m2"]) / 999, np.cov(np.stack([x, y])), rtol=1e-12)


def test_p_success_agrees_with_an_independent_generator():
    """The counter-based draws vs numpy's default_rng through the same impact table and flights:
    P(success) within 4 binomial standard errors (n = 20000 each), mean landing x within 4 se."""
    n = 20000
    r = run_mc("pro", 4, 9, n=n, seed=0)
    setup = make_setup("pro", steps=TABLE_STEPS)  # the workflows' default physics, as run_mc's
    t = scatter_table(setup, 4, 1.0, 1.0)
    g = np.random.default_rng(12345)
    a = np.radians(4 + g.standard_normal(n))
    b = np.radians(9 + g.standard_normal(n))
    psi = np.radians(g.standard_normal(n))
    V = 40 + g.standard_normal(n)
    ref = flights({**lookup(t, V, a), "beta": b, "azimuth": psi}, setup=setup)
    p_ref = float(ref["success"].mean())
    se = math.sqrt(2 * p_ref * (1 - p_ref) / n)
    assert 0.2 < p_ref < 0.8 and abs(r["p_success"] - p_ref) < 4 * se
    lx = ref["land_x"][ref["landed"]]
    assert abs(r["landing"]["mean"][0] - lx.mean()) < 4 * math.sqrt(2 * lx.var() / lx.size)
    assert r["landing"]["cov"][0][0] == pytest.approx(lx.var(), rel=0.08)


def test_flights_take_states_or_racket_rows():
    """Stages 2-4 of the pipeline on given states, and on racket-frame rows that launch the same states."""
    setup = make_setup("pro", flight=seed_flight_params())
    inputs = {"v_n": np.array([50.0, 55, 30]), "v_t": np.array([5.0, 6, 1]), "omega": np.full(3, 100.0)}
    out = flights({**inputs, "beta": np.zeros(3)}, setup=setup)
    states = np.zeros((3, 9))
    states[:, 0], states[:, 2] = -11.885, 3.0
    states[:, 3], states[:, 5], states[:, 7] = inputs["v_n"], inputs["v_t"], 100.0  # beta 0: v_n along x, v_t up
    direct = flights({"state": states}, setup=setup)
    assert set(out) >= {"land_x", "land_y", "success", "net_height", "landing_x", "reason", "landed"}
    assert all(len(v) == 3 for v in out.values())
    np.testing.assert_allclose(out["land_x"], direct["land_x"], rtol=1e-12)


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
    with pytest.raises(InputError, match="impact_angle"):
        run_mc("pro", 95, 10, n=10)
    with pytest.raises(InputError, match="target"):
        run_mc("pro", 10, 10, n=10, target="middle")
