"""tennislab.batch on a real Dask cluster of worker processes started by the test.

One ``LocalCluster(n_workers=2, processes=True, threads_per_worker=1)`` per
module; jobs are small.  Checks: bit-identical results local vs cluster vs a
resumed run, resume skipping finished chunks (calls counted by marker files,
since workers are other processes), manifest mismatch refused, worker errors
surfacing as themselves, and the ``processes`` scheduler starting its own cluster.
"""

from __future__ import annotations

import functools
import os

import numpy as np
import pytest

distributed = pytest.importorskip("distributed")
pytest.importorskip("pyarrow")

from tennislab.batch import (  # noqa: E402
    GridSpec,
    RowRange,
    map_chunks,
    read_output,
    rng,
    run_batch,
)
from tennislab.batch.schedulers import worker_environment  # noqa: E402
from tennislab.batch.tasks import fly_chunk  # noqa: E402
from tennislab.core.flight import FlightParams  # noqa: E402
from tennislab.errors import InputError  # noqa: E402


@pytest.fixture(scope="module")
def cluster():
    with worker_environment(NUMBA_NUM_THREADS="1"):
        c = distributed.LocalCluster(
            n_workers=2, processes=True, threads_per_worker=1, dashboard_address=":0", silence_logs=40
        )
    with c:
        yield c


@pytest.fixture(scope="module")
def address(cluster):
    return cluster.scheduler_address


def serve_states(n: int, seed: int = 2) -> np.ndarray:
    g = np.random.default_rng(seed)
    v, el = g.uniform(40, 65, n), np.radians(g.uniform(-8, -2, n))
    s = np.zeros((n, 9))
    s[:, 0], s[:, 2] = -11.885, 2.8
    s[:, 3], s[:, 5] = v * np.cos(el), v * np.sin(el)
    s[:, 6:9] = g.uniform(-300, 300, (n, 3))
    return s


def counted_mc(chunk, marker_dir, trigger, seed=5):
    """Monte Carlo with per-row draws; leaves a marker file per call; fails at row 3000 while ``trigger`` exists."""
    row = chunk["row"]
    if os.path.exists(trigger) and row[0] <= 3000 <= row[-1]:
        raise RuntimeError("worker lost")
    with open(os.path.join(marker_dir, f"call-{row[0]}-{os.getpid()}"), "w"):
        pass
    return {"v": chunk["v0"] * (1 + 0.05 * rng.normal(seed, row)), "pid": np.full(len(row), os.getpid())}


def bad_input(chunk):
    raise InputError("spin: 99999 rpm is outside the allowed range [0, 6000] rpm")


def grid_fn(chunk):
    return {"reach": chunk["v"] ** 2 * np.sin(2 * chunk["el"]) / 9.80665}


def test_fly_batch_bit_identical_local_vs_cluster(address):
    s = serve_states(4000)
    job = functools.partial(fly_chunk, params=FlightParams(), columns=("land_x", "land_y", "net_z", "status"))
    local = map_chunks(job, {"states": s}, chunk_size=500, progress=False)
    remote = map_chunks(job, {"states": s}, chunk_size=500, scheduler=address, progress=False)
    other_chunks = map_chunks(job, {"states": s}, chunk_size=1300, scheduler=address, progress=False)
    for k in local:
        # the workers run the kernel from Numba's on-disk cache; a process that compiled it itself (this
        # one, on a cold cache) runs code that can differ in the last bits (docs/batch.md, "Reproducibility")
        assert np.allclose(local[k], remote[k], rtol=0, atol=1e-9), k
        assert np.array_equal(remote[k], other_chunks[k]), k  # chunking never changes a bit
    assert np.isfinite(local["land_x"]).all()


def test_resume_across_schedulers_and_call_counts(address, tmp_path):
    x = {"v0": np.linspace(30, 60, 6000)}
    marks, trigger = tmp_path / "marks", tmp_path / "crash"
    marks.mkdir()
    trigger.write_text("")
    job = functools.partial(counted_mc, marker_dir=str(marks), trigger=str(trigger))
    out = str(tmp_path / "mc")
    with pytest.raises(RuntimeError, match="worker lost"):  # a "crash" on the cluster mid-job
        map_chunks(job, x, chunk_size=1000, row_key="row", out=out, scheduler=address, progress=False)
    finished = sorted(n for n in os.listdir(out) if n.startswith("part-"))
    assert "part-00003.parquet" not in finished
    trigger.unlink()
    for m in marks.iterdir():
        m.unlink()
    res = run_batch(job, x, row_key="row", out=out, scheduler=address, progress=False)
    assert res.skipped == len(finished) and res.computed == 6 - len(finished)
    assert len(list(marks.iterdir())) == res.computed  # each unfinished chunk ran exactly once
    ref = map_chunks(job, x, chunk_size=700, row_key="row", progress=False)  # in process, other chunking
    assert np.array_equal(res.data["v"], ref["v"]) and np.array_equal(read_output(out)["v"], ref["v"])
    assert len(set(res.data["pid"])) >= 2  # really ran in other processes
    for m in marks.iterdir():
        m.unlink()
    again = run_batch(job, x, row_key="row", out=out, scheduler="local", progress=False)
    assert (again.computed, again.skipped) == (0, 6) and not list(marks.iterdir())
    with pytest.raises(InputError, match="another job"):
        map_chunks(job, {"v0": x["v0"] + 1}, row_key="row", out=out, scheduler=address, progress=False)


def test_grid_chunks_built_on_workers(address):
    g = GridSpec({"v": np.linspace(10, 40, 31), "el": np.radians(np.arange(0, 60.0, 0.5))})
    local = map_chunks(grid_fn, g, chunk_size=256, include_inputs=True, progress=False)
    remote = map_chunks(grid_fn, g, chunk_size=256, include_inputs=True, scheduler=address, progress=False)
    for k in local:
        assert np.array_equal(local[k], remote[k])
    assert len(local["reach"]) == g.size
    src = RowRange(5000, constants={"v0": 50.0})
    a = map_chunks(rows_mc, src, chunk_size=1000, progress=False)
    b = map_chunks(rows_mc, src, chunk_size=700, scheduler=address, progress=False)
    assert np.array_equal(a["v"], b["v"])


def rows_mc(chunk):
    return {"v": chunk["v0"] + rng.normal(9, chunk["row"])}


def test_worker_input_error_surfaces(address):
    with pytest.raises(InputError, match="spin"):
        map_chunks(bad_input, {"a": np.zeros(10)}, scheduler=address, progress=False)


def test_client_object_and_processes_scheduler(cluster):
    s = serve_states(600)
    job = functools.partial(fly_chunk, columns=("land_x", "land_t"))
    ref = map_chunks(job, {"states": s}, chunk_size=100, progress=False)
    with distributed.Client(cluster, set_as_default=False) as client:
        via_client = map_chunks(job, {"states": s}, chunk_size=100, scheduler=client, progress=False)
        assert client.status == "running"  # a client passed in is left open
    own = run_batch(job, {"states": s}, chunk_size=100, scheduler="processes", n_workers=1, progress=False)
    for k in ref:  # workers load the cached kernels: bit-identical among them (docs/batch.md)
        assert np.array_equal(via_client[k], own.data[k]), k
        assert np.allclose(ref[k], via_client[k], rtol=0, atol=1e-9), k
    assert own.scheduler == "processes" and own.computed == 6
