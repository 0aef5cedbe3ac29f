"""Progress of long work, counted in the user's units (serves/s, flights/s, calls/s), on any stream.

Written to stderr.  On a terminal, one line redrawn in place (carriage returns); on any other stream
(a log file, a pipe, a CI job) one plain line every :data:`LOG_INTERVAL_S` seconds and a last one
at the end, so a log gets a few lines, never thousands of carriage returns.

When it is drawn (:func:`progress_mode`):

* ``"auto"`` (the default of the library and the commands): on a terminal, for work that takes
  longer than about :data:`AUTO_AFTER_S` seconds (a short job stays silent);
* ``True``: on a terminal, from the start;
* ``"always"`` (``--progress``): on any stream, from the start;
* ``False`` (``--no-progress``): never.

The environment variable ``TENNISLAB_PROGRESS=1`` makes every progress ``"always"``; ``=0`` turns it off.
"""

from __future__ import annotations

import os
import sys
import time

#: the default progress ("auto") appears once the work is expected to take longer than this [s]
AUTO_AFTER_S = 5.0
#: ... and no earlier than this [s] into the work (the first estimate of its length)
AUTO_FIRST_S = 1.0
#: seconds between two lines on a stream that is not a terminal (a log)
LOG_INTERVAL_S = 5.0
#: seconds between two redraws of a terminal line
BAR_INTERVAL_S = 0.1
MODES = ("auto", True, "always", False)


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
    return f"{r:.1f}" if r < 10 else f"{r:.0f}"


def _isatty(stream) -> bool:
    isatty = getattr(stream, "isatty", None)
    try:
        return bool(isatty and isatty())
    except (OSError, ValueError):  # a closed stream
        return False


def progress_mode(progress, stream=None) -> str | None:
    """How progress is drawn on ``stream`` (default stderr): ``"bar"`` (a terminal line redrawn in
    place), ``"lines"`` (a line every :data:`LOG_INTERVAL_S` s), ``"auto-bar"`` (a bar once the work
    is seen to be long) or None (nothing); ``progress`` is one of :data:`MODES` (module docstring)."""
    stream = stream or sys.stderr
    env = os.environ.get("TENNISLAB_PROGRESS")
    if env == "0":
        return None
    if env == "1" or progress == "always":
        return "bar" if _isatty(stream) else "lines"
    if progress is None or progress == "auto":
        return "auto-bar" if _isatty(stream) else None
    if not progress:
        return None
    return "bar" if _isatty(stream) else None


def progress_enabled(progress, stream=None) -> bool:
    """Whether ``progress`` draws anything on ``stream`` (:func:`progress_mode`)."""
    return progress_mode(progress, stream) is not None


