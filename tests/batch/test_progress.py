"""Progress on any stream in the user's units (tennislab.batch.progress): a bar redrawn in place on a
terminal, a line every few seconds in a log, silent for short default ("auto") work."""

from __future__ import annotations

import io

import numpy as np
import pytest

from tennislab.batch import progress as P
from tennislab.batch import run_batch


class Clock:
    def __init__(self):
        self.t = 0.0

    def __call__(self):
        return self.t


class Tty(io.StringIO):
    def isatty(self):
        return True


@pytest.fixture
def clock(monkeypatch):
    c = Clock()
    monkeypatch.setattr(P.time, "perf_counter", c)
    monkeypatch.delenv("TENNISLAB_PROGRESS", raising=False)
    return c


def _run(clock, stream, progress, n_chunks=40, dt=0.5, per=250):
    mode = P.progress_mode(progress, stream)
    bar = P.ProgressBar(n_chunks, enabled=mode is not None, mode=mode, stream=stream, unit="serves",
                        total_units=n_chunks * per)  # fmt: skip
    for _ in range(n_chunks):
        clock.t += dt
        bar.update(per)
    bar.close()
    return stream.getvalue()


def test_modes(monkeypatch):
    monkeypatch.delenv("TENNISLAB_PROGRESS", raising=False)
    log, tty = io.StringIO(), Tty()
    assert P.progress_mode("auto", tty) == "auto-bar" and P.progress_mode("auto", log) is None
    assert P.progress_mode(True, tty) == "bar" and P.progress_mode(True, log) is None
    assert P.progress_mode("always", tty) == "bar" and P.progress_mode("always", log) == "lines"
    assert P.progress_mode(False, tty) is None
    monkeypatch.setenv("TENNISLAB_PROGRESS", "1")
    assert P.progress_mode(False, log) == "lines"
    monkeypatch.setenv("TENNISLAB_PROGRESS", "0")
    assert P.progress_mode("always", tty) is None


def test_a_log_gets_a_line_every_few_seconds(clock):
    out = _run(clock, io.StringIO(), "always")  # 20 s of work, 40 updates
    lines = out.splitlines()
    assert "\r" not in out and "\x1b" not in out
    assert 4 <= len(lines) <= 7, lines  # the first, one per 5 s, the last
    assert lines[-1].startswith("10,000/10,000 serves 100%")
    assert "500 serves/s" in lines[-1]  # the user's unit, not rows or blocks


def test_a_terminal_bar_in_place_in_the_users_units(clock):
    out = _run(clock, Tty(), True)
    assert out.count("\n") == 1 and out.count("\r") >= 30
    last = out.rsplit("\r", 1)[1]
    assert last.startswith("[" + "#" * 28 + "]  10,000/10,000 serves 100%") and "serves/s" in last


def test_auto_is_silent_for_short_work_and_shown_for_long(clock):
    assert _run(clock, Tty(), "auto", n_chunks=8, dt=0.25) == ""  # 2 s of work
    long = _run(clock, Tty(), "auto", n_chunks=40, dt=0.5)  # 20 s: shown from its first estimate
    assert long.count("\r") >= 30 and "10,000/10,000 serves" in long
    assert _run(clock, io.StringIO(), "auto") == ""  # never in a log unless asked


def test_points_and_calls(clock):
    s = io.StringIO()
    bar = P.ProgressBar(3, mode="lines", stream=s, unit="calls", chunk_unit="points")
    for n in (4, 5, 3):
        clock.t += 1.0
        bar.update(n)
    bar.close()
    assert s.getvalue().splitlines()[-1].startswith("3/3 points, 12 calls 100%  4.0 calls/s")


def _double(chunk):
    return {"y": 2 * chunk["x"]}


def test_run_batch_counts_units(monkeypatch, capsys):
    monkeypatch.setenv("TENNISLAB_PROGRESS", "1")
    run_batch(_double, {"x": np.arange(3000.0)}, chunk_size=1000, unit="flights")
    err = capsys.readouterr().err
    assert "3,000/3,000 flights 100%" in err and "flights/s" in err
    run_batch(_double, {"x": np.arange(3000.0)}, chunk_size=1000, unit="serves", count=lambda o: 10 * len(o["y"]),
              total_units=30000)  # fmt: skip
    assert "30,000/30,000 serves 100%" in capsys.readouterr().err
    monkeypatch.delenv("TENNISLAB_PROGRESS")
    run_batch(_double, {"x": np.arange(3000.0)}, chunk_size=1000)  # the default: short work stays silent
    assert capsys.readouterr().err == ""
