"""HTML pieces of the report: a self-contained page (inline CSS, no scripts, no external links).

Figures are embedded as PNG data URIs (:func:`tennislab.plot.save.figure_data_uri`), so the page
is one file that can be mailed, served or opened from a USB stick with nothing beside it.
"""

from __future__ import annotations

import html
import math
from dataclasses import dataclass, field

#: width [CSS px] a figure keeps on a narrow screen (it scrolls sideways there): its labels about 11 px
#: (10-point text at the figures' 130 dpi is 18 px at full size; a 10-13 inch figure is 1300-1700 px)
FIGURE_MIN_PX = 800

CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, "DejaVu Sans", sans-serif; margin: 0;
       color: #1b1b1b; background: #f7f7f4; line-height: 1.45; }
header { background: #234d2c; color: #fff; padding: 1em 2em; }
header h1 { margin: 0 0 0.2em; }
header p { margin: 0; opacity: 0.85; }
main { max-width: 1100px; margin: 0 auto; padding: 1em 2em 3em; }
nav.toc { background: #fff; border: 1px solid #ddd; padding: 0.5em 1em; margin: 1em 0; }
nav.toc a { margin-right: 1.2em; }
section { background: #fff; border: 1px solid #ddd; border-radius: 6px; padding: 0.5em 1.5em 1em; margin: 1.2em 0; }
h2 { color: #234d2c; border-bottom: 2px solid #3a7d44; padding-bottom: 0.2em; }
figure { margin: 1em 0; text-align: center; }
figure img { max-width: 100%; border: 1px solid #eee; }
figcaption { font-size: 0.9em; color: #444; margin-top: 0.3em; }
.tablewrap { overflow-x: auto; }
table { border-collapse: collapse; margin: 0.8em 0; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 3px 8px; text-align: right; }
th { background: #eef3ee; }
td.l, th.l { text-align: left; }
tr.paper td { color: #555; background: #fafafa; }
.note { font-size: 0.9em; color: #444; }
.unavailable { background: #fff8e1; border: 1px solid #e0c060; padding: 0.7em 1em; }
.failed { background: #fdecea; border: 1px solid #e08080; padding: 0.7em 1em; }
.caveats { background: #f3f6fb; border-left: 4px solid #6b8fc7; padding: 0.4em 1em; margin: 0.8em 0;
            font-size: 0.9em; }
.caveats ul { margin: 0.2em 0 0.2em 1.2em; padding: 0; }
.kpi { display: inline-block; background: #eef3ee; border-radius: 6px; padding: 0.4em 0.9em;
       margin: 0.2em 0.4em 0.2em 0; }
.kpi b { font-size: 1.25em; }
footer { font-size: 0.8em; color: #666; text-align: center; margin: 2em 0; }
/* a phone: the figures keep a readable scale (about 11 px text) and scroll sideways inside their box */
@media (max-width: 760px) {
  header, main { padding-left: 0.7em; padding-right: 0.7em; }
  section { padding: 0.4em 0.7em 0.8em; }
  figure { overflow-x: auto; }
  figure img { max-width: none; width: FIGURE_MIN_PX; }
  figcaption::before { content: "(scroll sideways for the whole figure) "; }
}
""".replace("FIGURE_MIN_PX", f"{FIGURE_MIN_PX}px")


def esc(s) -> str:
    return html.escape(str(s), quote=True)


def num(x, digits: int = 2) -> str:
    """A number for a table cell ('-' for None/NaN)."""
    if x is None:
        return "–"
    try:
        f = float(x)
    except (TypeError, ValueError):
        return esc(x)
    if not math.isfinite(f):
        return "–"
    return f"{f:.{digits}f}"


def rng(pair, digits: int = 1) -> str:
    """A [min, max] range as 'a – b'."""
    if pair is None:
        return "–"
    a, b = pair
    return f"{num(a, digits)} – {num(b, digits)}"


def table(header: list[str], rows: list[list], row_classes: list[str] | None = None, left_cols: int = 1) -> str:
    """An HTML table; cells are escaped unless given as :class:`Raw`."""

    def cell(tag, v, i):
        cls = ' class="l"' if i < left_cols else ""
        return f"<{tag}{cls}>{v.html if isinstance(v, Raw) else esc(v)}</{tag}>"

    out = ['<div class="tablewrap"><table>', "<tr>" + "".join(cell("th", h, i) for i, h in enumerate(header)) + "</tr>"]
    for k, r in enumerate(rows):
        cls = f' class="{row_classes[k]}"' if row_classes and row_classes[k] else ""
        out.append(f"<tr{cls}>" + "".join(cell("td", v, i) for i, v in enumerate(r)) + "</tr>")
    out.append("</table></div>")
    return "\n".join(out)


@dataclass(frozen=True)
class Raw:
    """Trusted HTML (built by this package, never from user text)."""

    html: str


def figure(path: str, caption: str) -> str:
    return f'<figure><img src="{esc(path)}" alt="{esc(caption)}"><figcaption>{esc(caption)}</figcaption></figure>'


def caveats(items) -> str:
    """A "Caveats" box listing what a model leaves out ('' when there is nothing to say)."""
    lines = [str(c) for c in items or () if str(c).strip()]
    if not lines:
        return ""
    body = "".join(f"<li>{esc(c)}</li>" for c in lines)
    return f'<div class="caveats"><b>Caveats</b><ul>{body}</ul></div>'


def para(text: str, cls: str = "") -> str:
    c = f' class="{cls}"' if cls else ""
    return f"<p{c}>{esc(text)}</p>"


def kpi(label: str, value: str) -> str:
    return f'<span class="kpi">{esc(label)}: <b>{esc(value)}</b></span>'


@dataclass
class Section:
    """One section of the report: an anchor, a title and HTML body parts."""

    key: str
    title: str
    parts: list[str] = field(default_factory=list)
    status: str = "ok"  # ok | unavailable | failed
    seconds: float = 0.0

    def add(self, *parts: str) -> Section:
        self.parts.extend(parts)
        return self

    def render(self) -> str:
        return (
            f'<section id="{esc(self.key)}" data-status="{esc(self.status)}">\n<h2>{esc(self.title)}</h2>\n'
            + "\n".join(self.parts)
            + "\n</section>"
        )


def page(title: str, subtitle: str, sections: list[Section], footer: str, intro: str = "") -> str:
    toc = " ".join(f'<a href="#{esc(s.key)}">{esc(s.title)}</a>' for s in sections)
    body = "\n".join(s.render() for s in sections)
    return f"""<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{esc(title)}</title>
<style>{CSS}</style>
</head>
<body>
<header><h1>{esc(title)}</h1><p>{esc(subtitle)}</p></header>
<main>
<nav class="toc">{toc}</nav>
{intro}
{body}
<footer>{esc(footer)}</footer>
</main>
</body>
</html>
"""
