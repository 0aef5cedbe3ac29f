"""Tests of ``tennislab report``: the HTML report, its sections, graceful degradation and the CLI."""

from __future__ import annotations

import ast
import base64
import os
import stat
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest

from tennislab.cli import main
from tennislab.io.files import new_file_mode
from tennislab.report import build as B
from tennislab.report import html as H

SRC = Path(B.__file__).resolve().parent


class _Collect(HTMLParser):
    def __init__(self):
        super().__init__()
        self.imgs, self.links, self.scripts, self.sections = [], [], 0, {}

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img":
            self.imgs.append(a["src"])
        if tag in ("a", "link") and "href" in a:
            self.links.append(a["href"])
        if tag == "script":
            self.scripts += 1
        if tag == "section":
            self.sections[a["id"]] = a["data-status"]


@pytest.fixture(autouse=True)
def _restore_player_registry():
    """Profiles registered from configuration files must not leak into other tests."""
    from tennislab.serve import players

    saved = dict(players._PLAYERS), dict(players._ALIASES)
    yield
    players._PLAYERS.clear()
    players._PLAYERS.update(saved[0])
    players._ALIASES.clear()
    players._ALIASES.update(saved[1])


def parse(path) -> _Collect:
    p = _Collect()
    with open(path) as fh:
        p.feed(fh.read())
    return p


def check_self_contained(out_dir):
    """One HTML file, figures embedded as PNG data URIs, nothing beside it, no scripts or outside links,
    readable by others (the user's umask)."""
    index = os.path.join(out_dir, "index.html")
    assert os.listdir(out_dir) == ["index.html"], os.listdir(out_dir)
    assert stat.S_IMODE(os.stat(index).st_mode) == new_file_mode()
    doc = parse(index)
    assert doc.scripts == 0
    for src in doc.imgs:
        assert src.startswith("data:image/png;base64,"), src[:40]
        png = base64.b64decode(src.split(",", 1)[1])
        assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 5000
    for href in doc.links:
        assert href.startswith("#"), href
    return doc


@pytest.fixture(scope="module")
def full_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    lines = []
    summary = B.build_report(str(out), progress=lines.append, strict=True)
    return out, summary, lines


def test_full_report_sections_and_progress(full_report):
    out, summary, lines = full_report
    doc = check_self_contained(out)
    keys = [k for k, _, _ in B.SECTIONS]
    assert list(doc.sections) == keys
    assert all(status == "ok" for status in doc.sections.values()), doc.sections
    assert len(doc.imgs) == len(summary["figures"]) >= len(keys)
    for i in range(1, len(keys) + 1):  # one start and one end line per section
        assert sum(ln.startswith(f"[{i}/{len(keys)}]") for ln in lines) == 2
    assert summary["seconds"] < 60
    assert summary["players"] == ["professional", "recreational", "junior"]


def test_report_names_the_papers_not_the_seeds(full_report):
    """User-facing text of the report's own files names the papers, never "seed 000/002"."""
    out, _, _ = full_report
    head = open(os.path.join(out, "index.html")).read().split('<section id="serve-windows"')[0]
    assert "Grosen, Kousted &amp; Treichel 2021" in head
    assert "seed" not in head.lower()
    for name in ("build.py", "flight_section.py", "html.py"):
        text = (SRC / name).read_text()
        strings = [
            n.value for n in ast.walk(ast.parse(text)) if isinstance(n, ast.Constant) and isinstance(n.value, str)
        ]
        shown = [t for t in strings if not t.startswith(("``", "Report section", "HTML pieces")) and "\n" not in t]
        assert not [t for t in shown if "seed 0" in t.lower() or "seed-0" in t.lower()], name


def test_caveats_are_rendered_next_to_the_numbers(full_report):
    out, _, _ = full_report
    html = open(os.path.join(out, "index.html")).read()
    flight = html[html.index('<section id="flight"') :]
    assert '<div class="caveats"><b>Caveats</b>' in flight and "extrapolation" in flight


