"""tennislab.batch in process: chunking invariance, resumable Parquet output, manifests, grids, RNG, CLI flags."""

from __future__ import annotations

import argparse
import functools
import io
import os

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from tennislab.batch import (
    GridSpec,
    RowRange,
    StreamSource,
    default_chunk_size,
    map_chunks,
    read_manifest,
    read_output,
    rng,
    run_batch,
)
from tennislab.batch.progress import ProgressBar, progress_enabled
from tennislab.batch.tasks import STATE_KEYS, fly_chunk
from tennislab.cli import add_scheduler_flag, batch_options_from_args
from tennislab.core.flight import FlightParams, fly_batch
from tennislab.errors import InputError

CALLS = []


def serve_states(n: int, seed: int = 1) -> np.ndarray:
    """Serve-like initial states (N, 9): 40-65 m/s, -8..-2 deg, topspin/sidespin up to 3000 rpm."""
    g = np.random.default_rng(seed)
    v = g.uniform(40, 65, n)
    el = np.radians(g.uniform(-8, -2, n))
    az = np.radians(g.uniform(-6, 6, n))
    s = np.zeros((n, 9))
    s[:, 0], s[:, 1], s[:, 2] = -11.885, g.uniform(-1, 1, n), 2.8
    s[:, 3] = v * np.cos(el) * np.cos(az)
    s[:, 4] = v * np.cos(el) * np.sin(az)
    s[:, 5] = v * np.sin(el)
    s[:, 6:9] = g.uniform(-300, 300, (n, 3))
    return s


def affine(chunk):
    CALLS.append(len(chunk["a"]))
    return {"s": chunk["a"] * 2.0 + chunk["b"], "pos": chunk["a"] > 0.5}


def mc(chunk, seed=11):
    """Monte Carlo: perturb each row with per-row draws (independent of chunking)."""
    CALLS.append(len(chunk["row"]))
    return {
        "v": chunk["v0"] + 0.5 * rng.normal(seed, chunk["row"], stream=0),
        "u": rng.uniform(seed, chunk["row"], stream=1),
    }


def flaky(chunk, trigger, bad_row):
    """``affine``, but fails on the chunk holding ``bad_row`` while the file ``trigger`` exists."""
    if os.path.exists(trigger) and chunk["row"][0] <= bad_row <= chunk["row"][-1]:
        raise RuntimeError("worker died")
    return affine(chunk)


@pytest.fixture
def data():
    g = np.random.default_rng(3)
    return {"a": g.random(5000), "b": g.random(5000)}


@pytest.fixture(autouse=True)
def _clear_calls():
    CALLS.clear()


# ------------------------------------------------------------------- results
def test_fly_chunks_bit_identical_to_one_batch():
    s = serve_states(3000)
    params = FlightParams()
    ref = fly_batch(s, params).to_dict()
    for cs in (1000, 777, 3000):
        out = map_chunks(functools.partial(fly_chunk, params=params), {"states": s}, chunk_size=cs, progress=False)
        for k in ("land_x", "land_y", "land_t", "net_z", "apex_z", "status"):
            assert np.array_equal(out[k], ref[k]), (cs, k)
    assert np.isfinite(ref["land_x"]).all()


def test_fly_chunk_accepts_named_state_columns():
    s = serve_states(200)
    cols = {k: s[:, i] for i, k in enumerate(STATE_KEYS)}
    out = map_chunks(fly_chunk, cols, chunk_size=64, progress=False)
    assert np.array_equal(out["land_x"], fly_batch(s)["land_x"])


