"""The report in Chromium at 1400 px and at 390 px: figures fill the page on a desktop; on a phone they
keep a readable scale and scroll sideways inside their box, the page itself never wider than the screen.
Screenshots: out/screenshots/report-*.png."""

from __future__ import annotations

import pytest

from tennislab.report import build as B
from tennislab.report import html as H

from .conftest import WIDTHS, screenshot

pytestmark = pytest.mark.e2e


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    B.build_report(str(out), progress=None, strict=True, only=["line-calling", "flight"])
    return out / "index.html"


@pytest.mark.parametrize("tag", list(WIDTHS))
def test_report_figures_readable_at_both_widths(browser, report, tag):
    w, h = WIDTHS[tag]
    ctx = browser.new_context(viewport={"width": w, "height": h})
    pg = ctx.new_page()
    try:
        pg.goto(report.as_uri())
        assert pg.evaluate("document.documentElement.scrollWidth") <= w  # the page never scrolls sideways
        imgs = pg.eval_on_selector_all(
            "figure img", "els => els.map(e => [e.getBoundingClientRect().width, e.naturalWidth])"
        )
        assert len(imgs) == 2
        for shown, natural in imgs:
            if w >= 1000:
                assert shown >= 0.75 * min(natural, 1000), (shown, natural)  # the figure uses the page
            else:
                assert shown == pytest.approx(H.FIGURE_MIN_PX, abs=3), shown  # readable (+ border)
                assert shown / natural >= 0.45, (shown, natural)  # 10-point text no smaller than ~8-9 px
        if w < 1000:
            boxes = pg.eval_on_selector_all("figure", "els => els.map(e => [e.scrollWidth, e.clientWidth])")
            assert all(sw > cw for sw, cw in boxes)  # the figure's own box scrolls
            hint = pg.eval_on_selector("figure figcaption", "e => getComputedStyle(e, '::before').content")
            assert "scroll sideways" in hint
        screenshot(pg, f"report-{tag}")
    finally:
        ctx.close()
