"""Batch output directories that were damaged, foreign or malformed: recovered or refused, never mixed (issue 16)."""

from __future__ import annotations

import functools
import json
import os
import stat

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tennislab.batch import read_manifest, read_output, run_batch
from tennislab.batch.store import LEDGER, LOCK, MANIFEST, ChunkStore
from tennislab.errors import InputError

CALLS: list[int] = []


def affine(chunk):
    CALLS.append(len(chunk["a"]))
    return {"s": chunk["a"] * 2.0 + chunk["b"]}


def failing(chunk):
    raise RuntimeError("no worker")


def flaky(chunk, trigger):
    """``affine``, but the third chunk fails while the file ``trigger`` exists."""
    if os.path.exists(trigger) and chunk["row"][0] == 2000:
        raise RuntimeError("killed")
    return affine(chunk)


@pytest.fixture
def data():
    g = np.random.default_rng(5)
    return {"a": g.random(3000), "b": g.random(3000)}


@pytest.fixture(autouse=True)
def _clear():
    CALLS.clear()


def _snapshot(d) -> dict:
    """Every file under ``d`` with its bytes (a refused run must leave them as they were)."""
    out = {}
    for name in sorted(os.listdir(d)):
        with open(os.path.join(d, name), "rb") as fh:
            out[name] = fh.read()
    return out


def _job(tmp_path, data):
    out = str(tmp_path / "job")
    ref = run_batch(affine, data, chunk_size=1000, out=out, progress=False).data
    CALLS.clear()
    return out, ref


def _part(out, i):
    return os.path.join(out, f"part-{i:05d}.parquet")


