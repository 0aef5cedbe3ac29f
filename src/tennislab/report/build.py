"""``tennislab report --out DIR``: the coach-facing report, one self-contained HTML file.

Sections (:data:`SECTIONS`, each a function ``fn(ctx) -> None`` that fills a
:class:`~tennislab.report.html.Section`):

* ``serve-windows`` - serve windows of the players; Table 1 side by side with the paper
  (Grosen, Kousted & Treichel 2021)
* ``peak-spin`` - speed and spin vs impact angle, the peak-spin angle per player (the paper's
  Figure 5) and the Monte Carlo margin of error
* ``optimum-serves`` - the optimum flat and topspin serves drawn on the court
* ``line-calling`` - a line call from a synthetic track: the mark against the line
* ``launcher-drill`` - a launcher drill drawn on the court with its settings table
* ``flight`` - the flight engine's aero models compared

The page is one file: figures are embedded as PNG data URIs (:meth:`Context.save`), so it can be
mailed, served or opened offline with nothing beside it.  It is written atomically, last, with the
user's default permissions (``0644`` with the usual umask).  A section that needs a module that is
not installed (``ImportError``) says "not available"; a section that fails is reported as failed
(with the error) and the rest of the report is still written (``strict=True`` raises instead).
Progress goes to stderr per section.

``players`` (:func:`build_report`): the player profiles the serve sections study (default the
three players of Grosen, Kousted & Treichel 2021); ``tennislab report --player FILE.toml`` puts
one's own player first.
"""

from __future__ import annotations

import os
import sys
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field

import tennislab.report.flight_section as flight_section
import tennislab.report.html as H
import tennislab.report.launcher_section as launcher_section
import tennislab.report.linecall_section as linecall_section
import tennislab.report.serve_sections as serve_sections
from tennislab import __version__
from tennislab.errors import InputError
from tennislab.io.files import atomic_write, check_output_dir, check_output_path
from tennislab.plot import close_figure, figure_data_uri
from tennislab.serve.players import SEED_PLAYERS, PlayerProfile, get_player

#: (key, title, section function) in report order
SECTIONS: list[tuple[str, str, Callable]] = [
    ("serve-windows", "Serve windows of the players (Table 1)", serve_sections.windows),
    ("peak-spin", "Peak spin and margin of error", serve_sections.peak_spin),
    ("optimum-serves", "Optimum serves on the court", serve_sections.optimum),
    ("line-calling", "Line calling: the mark against the line", linecall_section.linecall),
    ("launcher-drill", "Launcher drill", launcher_section.drill),
    ("flight", "Flight engine: aerodynamic models compared", flight_section.flight),
]
SECTION_KEYS = tuple(k for k, _, _ in SECTIONS)

INTRO = H.para(
    "How to read this report: the serve sections reproduce a published study of which racket angles make a "
    "serve go in (Grosen, Kousted & Treichel 2021), for the players below, and put our numbers beside the "
    "paper's where the paper has them; the line-calling section shows how a Hawk-Eye-style system decides a "
    "close ball and how sure it can be; the launcher section is a ready training drill with the machine "
    "settings to dial. Every number was computed by tennislab when this page was made; angles in degrees, "
    "speeds in m/s or km/h, spin in rpm. Boxes marked \u201cCaveats\u201d say what a model leaves out, next to "
    "its numbers.",
    "note",
)


@dataclass
class Context:
    """What a section function gets: its section, the players, shared results, progress."""

    out: str
    section: H.Section | None = None
    shared: dict = field(default_factory=dict)
    progress: Callable[[str], None] | None = None
    figures: list = field(default_factory=list)
    players: tuple = ()

    def save(self, fig, name: str) -> str:
        """Embed a Matplotlib figure: returns a PNG data URI for ``<img src>`` (``name`` labels it in
        the summary; no file is written) and closes the figure."""
        try:
            uri = figure_data_uri(fig)
        finally:
            close_figure(fig)
        self.figures.append(name)
        return uri

    def log(self, msg: str) -> None:
        if self.progress:
            self.progress(f"        {msg}")

    def caveats(self, obj) -> None:
        """Add the caveats of a result (``obj.to_dict()["caveats"]``), a dict with ``caveats``, or a
        list of sentences to the current section, next to its numbers."""
        if self.section is None:
            return
        box = H.caveats(caveats_of(obj))
        if box:
            self.section.add(box)


