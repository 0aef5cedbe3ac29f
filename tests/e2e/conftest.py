"""Fixtures of the browser end-to-end tests: a real ``tennislab app`` server and headless Chromium.

The tests are marked ``e2e`` and skip cleanly when Playwright or a Chromium
binary is missing (``make test`` without a browser still passes).  The browser
is the system's (Debian ``chromium``; override with ``TENNISLAB_CHROMIUM``),
driven through Playwright's ``executable_path`` (never ``playwright install``).
Pages are opened at a desktop width (1400 px) and a phone's (390 px).
Screenshots go to ``out/screenshots/`` (kept as CI artifacts).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SHOTS = ROOT / "out" / "screenshots"
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
WIDTHS = {"1400px": (1400, 1000), "390px": (390, 844)}


def chromium_path() -> str | None:
    env = os.environ.get("TENNISLAB_CHROMIUM")
    if env:
        return env if os.path.exists(env) else None
    for name in ("chromium", "chromium-browser"):
        p = shutil.which(name)
        if p:
            return p
    return "/usr/bin/chromium" if os.path.exists("/usr/bin/chromium") else None


def start_server():
    """Start ``tennislab app --port 0``; returns (process, base URL) once it prints its URL."""
    pytest.importorskip("fastapi")
    pytest.importorskip("uvicorn")
    proc = subprocess.Popen(
        [sys.executable, "-m", "tennislab", "app", "--host", "127.0.0.1", "--port", "0"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 90
    lines = []
    while time.monotonic() < deadline:
        line = proc.stderr.readline()
        if not line:
            break
        lines.append(line)
        m = re.search(r"(http://\S+?)/\s", line)
        if m:
            return proc, m.group(1)
    proc.kill()
    pytest.fail("tennislab app did not start:\n" + "".join(lines))


@pytest.fixture(scope="session")
def server():
    """``tennislab app`` started as a subprocess on a free loopback port; yields its base URL."""
    proc, url = start_server()
    yield url
    proc.terminate()
    try:
        _, err = proc.communicate(timeout=15)
    except subprocess.TimeoutExpired:
        proc.kill()
        _, err = proc.communicate()
    assert "Traceback" not in (err or ""), err


@pytest.fixture(scope="session")
def browser():
    sync_api = pytest.importorskip("playwright.sync_api")
    exe = chromium_path()
    if exe is None:
        pytest.skip("no chromium binary (apt-get install chromium, or set TENNISLAB_CHROMIUM)")
    with sync_api.sync_playwright() as pw:
        b = pw.chromium.launch(executable_path=exe, args=CHROMIUM_ARGS)
        yield b
        b.close()


def _page(browser, base, size, tag):
    ctx = browser.new_context(viewport={"width": size[0], "height": size[1]}, accept_downloads=True)
    pg = ctx.new_page()
    errors: list[str] = []
    pg.on("pageerror", lambda e: errors.append(str(e)))
    pg.on(
        "console",
        lambda m: (
            errors.append(m.text)
            if m.type == "error" and "status of 4" not in m.text and "status of 5" not in m.text
            else None
        ),
    )
    pg.base = base
    pg.width = size[0]
    pg.snap = lambda name: screenshot(pg, f"{name}-{tag}")
    return ctx, pg, errors


@pytest.fixture(params=list(WIDTHS))
def page(request, browser, server):
    """A fresh page at 1400 px and at 390 px, JS errors collected (a test fails on any uncaught error)."""
    ctx, pg, errors = _page(browser, server, WIDTHS[request.param], request.param)
    yield pg
    ctx.close()
    assert not errors, errors


@pytest.fixture
def wide_page(browser, server):
    """A fresh page at 1400 px only (for the tests whose subject is not the layout)."""
    ctx, pg, errors = _page(browser, server, WIDTHS["1400px"], "1400px")
    yield pg
    ctx.close()
    assert not errors, errors


def screenshot(pg, name: str) -> Path:
    SHOTS.mkdir(parents=True, exist_ok=True)
    p = SHOTS / f"{name}.png"
    pg.screenshot(path=str(p), full_page=True)
    return p