class ProgressBar:
    """``[#####-----]  3,400/10,000 serves  34%  1.2k serves/s  ETA 00:05  desc``.

    ``total``: chunks (None: unknown, a stream); ``total_units``: the user's units of the whole job
    (``unit``: "serves", "flights", "calls"; default the chunks' rows); without it progress counts
    chunks.  Units of skipped (resumed) chunks count toward completion but not the rate.  ``mode``:
    :func:`progress_mode` (default: a bar when ``enabled``).
    """

    def __init__(
        self,
        total: int | None,
        desc: str = "",
        enabled: bool = True,
        stream=None,
        width: int = 28,
        min_interval: float = BAR_INTERVAL_S,
        *,
        unit: str = "rows",
        total_units: int | None = None,
        mode: str | None = "bar",
        log_interval: float = LOG_INTERVAL_S,
        chunk_unit: str = "chunks",
    ):
        self.total = total
        self.desc = desc
        self.mode = mode if enabled else None
        self.enabled = self.mode is not None
        self.stream = stream or sys.stderr
        self.width = width
        self.min_interval = min_interval
        self.log_interval = log_interval
        self.unit = unit
        self.chunk_unit = chunk_unit
        self.total_units = total_units
        self.done = 0
        self.rows = 0  #: units computed by this run (the rate's numerator)
        self.units_skipped = 0
        self.skipped = 0
        self.t0 = time.perf_counter()
        self._last = -float("inf")
        self._drawn = False

    # ------------------------------------------------------------------ counting
    def skip(self, n_chunks: int = 1, n_units: int = 0) -> None:
        self.done += n_chunks
        self.skipped += n_chunks
        self.units_skipped += int(n_units)
        self._draw()

    def update(self, n_rows: int, n_chunks: int = 1) -> None:
        """``n_rows`` units (rows, serves, ...) and ``n_chunks`` chunks finished."""
        self.done += n_chunks
        self.rows += int(n_rows)
        self._draw()

    # ------------------------------------------------------------------ what is said
    def fraction(self) -> float | None:
        """Share of the job done (units when their total is known, else chunks); None if unknown."""
        if self.total_units:
            return min(1.0, (self.rows + self.units_skipped) / self.total_units)
        if self.total:
            return min(1.0, self.done / self.total)
        return None

    def eta(self) -> float:
        """Seconds left (NaN before the first computed chunk)."""
        frac, dt = self.fraction(), time.perf_counter() - self.t0
        if frac is None or self.done - self.skipped <= 0:
            return float("nan")
        if self.total_units:
            computed = self.rows / self.total_units
        else:
            computed = (self.done - self.skipped) / (self.total or 1)
        left = 1.0 - frac
        return dt / computed * left if computed > 0 else float("nan")

    def line(self) -> str:
        dt = max(time.perf_counter() - self.t0, 1e-9)
        rate = self.rows / dt
        frac = self.fraction()
        parts = []
        if self.total_units:
            count = f"{self.rows + self.units_skipped:,}/{self.total_units:,} {self.unit}"
        elif self.total:
            count = f"{self.done}/{self.total} {self.chunk_unit}"
            if self.unit != "rows":
                count += f", {self.rows:,} {self.unit}"
        else:
            count = f"{self.rows:,} {self.unit}"
        if frac is not None:
            if self.mode != "lines":
                fill = int(round(frac * self.width))
                parts.append("[" + "#" * fill + "-" * (self.width - fill) + "]")
            parts.append(f"{count} {100 * frac:3.0f}%")
            parts.append(f"{_fmt_rate(rate)} {self.unit}/s")
            parts.append(f"ETA {_fmt_time(self.eta())}")
        else:
            parts.append(f"{count}  {_fmt_rate(rate)} {self.unit}/s  {_fmt_time(dt)}")
        if self.skipped:
            parts.append(f"({self.skipped} {self.chunk_unit} resumed)")
        if self.desc:
            parts.append(self.desc)
        return "  ".join(parts)

    # ------------------------------------------------------------------ drawing
    def _due(self, now: float) -> bool:
        if self.mode == "auto-bar":
            dt = now - self.t0
            if not self._drawn:
                long = dt >= AUTO_AFTER_S or (dt >= AUTO_FIRST_S and dt + self.eta() >= AUTO_AFTER_S)
                if not long:
                    return False
        interval = self.log_interval if self.mode == "lines" else self.min_interval
        return now - self._last >= interval

    def _draw(self, force: bool = False) -> None:
        if not self.enabled:
            return
        now = time.perf_counter()
        if not force and not self._due(now):
            return
        self._last = now
        self._drawn = True
        if self.mode == "lines":
            self.stream.write(self.line() + "\n")
        else:
            self.stream.write("\r" + self.line() + "\x1b[K")
        self.stream.flush()

    def close(self) -> None:
        """The last line (only where progress was shown: a short "auto" job stays silent)."""
        if not self.enabled or (self.mode == "auto-bar" and not self._drawn):
            return
        self._draw(force=True)
        if self.mode != "lines":
            self.stream.write("\n")
        self.stream.flush()
