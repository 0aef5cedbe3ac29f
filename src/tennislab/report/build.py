"""``tennislab report --out DIR``: the coach-facing HTML report (``DIR/index.html`` + PNG figures).

Sections (registry :data:`SECTIONS`, each a function ``fn(ctx) -> None`` that
fills a :class:`~tennislab.report.html.Section`):

* ``serve-windows`` - serve windows of the three seed-000 players; Table 1
  side by side with the paper (Grosen, Kousted & Treichel 2021)
* ``peak-spin`` - speed and spin vs impact angle, the peak-spin angle per
  player (the paper's Figure 5) and the Monte Carlo margin of error
* ``optimum-serves`` - the optimum flat and topspin serves drawn on the court
* ``line-calling`` - a line call from a synthetic track: the mark against the line
* ``launcher-drill`` - a launcher drill drawn on the court with its settings table
* ``flight`` - the flight engine's aero models compared (always available)

A section whose module is not installed says "not available"; a section that
fails is reported as failed (with the error) and the rest of the report is still
written (``strict=True`` raises instead).  Progress goes to stderr per section.
Figures are written atomically; ``index.html`` last.
"""

from __future__ import annotations

import importlib
import os
import sys
import time
import traceback
from dataclasses import dataclass, field

import matplotlib

matplotlib.use("Agg")

from tennislab import __version__
from tennislab.app.services import Unavailable
from tennislab.io.files import atomic_write
from tennislab.plot.save import save_figure
from tennislab.report import html as H

#: (key, title, "module:function") in report order
SECTIONS = [
    ("serve-windows", "Serve windows of the three players (Table 1)", "tennislab.report.serve_sections:windows"),
    ("peak-spin", "Peak spin and margin of error", "tennislab.report.serve_sections:peak_spin"),
    ("optimum-serves", "Optimum serves on the court", "tennislab.report.serve_sections:optimum"),
    ("line-calling", "Line calling: the mark against the line", "tennislab.report.linecall_section:linecall"),
    ("launcher-drill", "Launcher drill", "tennislab.report.launcher_section:drill"),
    ("flight", "Flight engine: aerodynamic models compared", "tennislab.report.flight_section:flight"),
]


INTRO = H.para(
    "How to read this report: the serve sections reproduce a published study of which racket angles make a "
    "serve go in (Grosen, Kousted & Treichel 2021), for a professional, a recreational and a junior player, and "
    "put our numbers beside the paper's; the line-calling section shows how a Hawk-Eye-style system decides a "
    "close ball and how sure it can be; the launcher section is a ready training drill with the machine "
    "settings to dial. Every number was computed by tennislab when this page was made; angles in degrees, "
    "speeds in m/s or km/h, spin in rpm.",
    "note",
)


@dataclass
class Context:
    """What a section function gets: the output directory, its section, shared results, progress."""

    out: str
    section: H.Section | None = None
    shared: dict = field(default_factory=dict)
    progress: object = None
    figures: list = field(default_factory=list)

    def save(self, fig, name: str) -> str:
        """Save a Matplotlib figure as ``DIR/name`` (PNG); returns the relative path for the HTML."""
        import matplotlib.pyplot as plt

        save_figure(fig, os.path.join(self.out, name))
        plt.close(fig)
        self.figures.append(name)
        return name

    def log(self, msg: str) -> None:
        if self.progress:
            self.progress(f"        {msg}")


def _stderr(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def _resolve(spec: str):
    mod, fn = spec.split(":")
    return getattr(importlib.import_module(mod), fn)


def build_report(out: str, *, progress=_stderr, strict: bool = False, only: list[str] | None = None) -> dict:
    """Write the report into directory ``out``; returns a summary dict.

    ``progress``: callable taking one line (default: stderr; ``None`` for silence).
    ``only``: section keys to build (default all).  Returns ``{"index": path,
    "sections": {key: status}, "figures": [...], "seconds": total}``.
    """
    os.makedirs(out, exist_ok=True)
    t_all = time.perf_counter()
    ctx = Context(out=out, progress=progress)
    chosen = [s for s in SECTIONS if only is None or s[0] in only]
    sections = []
    for i, (key, title, spec) in enumerate(chosen, 1):
        sec = H.Section(key, title)
        ctx.section = sec
        if progress:
            progress(f"[{i}/{len(chosen)}] {title} ...")
        t0 = time.perf_counter()
        try:
            _resolve(spec)(ctx)
        except (Unavailable, ImportError) as exc:
            sec.status = "unavailable"
            sec.parts = [f'<p class="unavailable">Not available in this installation: {H.esc(exc)}</p>']
        except Exception as exc:
            if strict:
                raise
            sec.status = "failed"
            sec.parts = [
                f'<p class="failed">This section could not be computed: {H.esc(type(exc).__name__)}: {H.esc(exc)}</p>'
            ]
            if progress:
                progress(traceback.format_exc().rstrip())
        sec.seconds = time.perf_counter() - t0
        if progress:
            progress(f"[{i}/{len(chosen)}] {title}: {sec.status} ({sec.seconds:.1f} s)")
        sections.append(sec)
    total = time.perf_counter() - t_all
    footer = f"tennislab {__version__} - generated in {total:.1f} s - sections: " + ", ".join(
        f"{s.key} {s.status}" for s in sections
    )
    doc = H.page(
        "tennislab report",
        "Serve windows, spin, line calling and launcher drills - computed by tennislab from the seed papers' models",
        sections,
        footer,
        INTRO,
    )
    index = os.path.join(out, "index.html")
    atomic_write(index, lambda fh: fh.write(doc))
    if progress:
        progress(f"report: {index} ({len(ctx.figures)} figures, {total:.1f} s)")
    return {
        "index": index,
        "sections": {s.key: s.status for s in sections},
        "figures": list(ctx.figures),
        "seconds": total,
    }