@pytest.mark.parametrize("damage", ["zero-byte", "truncated", "bit-flip", "deleted", "foreign-part"])
def test_damaged_part_is_recomputed(tmp_path, data, damage):
    out, ref = _job(tmp_path, data)
    p = _part(out, 1)
    blob = open(p, "rb").read()
    if damage == "zero-byte":
        open(p, "wb").close()
    elif damage == "truncated":
        open(p, "wb").write(blob[: len(blob) // 2])
    elif damage == "bit-flip":
        b = bytearray(blob)
        b[len(b) // 2] ^= 0x10
        open(p, "wb").write(bytes(b))
    elif damage == "deleted":
        os.unlink(p)
    else:  # a valid Parquet file of the right shape, but not the one recorded
        open(p, "wb").write(open(_part(out, 0), "rb").read())
    if damage != "deleted":
        with pytest.raises(InputError, match="damaged"):
            read_output(out)  # never read as if it were good
    res = run_batch(affine, data, out=out, progress=False)
    assert (res.computed, res.skipped) == (1, 2) and CALLS == [1000]
    assert np.array_equal(res.data["s"], ref["s"])
    assert np.array_equal(read_output(out)["s"], ref["s"])
    assert read_manifest(out)["complete"]


def test_part_written_but_not_recorded_is_recomputed(tmp_path, data):
    """A run killed between the rename of a part and its ledger line: the part is not trusted."""
    out = str(tmp_path / "job")
    trigger = tmp_path / "kill"
    trigger.write_text("")
    job = functools.partial(flaky, trigger=str(trigger))
    with pytest.raises(RuntimeError, match="killed"):
        run_batch(job, data, chunk_size=1000, out=out, row_key="row", progress=False)
    trigger.unlink()
    ledger = os.path.join(out, LEDGER)
    lines = open(ledger).read().splitlines()
    assert len(lines) == 2
    open(ledger, "w").write(lines[0] + "\n" + lines[1][:10])  # torn last line
    CALLS.clear()
    res = run_batch(job, data, chunk_size=1000, out=out, row_key="row", progress=False)
    assert res.computed == 2 and CALLS == [1000, 1000]
    assert np.array_equal(res.data["s"], data["a"] * 2 + data["b"])
    assert not os.path.exists(ledger)  # folded into the manifest
    man = read_manifest(out)
    assert sorted(man["parts"]) == ["0", "1", "2"] and all(r["rows"] == 1000 for r in man["parts"].values())


@pytest.mark.parametrize("text", ["[]", "", "{", "null", '{"format": 1}', '"x"', "\xff\xfe"])
def test_malformed_manifest_is_one_line_and_nothing_changes(tmp_path, data, text):
    out, _ = _job(tmp_path, data)
    with open(os.path.join(out, MANIFEST), "w", encoding="latin-1") as fh:
        fh.write(text)
    before = _snapshot(out)
    with pytest.raises(InputError, match=r"^out: .*(not a tennislab batch manifest|another version)") as e:
        run_batch(affine, data, out=out, progress=False)
    assert "\n" not in str(e.value)
    with pytest.raises(InputError):
        read_output(out)
    assert _snapshot(out) == before and CALLS == []


def test_manifest_of_an_older_format_is_refused(tmp_path, data):
    out, _ = _job(tmp_path, data)
    man = json.load(open(os.path.join(out, MANIFEST)))
    man["format"] = "tennislab.batch/1"
    json.dump(man, open(os.path.join(out, MANIFEST), "w"))
    with pytest.raises(InputError, match="another version"):
        run_batch(affine, data, out=out, progress=False)


def test_foreign_job_refused_untouched(tmp_path, data):
    out, _ = _job(tmp_path, data)
    open(os.path.join(out, ".tmp-users-own"), "w").write("keep")
    before = _snapshot(out)
    other = {"a": data["a"][::-1].copy(), "b": data["b"]}
    with pytest.raises(InputError, match="holds another job"):
        run_batch(affine, other, out=out, progress=False)
    assert _snapshot(out) == before


def test_non_empty_folder_without_manifest_untouched(tmp_path, data):
    d = tmp_path / "mine"
    d.mkdir()
    (d / ".tmp-draft").write_text("a user's temp file")
    (d / ".tmp-part-00000.parquet").write_text("not ours either")
    (d / "notes.txt").write_text("notes")
    before = _snapshot(d)
    with pytest.raises(InputError, match="not empty"):
        run_batch(affine, data, out=str(d), progress=False)
    assert _snapshot(d) == before  # nothing deleted, no .lock, no manifest


def test_own_leftover_temporaries_are_cleaned_others_kept(tmp_path, data):
    out, ref = _job(tmp_path, data)
    ours = os.path.join(out, ".part-00001.parquet.tmp-0123456789abcdef")
    theirs = os.path.join(out, ".tmp-notes")
    open(ours, "w").write("half a part")
    open(theirs, "w").write("user")
    res = run_batch(affine, data, out=out, progress=False)
    assert res.computed == 0 and not os.path.exists(ours) and open(theirs).read() == "user"
    assert np.array_equal(res.data["s"], ref["s"])


def test_only_temporaries_this_job_can_write_are_removed(tmp_path, data):
    """Issue 24 point 15: a rerun deleted user files that only looked like its leftovers.  A 3-part job
    writes ``.part-00000..00002.parquet.tmp-<16 hex>`` and ``.manifest.json.tmp-<16 hex>``, nothing else."""
    out, ref = _job(tmp_path, data)
    ours = [".part-00002.parquet.tmp-0123456789abcdef", ".manifest.json.tmp-fedcba9876543210"]
    theirs = [
        ".part-00099.parquet.tmp-0123456789abcdef",  # a part this job does not have
        ".part-000001.parquet.tmp-0123456789abcdef",  # a spelling it does not write
        ".part-00001.parquet.tmp-0123456789ABCDEF",  # not its random suffix
        ".part-00001.parquet.tmp-0123456789abcdef0",
    ]
    for name in ours + theirs:
        with open(os.path.join(out, name), "w") as fh:
            fh.write("x")
    res = run_batch(affine, data, chunk_size=1000, out=out, progress=False)
    assert res.computed == 0 and np.array_equal(res.data["s"], ref["s"])
    left = set(os.listdir(out))
    assert not left & set(ours) and set(theirs) <= left


@pytest.mark.parametrize(
    "parts",
    [{"x": {"rows": 1, "bytes": 1, "blake2b": "0" * 32}}, {"-1": {"rows": 1, "bytes": 1, "blake2b": "0" * 32}}],
    ids=["part-key-not-a-number", "part-key-negative"],
)
def test_malformed_part_keys_are_one_line(tmp_path, data, parts):
    """Issue 24 point 6: a manifest whose part key is not a part number gave a ValueError traceback."""
    out, _ = _job(tmp_path, data)
    man = json.load(open(os.path.join(out, MANIFEST)))
    man["parts"] = parts
    with open(os.path.join(out, MANIFEST), "w") as fh:
        json.dump(man, fh)
    before = _snapshot(out)
    with pytest.raises(InputError, match="malformed part records"):
        run_batch(affine, data, chunk_size=1000, out=out, progress=False)
    with pytest.raises(InputError, match="malformed part records"):
        read_output(out)
    assert _snapshot(out) == before


@pytest.mark.parametrize("which", [MANIFEST, LEDGER, LOCK, "part-00001.parquet"])
def test_special_files_in_the_folder_never_block(tmp_path, data, which):
    """A FIFO in place of the manifest, the ledger or a part never blocks a rerun: the manifest's and the
    ledger's are refused in one line, a part's is computed again."""
    out, ref = _job(tmp_path, data)
    path = os.path.join(out, which)
    if os.path.exists(path):
        os.unlink(path)
    os.mkfifo(path)
    if which in (MANIFEST, LEDGER, LOCK):
        with pytest.raises(InputError, match="FIFO|not a regular file"):
            run_batch(affine, data, chunk_size=1000, out=out, progress=False)
        return
    res = run_batch(affine, data, chunk_size=1000, out=out, progress=False)
    assert np.array_equal(res.data["s"], ref["s"])


def test_failed_start_leaves_no_directory(tmp_path, data):
    out = tmp_path / "new"
    with pytest.raises(RuntimeError, match="no worker"):
        run_batch(failing, data, out=str(out), progress=False)
    assert not out.exists()
    (tmp_path / "f").write_text("")
    with pytest.raises(InputError, match="cannot create"):
        run_batch(affine, data, out=str(tmp_path / "f" / "x"), progress=False)


def test_files_follow_the_umask(tmp_path, data):
    old = os.umask(0o022)
    try:
        out, _ = _job(tmp_path, data)
    finally:
        os.umask(old)
    for name in os.listdir(out):
        mode = stat.S_IMODE(os.stat(os.path.join(out, name)).st_mode)
        assert mode == 0o644, (name, oct(mode))


def test_ledger_records_sizes_and_checksums(tmp_path, data):
    out = str(tmp_path / "job")
    store = ChunkStore(out, {"fn": "f", "chunk_size": 10, "n_rows": 20}, lock=True)
    try:
        store.write(0, {"x": np.arange(10.0)}, {})
        rec = json.loads(open(os.path.join(out, LEDGER)).read())
        assert rec["part"] == 0 and rec["rows"] == 10 and rec["bytes"] == os.path.getsize(_part(out, 0))
        assert len(rec["blake2b"]) == 32
    finally:
        store.close()


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(cut=st.integers(0, 4000), flip=st.integers(0, 4000), which=st.integers(0, 2))
def test_any_damage_recovers_to_the_same_result(tmp_path_factory, cut, flip, which):
    g = np.random.default_rng(9)
    x = {"a": g.random(300), "b": g.random(300)}
    out = str(tmp_path_factory.mktemp("h") / "job")
    ref = run_batch(affine, x, chunk_size=100, out=out, progress=False).data["s"]
    p = _part(out, which)
    b = bytearray(open(p, "rb").read())
    if flip < len(b):
        b[flip] ^= 0x01
    open(p, "wb").write(bytes(b[: min(cut, len(b))]) if cut < len(b) else bytes(b))
    res = run_batch(affine, x, out=out, progress=False)
    assert np.array_equal(res.data["s"], ref)
    assert np.array_equal(read_output(out)["s"], ref)