def caveats_of(obj) -> list[str]:
    """The caveat sentences of a result object, a dict (key ``caveats``) or a list of sentences."""
    if obj is None:
        return []
    if hasattr(obj, "to_dict"):
        obj = obj.to_dict()
    if isinstance(obj, dict):
        obj = obj.get("caveats") or []
    if isinstance(obj, str):
        return [obj]
    return [str(c) for c in obj if str(c).strip()]


def _stderr(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def index_path(out: str) -> str:
    """The HTML file written for ``out``: ``out`` itself when it ends in ``.html``, else ``out/index.html``."""
    return out if out.lower().endswith((".html", ".htm")) else os.path.join(out, "index.html")


def _players(players) -> tuple[PlayerProfile, ...]:
    chosen = SEED_PLAYERS if players is None else players
    if isinstance(chosen, (str, PlayerProfile)):
        chosen = (chosen,)
    return tuple(get_player(p) for p in chosen)


def _player_box(players: tuple[PlayerProfile, ...]) -> str:
    rows = [[p.name, H.num(p.impact_height, 2), H.num(p.racket_speed, 1)] for p in players]
    return "<h3>Players</h3>" + H.table(["player", "impact height [m]", "racket speed [m/s]"], rows)


def build_report(
    out: str,
    *,
    progress=_stderr,
    strict: bool = False,
    only: list[str] | None = None,
    players=None,
) -> dict:
    """Write the report to ``out`` (a directory -> ``out/index.html``, or a file ending in ``.html``);
    returns a summary dict.

    ``progress``: callable taking one line (default: stderr; ``None`` for silence).  ``only``: section
    keys to build (default all).  ``players``: player names or :class:`~tennislab.serve.players.PlayerProfile`
    profiles for the serve sections (default the paper's three).  Returns ``{"index": path,
    "sections": {key: status}, "figures": [...], "seconds": total, "players": [...]}``.
    """
    index = index_path(out)
    if index == out:
        check_output_path("out", out)
    else:
        check_output_dir("out", out)
    unknown = [k for k in only or () if k not in SECTION_KEYS]
    if unknown:
        raise InputError(f"only: unknown section {unknown[0]!r}; allowed: {', '.join(SECTION_KEYS)}")
    plist = _players(players)
    if index != out:
        os.makedirs(out, exist_ok=True)
    t_all = time.perf_counter()
    ctx = Context(out=os.path.dirname(index) or ".", progress=progress, players=plist)
    chosen = [s for s in SECTIONS if only is None or s[0] in only]
    sections = []
    for i, (key, title, fn) in enumerate(chosen, 1):
        sec = H.Section(key, title)
        ctx.section = sec
        if progress:
            progress(f"[{i}/{len(chosen)}] {title} ...")
        t0 = time.perf_counter()
        try:
            fn(ctx)
        except ImportError as exc:
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
        "Serve windows, spin, line calling and launcher drills - computed by tennislab from published models "
        "(Grosen, Kousted & Treichel 2021; Deng 2014; Wójcicki, Pucilowski & Kulesza)",
        sections,
        footer,
        INTRO + _player_box(plist),
    )
    atomic_write(index, lambda fh: fh.write(doc))
    if progress:
        progress(f"report: {index} ({len(ctx.figures)} figures embedded, {total:.1f} s)")
    return {
        "index": index,
        "sections": {s.key: s.status for s in sections},
        "figures": list(ctx.figures),
        "seconds": total,
        "players": [p.name for p in plist],
    }