def test_caveats_of_results_dicts_and_lists():
    class R:
        def to_dict(self):
            return {"x": 1, "caveats": ["placeholder ball data"]}

    assert B.caveats_of(R()) == ["placeholder ball data"]
    assert B.caveats_of({"caveats": "one"}) == ["one"]
    assert B.caveats_of(["a", " ", "b"]) == ["a", "b"]
    assert B.caveats_of({"x": 1}) == [] and B.caveats_of(None) == []
    assert H.caveats([]) == "" and "<li>a &lt;b&gt;</li>" in H.caveats(["a <b>"])


def test_build_imports_its_sections_directly_and_not_the_app():
    tree = ast.parse((SRC / "build.py").read_text())
    imported = [n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)] + [
        a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names
    ]
    assert not [m for m in imported if m.startswith("tennislab.app")]
    assert "importlib" not in imported
    for key, _, fn in B.SECTIONS:
        assert callable(fn) and fn.__module__.startswith("tennislab.report."), key


def test_report_package_does_not_load_the_app():
    code = "import sys, tennislab.report.build; print(any(m.startswith('tennislab.app') for m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_table1_beside_the_paper(full_report):
    pytest.importorskip("tennislab.serve.published")
    from tennislab.serve import published

    out, _, _ = full_report
    html = open(os.path.join(out, "index.html")).read()
    sec = html[html.index('id="serve-windows"') : html.index('id="peak-spin"')]
    for p in ("professional", "recreational", "junior"):
        for cat in ("flat", "topspin"):
            pap = published.TABLE1[p][cat]
            cells = f"<td>{pap['n']}</td><td>{H.rng(pap['beta'], 0)}</td><td>{H.rng(pap['alpha'], 0)}</td>"
            assert cells in sec, (p, cat)
    assert sec.count(">tennislab</td>") == 6 and sec.count(">paper</td>") == 6


def test_table1_rows_are_the_window_summary():
    pytest.importorskip("tennislab.serve.window")
    from tennislab.report.serve_sections import PLAYERS, table1_rows
    from tennislab.serve import window as serve_window

    ws = {p: serve_window(p, step=3.0) for p in PLAYERS}
    rows, classes = table1_rows(ws, None)
    assert len(rows) == 6 and classes == [""] * 6
    s = ws["junior"].summary()["topspin"]
    row = rows[5]
    assert row[:4] == ["junior", "topspin", "tennislab", s["n"]]
    assert row[4] == H.rng(s["beta"], 0) and row[7] == H.rng(s["speed"], 1)


def _fake(tmp_monkey, fn):
    tmp_monkey.setattr(B, "SECTIONS", [("flight", "Flight", section_ok), ("fake", "Fake", fn)])


def section_ok(ctx):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(3, 2))
    ax.plot([0, 1], [0, 1])
    ctx.section.add(H.figure(ctx.save(fig, "ok.png"), "a line"))


def section_unavailable(ctx):
    raise ImportError("fake: needs a module that is not installed")


def section_broken(ctx):
    raise RuntimeError("boom <script>")


def test_unavailable_section_degrades(tmp_path, monkeypatch):
    _fake(monkeypatch, section_unavailable)
    summary = B.build_report(str(tmp_path), progress=None)
    assert summary["sections"] == {"flight": "ok", "fake": "unavailable"}
    html = open(tmp_path / "index.html").read()
    assert "Not available in this installation" in html


def test_failed_section_is_reported_and_strict_raises(tmp_path, monkeypatch):
    _fake(monkeypatch, section_broken)
    summary = B.build_report(str(tmp_path), progress=None)
    assert summary["sections"]["fake"] == "failed"
    html = open(tmp_path / "index.html").read()
    assert "boom &lt;script&gt;" in html and "<script>" not in html
    with pytest.raises(RuntimeError):
        B.build_report(str(tmp_path / "strict"), progress=None, strict=True)
    assert not (tmp_path / "strict" / "index.html").exists()


