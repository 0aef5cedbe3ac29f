"""Tests of ``tennislab report``: the HTML report, its sections, graceful degradation and the CLI."""

from __future__ import annotations

import os
import re
from html.parser import HTMLParser

import pytest

from tennislab.app.services import Unavailable, availability
from tennislab.cli import main
from tennislab.report import build as B
from tennislab.report import html as H


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


def parse(path) -> _Collect:
    p = _Collect()
    with open(path) as fh:
        p.feed(fh.read())
    return p


def check_self_contained(out_dir):
    doc = parse(os.path.join(out_dir, "index.html"))
    assert doc.scripts == 0
    for src in doc.imgs:
        assert not re.match(r"^[a-z]+:", src) and not src.startswith("/"), src
        assert os.path.getsize(os.path.join(out_dir, src)) > 5000, src
        with open(os.path.join(out_dir, src), "rb") as fh:
            assert fh.read(8) == b"\x89PNG\r\n\x1a\n"
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
    avail = availability()
    expected = {
        "serve-windows": "serve",
        "peak-spin": "serve",
        "optimum-serves": "serve",
        "line-calling": "linecall",
        "launcher-drill": "launcher",
    }
    for key, status in doc.sections.items():
        assert status in ("ok", "unavailable"), (key, status)
        if key in expected:
            assert status == ("ok" if avail[expected[key]]["available"] else "unavailable"), key
    assert doc.sections["flight"] == "ok"
    for i in range(1, len(keys) + 1):  # one start and one end line per section
        assert sum(ln.startswith(f"[{i}/{len(keys)}]") for ln in lines) == 2
    assert summary["seconds"] < 60


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
    from tennislab.serve.window import serve_window

    ws = {p: serve_window(p, step=3.0) for p in PLAYERS}
    rows, classes = table1_rows(ws, None)
    assert len(rows) == 6 and classes == [""] * 6
    s = ws["junior"].summary()["topspin"]
    row = rows[5]
    assert row[:4] == ["junior", "topspin", "tennislab", s["n"]]
    assert row[4] == H.rng(s["beta"], 0) and row[7] == H.rng(s["speed"], 1)


def _fake(tmp_monkey, fn):
    tmp_monkey.setattr(
        B, "SECTIONS", [("flight", "Flight", f"{__name__}:section_ok"), ("fake", "Fake", f"{__name__}:{fn}")]
    )


def section_ok(ctx):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(3, 2))
    ax.plot([0, 1], [0, 1])
    ctx.section.add(H.figure(ctx.save(fig, "ok.png"), "a line"))


def section_unavailable(ctx):
    raise Unavailable("fake: not available in this installation (no module)")


def section_broken(ctx):
    raise RuntimeError("boom <script>")


def test_unavailable_section_degrades(tmp_path, monkeypatch):
    _fake(monkeypatch, "section_unavailable")
    summary = B.build_report(str(tmp_path), progress=None)
    assert summary["sections"] == {"flight": "ok", "fake": "unavailable"}
    html = open(tmp_path / "index.html").read()
    assert "Not available in this installation" in html


def test_failed_section_is_reported_and_strict_raises(tmp_path, monkeypatch):
    _fake(monkeypatch, "section_broken")
    summary = B.build_report(str(tmp_path), progress=None)
    assert summary["sections"]["fake"] == "failed"
    html = open(tmp_path / "index.html").read()
    assert "boom &lt;script&gt;" in html and "<script>" not in html
    with pytest.raises(RuntimeError):
        B.build_report(str(tmp_path / "strict"), progress=None, strict=True)
    assert not (tmp_path / "strict" / "index.html").exists()


def test_launcher_drill_section_table(tmp_path):
    if not availability()["launcher"]["available"]:
        pytest.skip("launcher not installed")
    B.build_report(str(tmp_path), progress=None, strict=True, only=["launcher-drill"])
    html = open(tmp_path / "index.html").read()
    assert "launcher_drill.png" in html and "roller 1 [rpm]" in html
    n_rows = html.count("<tr>") - 1
    assert n_rows >= 3


def test_cli_report(tmp_path, capsys):
    assert main(["report", "--out", str(tmp_path / "r"), "--section", "flight"]) == 0
    cap = capsys.readouterr()
    assert cap.out.strip().endswith("index.html")
    assert "[1/1] Flight engine" in cap.err
    check_self_contained(tmp_path / "r")


def test_cli_report_quiet(tmp_path, capsys, monkeypatch):
    _fake(monkeypatch, "section_ok")
    assert main(["report", "--out", str(tmp_path / "q"), "--section", "flight", "--quiet"]) == 0
    cap = capsys.readouterr()
    assert cap.err == "" and cap.out.strip().endswith("index.html")


def test_cli_report_bad_input(tmp_path, capsys):
    assert main(["report", "--out", str(tmp_path), "--section", "nope"]) == 2
    assert "--section: unknown section 'nope'" in capsys.readouterr().err
    f = tmp_path / "file"
    f.write_text("x")
    assert main(["report", "--out", str(f)]) == 2
    assert "is a file" in capsys.readouterr().err


def test_html_helpers_escape():
    assert H.table(["a"], [["<b>"]]) == (
        '<div class="tablewrap"><table>\n<tr><th class="l">a</th></tr>\n'
        '<tr><td class="l">&lt;b&gt;</td></tr>\n</table></div>'
    )
    assert H.num(float("nan")) == "–" and H.num(None) == "–" and H.num(1.234, 1) == "1.2"
    assert H.rng((1, 2.5), 1) == "1.0 – 2.5"


def test_report_without_the_optional_modules(tmp_path, monkeypatch):
    """Serve, line calling and launcher missing: their sections say so, the rest is built."""
    monkeypatch.setenv("TENNISLAB_APP_DISABLE", "serve,linecall,launcher")
    summary = B.build_report(str(tmp_path), progress=None, strict=True)
    assert summary["sections"] == {
        "serve-windows": "unavailable",
        "peak-spin": "unavailable",
        "optimum-serves": "unavailable",
        "line-calling": "unavailable",
        "launcher-drill": "unavailable",
        "flight": "ok",
    }
    doc = check_self_contained(tmp_path)
    assert doc.imgs == ["flight_models.png"]
    assert open(tmp_path / "index.html").read().count("Not available in this installation") == 5