@settings(max_examples=25, deadline=None)
@given(n=st.integers(1, 400), cs=st.integers(1, 450))
def test_chunking_never_changes_results(n, cs):
    CALLS.clear()  # (the autouse fixture runs once per test, not per example)
    g = np.random.default_rng(n)
    x = {"a": g.random(n), "b": g.random(n), "row": np.arange(n)}
    out = map_chunks(affine, x, chunk_size=cs, progress=False)
    assert np.array_equal(out["s"], x["a"] * 2.0 + x["b"])
    assert np.array_equal(out["pos"], x["a"] > 0.5)
    assert len(CALLS) == -(-n // cs) and sum(CALLS) == n


def test_monte_carlo_independent_of_chunk_size():
    x = {"v0": np.linspace(40, 60, 4001)}
    outs = [map_chunks(mc, x, chunk_size=cs, row_key="row", progress=False) for cs in (4001, 1000, 333)]
    for o in outs[1:]:
        assert np.array_equal(o["v"], outs[0]["v"]) and np.array_equal(o["u"], outs[0]["u"])
    assert not np.array_equal(outs[0]["v"], x["v0"])
    other = map_chunks(functools.partial(mc, seed=12), x, row_key="row", progress=False)
    assert not np.array_equal(other["v"], outs[0]["v"])


def test_include_inputs_and_zero_rows():
    x = {"a": np.arange(5.0), "b": np.ones(5)}
    out = map_chunks(affine, x, include_inputs=True, progress=False)
    assert list(out) == ["a", "b", "s", "pos"] and np.array_equal(out["a"], x["a"])
    empty = map_chunks(affine, {"a": np.zeros(0), "b": np.zeros(0)}, progress=False)
    assert empty["s"].shape == (0,) and empty["pos"].dtype == bool


# ------------------------------------------------------------------- resume
def test_resume_skips_finished_chunks(tmp_path, data):
    out = str(tmp_path / "job")
    first = run_batch(affine, data, chunk_size=700, out=out, progress=False)
    assert (first.n_chunks, first.computed, first.skipped) == (8, 8, 0) and len(CALLS) == 8
    CALLS.clear()
    again = run_batch(affine, data, out=out, progress=False)  # chunk size taken from the manifest
    assert (again.computed, again.skipped, again.chunk_size) == (0, 8, 700) and CALLS == []
    assert np.array_equal(again.data["s"], first.data["s"]) and again.data["pos"].dtype == bool
    os.unlink(os.path.join(out, "part-00003.parquet"))
    os.unlink(os.path.join(out, "part-00007.parquet"))
    CALLS.clear()
    third = run_batch(affine, data, out=out, progress=False)
    assert (third.computed, third.skipped) == (2, 6) and CALLS == [700, 5000 - 7 * 700]
    for k in first.data:
        assert np.array_equal(third.data[k], first.data[k])
    assert np.array_equal(read_output(out)["s"], first.data["s"])


def test_interrupted_run_resumes_to_the_same_result(tmp_path, data):
    x = dict(data, row=np.arange(5000))
    ref = map_chunks(affine, x, progress=False)
    out = str(tmp_path / "job")
    trigger = tmp_path / "fail-now"
    trigger.write_text("")
    job = functools.partial(flaky, trigger=str(trigger), bad_row=2500)
    with pytest.raises(RuntimeError, match="worker died"):
        map_chunks(job, x, chunk_size=1000, out=out, progress=False)
    visible = sorted(n for n in os.listdir(out) if not n.startswith("."))
    assert visible == ["manifest.json", "part-00000.parquet", "part-00001.parquet"]
    assert not read_manifest(out)["complete"]
    with pytest.raises(InputError, match="incomplete"):
        read_output(out)
    trigger.unlink()  # the "crash" is gone; same job, same directory
    CALLS.clear()
    res = run_batch(job, x, out=out, progress=False)
    assert (res.computed, res.skipped) == (3, 2) and CALLS == [1000, 1000, 1000]
    for k in ref:
        assert np.array_equal(res.data[k], ref[k])
    assert read_manifest(out)["complete"]


def test_manifest_mismatch_refused(tmp_path, data):
    out = str(tmp_path / "job")
    map_chunks(affine, data, chunk_size=1000, out=out, progress=False)
    other = {"a": data["a"].copy(), "b": data["b"].copy()}
    other["b"][4321] += 1e-12
    with pytest.raises(InputError, match="fingerprint differs"):
        map_chunks(affine, other, out=out, progress=False)
    with pytest.raises(InputError, match="chunk_size differs"):
        map_chunks(affine, data, chunk_size=500, out=out, progress=False)
    with pytest.raises(InputError, match="fn differs"):
        map_chunks(mc, data, out=out, progress=False)
    with pytest.raises(InputError, match="tag differs"):
        map_chunks(affine, data, out=out, tag={"aero": "constant"}, progress=False)
    fly_out, states = str(tmp_path / "fly"), {"states": serve_states(4)}
    map_chunks(functools.partial(fly_chunk, params=FlightParams()), states, out=fly_out, progress=False)
    map_chunks(functools.partial(fly_chunk, params=FlightParams()), states, out=fly_out, progress=False)
    with pytest.raises(InputError, match="fn differs"):  # other physics = another job
        map_chunks(
            functools.partial(fly_chunk, params=FlightParams.from_options(air_density=1.1)),
            states,
            out=fly_out,
            progress=False,
        )
    (tmp_path / "junk").mkdir()
    (tmp_path / "junk" / "notes.txt").write_text("mine")
    with pytest.raises(InputError, match="not empty"):
        map_chunks(affine, data, out=str(tmp_path / "junk"), progress=False)
    # the refused runs changed nothing
    assert np.array_equal(read_output(out)["s"], data["a"] * 2.0 + data["b"])


def test_stream_source_resume_and_mismatch(tmp_path):
    def chunks(scale):
        for i in range(4):
            a = np.arange(i * 10, i * 10 + 10, dtype=float) * scale
            yield {"a": a, "b": np.ones(10)}

    out = str(tmp_path / "s")
    r1 = run_batch(affine, StreamSource(chunks(1.0), n_chunks=4), out=out, progress=False)
    assert (r1.n_rows, r1.n_chunks, r1.computed) == (40, 4, 4)
    CALLS.clear()
    r2 = run_batch(affine, chunks(1.0), out=out, progress=False)
    assert (r2.computed, r2.skipped) == (0, 4) and CALLS == []
    assert np.array_equal(r2.data["s"], np.arange(40.0) * 2 + 1)
    with pytest.raises(InputError, match="input chunk 0 differs"):
        run_batch(affine, chunks(2.0), out=out, progress=False)
    with pytest.raises(InputError, match="only 3 chunks"):
        run_batch(affine, (c for i, c in enumerate(chunks(1.0)) if i < 3), out=out, progress=False)
    assert np.array_equal(read_output(out)["s"], np.arange(40.0) * 2 + 1)


def test_collect_false_bounded_and_readable(tmp_path, data):
    out = str(tmp_path / "big")
    res = map_chunks(affine, data, out=out, collect=False, chunk_size=999, progress=False)
    assert res.data is None and res.n_rows == 5000 and res.computed == 6
    back = read_output(out)
    assert np.array_equal(back["s"], data["a"] * 2.0 + data["b"])
    with pytest.raises(InputError, match="collect"):
        map_chunks(affine, data, collect=False, progress=False)


def _multi(chunk):
    n = len(chunk["states"])
    return {
        "states2": chunk["states"] * 2,
        "i": np.arange(n, dtype=np.int32),
        "name": np.where(chunk["states"][:, 0] > 0, "far", "near"),
        "m": np.ones((n, 2, 3), np.float32),
    }


def test_parquet_roundtrip_keeps_shapes_and_dtypes(tmp_path):
    s = serve_states(50)
    s[::2, 0] *= -1
    a = map_chunks(_multi, {"states": s}, chunk_size=16, out=str(tmp_path / "m"), progress=False)
    b = read_output(str(tmp_path / "m"))
    for k in a:
        assert a[k].dtype == b[k].dtype and a[k].shape == b[k].shape and np.array_equal(a[k], b[k]), k
    assert b["states2"].shape == (50, 9) and b["m"].shape == (50, 2, 3) and b["name"][0] in ("far", "near")
    c = map_chunks(
        _labels, {"x": np.array([1.0, 2.0, -1.0, -2.0])}, chunk_size=2, out=str(tmp_path / "l"), progress=False
    )
    assert c["side"].tolist() == ["far", "far", "near", "near"] == read_output(str(tmp_path / "l"))["side"].tolist()


def _labels(chunk):
    return {"side": np.array(["far" if x > 0 else "near" for x in chunk["x"]])}  # <U3 then <U4


# --------------------------------------------------------------- validation
def test_bad_inputs_are_input_errors():
    with pytest.raises(InputError, match=r"inputs\['b'\]: has 3 rows, expected 4"):
        map_chunks(affine, {"a": np.zeros(4), "b": np.zeros(3)})
    with pytest.raises(InputError, match="scheduler"):
        map_chunks(affine, {"a": np.zeros(4), "b": np.zeros(4)}, scheduler="gpu")
    with pytest.raises(InputError, match="HOST:PORT"):
        map_chunks(affine, {"a": np.zeros(4), "b": np.zeros(4)}, scheduler="tcp://nohost")
    with pytest.raises(InputError, match="inputs"):
        map_chunks(affine, 42)
    with pytest.raises(TypeError, match="expected 4 rows"):
        map_chunks(lambda c: {"x": np.zeros(3)}, {"a": np.zeros(4)}, progress=False)


# ---------------------------------------------------------------------- grid
def test_grid_chunks_match_meshgrid():
    axes = {"v": np.array([20.0, 25.0, 30.0]), "w": np.array([0.0, 100.0]), "h": np.array([0.5, 0.7, 0.9, 1.1])}
    g = GridSpec(axes, row_key="row")
    mesh = np.meshgrid(*axes.values(), indexing="ij")
    full = {k: m.ravel() for k, m in zip(axes, mesh)}
    assert g.size == 24 and g.shape == (3, 2, 4)
    parts = [g.chunk(i, 5) for i in range(g.n_chunks(5))]
    for k in axes:
        assert np.array_equal(np.concatenate([p[k] for p in parts]), full[k])
    assert np.array_equal(np.concatenate([p["row"] for p in parts]), np.arange(24))
    assert g.index(v=2, w=1, h=3) == 23
    out = map_chunks(affine_grid, g, chunk_size=7, include_inputs=True, progress=False)
    assert np.array_equal(out["vw"], full["v"] * full["w"])


def affine_grid(chunk):
    return {"vw": chunk["v"] * chunk["w"]}


def test_huge_grid_is_never_materialised():
    """A 6-D launcher table at the machine's steps: ~10^10 rows, chunks by arithmetic."""
    axes = {
        "speed": np.linspace(10, 40, 121),
        "spin": np.linspace(-400, 400, 161),
        "axis": np.radians(np.arange(-90, 91, 5.0)),
        "elevation": np.radians(np.arange(-10, 45.1, 1.0)),
        "heading": np.radians(np.arange(-20, 20.1, 1.0)),
        "height": np.linspace(0.3, 1.5, 13),
    }
    g = GridSpec(axes)
    assert g.size == 121 * 161 * 37 * 56 * 41 * 13 and g.size > 10**10
    last = g.chunk(g.n_chunks(65536) - 1, 65536)
    assert len(last["speed"]) == g.size - (g.n_chunks(65536) - 1) * 65536
    assert last["speed"][-1] == 40 and last["height"][-1] == 1.5 and last["spin"][-1] == 400
    r = g.index(speed=60, spin=3, axis=7, elevation=11, heading=5, height=2)
    mid = g.rows(r, r + 3)
    assert mid["speed"][0] == axes["speed"][60] and mid["elevation"][0] == axes["elevation"][11]
    assert GridSpec(axes).fingerprint() == g.fingerprint()
    assert GridSpec(dict(axes, height=axes["height"] + 1e-9)).fingerprint() != g.fingerprint()
    with pytest.raises(InputError, match="axes\\['bad'\\]"):
        GridSpec({"bad": np.array([])})


# ----------------------------------------------------------------------- rng
def test_rng_distribution_and_streams():
    rows = np.arange(100_000)
    u = rng.uniform(5, rows)
    z = rng.normal(5, rows)
    assert 0 < u.min() and u.max() < 1
    assert stats.kstest(u, "uniform").pvalue > 1e-3
    assert stats.kstest(z, "norm").pvalue > 1e-3
    assert abs(np.corrcoef(z, rng.normal(5, rows, stream=1))[0, 1]) < 0.02
    assert abs(np.corrcoef(z, rng.normal(6, rows))[0, 1]) < 0.02
    assert abs(np.corrcoef(u[:-1], u[1:])[0, 1]) < 0.02
    # a pure function of (seed, stream, row): any subset, any order
    idx = np.array([99_999, 3, 50_000, 3])
    assert np.array_equal(rng.normal(5, idx), z[idx])


# ------------------------------------------------------------ CLI & progress
def test_scheduler_flags():
    p = argparse.ArgumentParser()
    add_scheduler_flag(p)
    a = p.parse_args([])
    assert batch_options_from_args(a) == {
        "scheduler": "local",
        "out": None,
        "n_workers": None,
        "chunk_size": None,
        "progress": "auto",
    }
    a = p.parse_args(["--scheduler", "tcp://10.0.0.5:8786", "--out-dir", "o", "--workers", "3", "--no-progress"])
    assert (a.scheduler, a.out_dir, a.workers, a.progress) == ("tcp://10.0.0.5:8786", "o", 3, False)
    assert batch_options_from_args(a)["progress"] is False
    assert batch_options_from_args(p.parse_args(["--progress"]))["progress"] == "always"
    assert p.parse_args(["--scheduler", "processes"]).scheduler == "processes"
    for bad in (["--scheduler", "threads"], ["--scheduler", "tcp://host"], ["--chunk-size", "0"]):
        with pytest.raises(SystemExit) as exc:
            p.parse_args(bad)
        assert exc.value.code == 2
    q = argparse.ArgumentParser()
    q.add_argument("--workers", type=int)  # a command's own flag wins, no clash
    add_scheduler_flag(q)
    assert q.parse_args(["--workers", "5"]).workers == 5


def test_the_flags_old_home_still_works():
    """The helpers moved to the CLI layer (argparse only under cli/); the old names still work, with a warning."""
    import tennislab.batch

    with pytest.warns(DeprecationWarning, match="moved to tennislab.cli.add_scheduler_flag"):
        assert tennislab.batch.add_scheduler_flag is add_scheduler_flag
    with pytest.warns(DeprecationWarning):
        from tennislab.batch import batch_options_from_args as old
    assert old is batch_options_from_args


def test_progress_bar_draws_only_when_enabled():
    s = io.StringIO()
    bar = ProgressBar(4, desc="serves", stream=s, min_interval=0)
    bar.skip()
    bar.update(1000)
    bar.close()
    assert "2/4 chunks" in s.getvalue() and "(1 chunks resumed)" in s.getvalue() and "serves" in s.getvalue()
    assert not progress_enabled(True, io.StringIO()) and progress_enabled("always", io.StringIO())
    assert not progress_enabled(False, io.StringIO())


def test_default_chunk_size():
    assert default_chunk_size(10) == 1024 and default_chunk_size(10**8) == 65536
    assert default_chunk_size(64 * 5000) == 5000


@settings(max_examples=30, deadline=None)
@given(shape=st.lists(st.integers(1, 5), min_size=1, max_size=4), cs=st.integers(1, 70))
def test_grid_rows_are_meshgrid_in_c_order(shape, cs):
    axes = {f"a{i}": np.arange(k, dtype=float) * (i + 1) + 0.5 for i, k in enumerate(shape)}
    g = GridSpec(axes, row_key="row")
    mesh = np.meshgrid(*axes.values(), indexing="ij")
    got = [g.chunk(i, cs) for i in range(g.n_chunks(cs))]
    assert sum(len(c["row"]) for c in got) == g.size == int(np.prod(shape))
    for k, m in zip(axes, mesh):
        assert np.array_equal(np.concatenate([c[k] for c in got]), m.ravel())
    pos = {k: n - 1 for k, n in zip(axes, shape)}
    assert g.index(**pos) == g.size - 1


def test_progress_forced_on_a_pipe(capsys, data):
    map_chunks(affine, data, chunk_size=1000, progress="always", desc="forced")
    err = capsys.readouterr().err
    assert "5,000/5,000 rows 100%" in err and "forced" in err and err.endswith("\n") and "\r" not in err
    map_chunks(affine, data, chunk_size=1000, progress=True)  # stderr is not a TTY here: silent
    assert capsys.readouterr().err == ""


def test_two_runs_never_share_an_output_directory(tmp_path, data):
    from tennislab.batch.store import ChunkStore

    out = str(tmp_path / "job")
    map_chunks(affine, data, out=out, chunk_size=1000, progress=False)
    held = ChunkStore(out, read_manifest(out), lock=True)  # another run in progress
    try:
        with pytest.raises(InputError, match="in use by another run"):
            map_chunks(affine, data, out=out, progress=False)
    finally:
        held.close()
    assert run_batch(affine, data, out=out, progress=False).skipped == 5


def mc_rows(chunk, seed=3):
    return {"v": chunk["v0"] + rng.normal(seed, chunk["row"])}


def test_row_range_monte_carlo_is_lazy_and_chunking_free(tmp_path):
    src = RowRange(10_000, constants={"v0": 50.0})
    assert src.chunk(3, 4096)["row"].size == 0
    last = src.chunk(2, 4096)
    assert last["row"][0] == 8192 and last["row"][-1] == 9999 and np.all(last["v0"] == 50.0)
    a = map_chunks(mc_rows, src, chunk_size=4096, progress=False)
    b = map_chunks(mc_rows, src, chunk_size=999, out=str(tmp_path / "mc"), progress=False)
    assert np.array_equal(a["v"], b["v"]) and np.array_equal(a["v"], 50.0 + rng.normal(3, np.arange(10_000)))
    assert RowRange(10**12).n_chunks(65536) == -(-(10**12) // 65536)  # nothing of size N is built
    with pytest.raises(InputError, match="fingerprint differs"):
        map_chunks(mc_rows, RowRange(10_001, constants={"v0": 50.0}), out=str(tmp_path / "mc"), progress=False)


# --------------------------------------------------------- per-chunk callback
class Sink:
    """An on_chunk consumer (like a database): records (chunk, row0, outputs)."""

    def __init__(self, fail_at=None):
        self.got, self.fail_at = [], fail_at

    def __call__(self, i, row0, outputs):
        if i == self.fail_at:
            raise RuntimeError("sink full")
        self.got.append((i, row0, outputs))

    def rows(self, key):
        return np.concatenate([o[key] for _, _, o in sorted(self.got, key=lambda t: t[0])])


def test_on_chunk_once_per_chunk_in_order_without_out(data):
    sink = Sink()
    res = run_batch(affine, data, chunk_size=700, collect=False, on_chunk=sink, progress=False)
    assert res.data is None and (res.computed, res.skipped, res.restored) == (8, 0, 0) and res.complete
    assert [(i, r0) for i, r0, _ in sink.got] == [(i, 700 * i) for i in range(8)]  # local: chunk order
    assert np.array_equal(sink.rows("s"), data["a"] * 2.0 + data["b"])
    for _i, r0, o in sink.got:
        assert len(o["s"]) == min(700, 5000 - r0)
    with pytest.raises(InputError, match="on_chunk"):
        run_batch(affine, data, on_chunk="print", progress=False)


def test_on_chunk_resume_restores_parts_the_sink_lacks(tmp_path, data):
    out = str(tmp_path / "job")
    sink = Sink(fail_at=3)  # parts 0-3 are written; the sink only got 0-2
    with pytest.raises(RuntimeError, match="sink full"):
        run_batch(affine, data, chunk_size=700, out=out, collect=False, on_chunk=sink, progress=False)
    assert [i for i, _, _ in sink.got] == [0, 1, 2] and not read_manifest(out)["complete"]
    have = {i for i, _, _ in sink.got}
    sink.fail_at = None
    CALLS.clear()
    res = run_batch(affine, data, out=out, collect=False, on_chunk=sink, skip=have, progress=False)
    # part 3 is read back (not recomputed), 0-2 are not delivered again, 4-7 are computed
    assert (res.computed, res.skipped, res.restored) == (4, 4, 1) and len(CALLS) == 4
    assert sorted(i for i, _, _ in sink.got) == list(range(8))
    assert np.array_equal(sink.rows("s"), data["a"] * 2.0 + data["b"])
    assert read_manifest(out)["complete"]
    # without skip every chunk of a finished output reaches the callback (restored), with collect
    again = Sink()
    res = run_batch(affine, data, out=out, on_chunk=again, progress=False)
    assert (res.computed, res.restored) == (0, 8) and [i for i, _, _ in again.got] == list(range(8))
    assert np.array_equal(res.data["s"], again.rows("s"))


def test_skip_without_out_and_with_missing_parts(tmp_path, data):
    sink = Sink()
    res = run_batch(affine, data, chunk_size=1000, collect=False, on_chunk=sink, skip={0, 4}, progress=False)
    assert (res.computed, res.skipped) == (3, 2) and CALLS == [1000] * 3
    assert [i for i, _, _ in sink.got] == [1, 2, 3]
    with pytest.raises(InputError, match="skip"):
        run_batch(affine, data, chunk_size=1000, skip={0}, progress=False)
    # with out, a skipped chunk without a part on disk is still computed (the directory must be complete)
    out, sink = str(tmp_path / "job"), Sink()
    res = run_batch(affine, data, chunk_size=1000, out=out, on_chunk=sink, skip={0, 4}, progress=False)
    assert res.computed == 5 and sorted(i for i, _, _ in sink.got) == list(range(5))
    assert np.array_equal(res.data["s"], data["a"] * 2.0 + data["b"]) and read_manifest(out)["complete"]


def test_max_chunks_stops_and_resumes(tmp_path, data):
    out, sink = str(tmp_path / "job"), Sink()
    first = run_batch(
        affine, data, chunk_size=1000, out=out, collect=False, on_chunk=sink, max_chunks=2, progress=False
    )
    assert (first.computed, first.n_chunks, first.n_rows, first.complete) == (2, 5, 5000, False)
    assert not read_manifest(out)["complete"]
    second = run_batch(
        affine,
        data,
        out=out,
        collect=False,
        on_chunk=sink,
        max_chunks=10,
        skip={i for i, _, _ in sink.got},
        progress=False,
    )
    assert (second.computed, second.skipped, second.complete) == (3, 2, True)
    assert np.array_equal(sink.rows("s"), data["a"] * 2.0 + data["b"]) and read_manifest(out)["complete"]
    for bad in ({"max_chunks": 0, "collect": False, "on_chunk": sink}, {"max_chunks": 1}):
        with pytest.raises(InputError, match="max_chunks"):
            run_batch(affine, data, progress=False, **bad)


def test_on_chunk_stream_source(tmp_path):
    chunks = [{"a": np.arange(i * 10, i * 10 + 10, dtype=float), "b": np.ones(10)} for i in range(4)]
    out, sink = str(tmp_path / "s"), Sink()
    run_batch(affine, iter(chunks), out=out, collect=False, on_chunk=sink, progress=False)
    assert [(i, r0) for i, r0, _ in sink.got] == [(0, 0), (1, 10), (2, 20), (3, 30)]
    again = Sink()
    res = map_chunks(affine, iter(chunks), out=out, on_chunk=again, skip={1}, progress=False)
    assert [(i, r0) for i, r0, _ in again.got] == [(0, 0), (2, 20), (3, 30)] and CALLS == [10] * 4
    assert np.array_equal(res["s"], np.arange(40.0) * 2 + 1)