def test_launcher_drill_section_table(tmp_path):
    summary = B.build_report(str(tmp_path), progress=None, strict=True, only=["launcher-drill"])
    html = open(tmp_path / "index.html").read()
    assert summary["figures"] == ["launcher_drill.png"] and "roller 1 [rpm]" in html
    n_rows = html.count("<tr>") - 1
    assert n_rows >= 3


def test_cli_report(tmp_path, capsys):
    assert main(["report", "--out", str(tmp_path / "r"), "--section", "flight"]) == 0
    cap = capsys.readouterr()
    assert cap.out.strip().endswith("index.html")
    assert "[1/1] Flight engine" in cap.err
    check_self_contained(tmp_path / "r")


def test_cli_report_quiet(tmp_path, capsys, monkeypatch):
    _fake(monkeypatch, section_ok)
    assert main(["report", "--out", str(tmp_path / "q"), "--section", "flight", "--quiet"]) == 0
    cap = capsys.readouterr()
    assert cap.err == "" and cap.out.strip().endswith("index.html")


def test_cli_report_bad_input(tmp_path, capsys):
    def err(*a):
        try:
            rc = main(["report", *a])
        except SystemExit as exc:  # argparse's own errors
            rc = exc.code
        assert rc == 2
        e = capsys.readouterr().err
        assert len(e.strip().splitlines()) == 1, e
        return e

    assert "--section: invalid choice: 'nope'" in err("--out", str(tmp_path), "--section", "nope")
    f = tmp_path / "file"
    f.write_text("x")
    assert "is a file" in err("--out", str(f))
    assert "is a file, not a directory" in err("--out", str(f / "r"))
    assert "is a file, not a directory" in err("--out", str(f / "r.html"))
    assert "no such file" in err("--out", str(tmp_path / "r"), "--player", str(tmp_path / "nobody.toml"))
    bad = tmp_path / "bad.toml"
    bad.write_text("impact_height = 2.5\nracket_speed = 300\n")
    assert "racket_speed: 300 m/s is outside" in err("--out", str(tmp_path / "r"), "--player", str(bad))
    assert sorted(os.listdir(tmp_path)) == ["bad.toml", "file"]  # nothing written


def test_cli_report_to_an_html_file_for_ones_own_player(tmp_path, capsys, monkeypatch):
    """`tennislab report --player FILE`: the player is studied first, the paper's three beside it."""
    me = tmp_path / "ana.toml"
    me.write_text('name = "Ana"\nimpact_height = 2.55\nracket_speed = 31\n')
    seen = {}

    def grab(ctx):
        seen["players"] = [(p.name, p.impact_height, p.racket_speed) for p in ctx.players]

    monkeypatch.setattr(B, "SECTIONS", [("fake", "Fake", grab)])
    out = tmp_path / "ana-report.html"
    assert main(["report", "--out", str(out), "--player", str(me), "--quiet"]) == 0
    assert capsys.readouterr().out.strip() == str(out)
    assert seen["players"][0] == ("Ana", 2.55, 31.0)
    assert [p[0] for p in seen["players"][1:]] == ["professional", "recreational", "junior"]
    html = out.read_text()
    assert '<td class="l">Ana</td><td>2.55</td><td>31.0</td>' in html
    assert sorted(os.listdir(tmp_path)) == ["ana-report.html", "ana.toml"]


def test_html_helpers_escape():
    assert H.table(["a"], [["<b>"]]) == (
        '<div class="tablewrap"><table>\n<tr><th class="l">a</th></tr>\n'
        '<tr><td class="l">&lt;b&gt;</td></tr>\n</table></div>'
    )
    assert H.num(float("nan")) == "–" and H.num(None) == "–" and H.num(1.234, 1) == "1.2"
    assert H.rng((1, 2.5), 1) == "1.0 – 2.5"
