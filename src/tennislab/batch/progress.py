"""A dependency-free terminal progress bar, updated once per finished chunk.

Written to stderr with carriage returns; silent when stderr is not a TTY
unless forced (``progress="always"`` or environment ``TENNISLAB_PROGRESS=1``),
so logs and pipes stay clean.
"""

from __future__ import annotations

import os
import sys
import time


def _fmt_time(s: float) -> str:
    if s != s or s == float("inf"):
        return "--:--"
    s = int(round(s))
    h, rem = divmod(s, 3600)
    m, sec = divmod(rem, 60)
    return f"{h}:{m:02d}:{sec:02d}" if h else f"{m:02d}:{sec:02d}"


def _fmt_rate(r: float) -> str:
    for unit, f in (("G", 1e9), ("M", 1e6), ("k", 1e3)):
        if r >= f:
            return f"{r / f:.1f}{unit}"
    return f"{r:.0f}"


def progress_enabled(progress, stream=None) -> bool:
    """True/False/"always" -> whether to draw (True draws only on a TTY)."""
    stream = stream or sys.stderr
    if progress == "always" or os.environ.get("TENNISLAB_PROGRESS") == "1":
        return True
    if not progress:
        return False
    isatty = getattr(stream, "isatty", None)
    return bool(isatty and isatty())


class ProgressBar:
    """``[#####-----]  12/100 chunks  12%  340k rows/s  ETA 00:12  desc``.

    ``total`` may be None (unknown chunk count of a stream): then no bar/ETA.
    Rows of skipped (resumed) chunks count toward completion but not the rate.
    """

    def __init__(
        self,
        total: int | None,
        desc: str = "",
        enabled: bool = True,
        stream=None,
        width: int = 28,
        min_interval: float = 0.1,
    ):
        self.total = total
        self.desc = desc
        self.enabled = enabled
        self.stream = stream or sys.stderr
        self.width = width
        self.min_interval = min_interval
        self.done = 0
        self.rows = 0
        self.skipped = 0
        self.t0 = time.perf_counter()
        self._last = 0.0

    def skip(self, n_chunks: int = 1) -> None:
        self.done += n_chunks
        self.skipped += n_chunks
        self._draw()

    def update(self, n_rows: int, n_chunks: int = 1) -> None:
        self.done += n_chunks
        self.rows += int(n_rows)
        self._draw()

    def line(self) -> str:
        dt = max(time.perf_counter() - self.t0, 1e-9)
        rate = self.rows / dt
        computed = self.done - self.skipped
        parts = []
        if self.total:
            frac = min(1.0, self.done / self.total)
            fill = int(round(frac * self.width))
            parts.append("[" + "#" * fill + "-" * (self.width - fill) + "]")
            parts.append(f"{self.done}/{self.total} chunks {100 * frac:3.0f}%")
            left = self.total - self.done
            eta = dt / computed * left if computed else float("nan")
            parts.append(f"{_fmt_rate(rate)} rows/s ETA {_fmt_time(eta)}")
        else:
            parts.append(f"{self.done} chunks  {_fmt_rate(rate)} rows/s  {_fmt_time(dt)}")
        if self.skipped:
            parts.append(f"({self.skipped} resumed)")
        if self.desc:
            parts.append(self.desc)
        return "  ".join(parts)

    def _draw(self, force: bool = False) -> None:
        if not self.enabled:
            return
        now = time.perf_counter()
        if not force and now - self._last < self.min_interval and self.done != self.total:
            return
        self._last = now
        self.stream.write("\r" + self.line() + "\x1b[K")
        self.stream.flush()

    def close(self) -> None:
        if self.enabled:
            self._draw(force=True)
            self.stream.write("\n")
            self.stream.flush()
