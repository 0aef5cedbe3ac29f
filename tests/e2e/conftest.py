"""Fixtures of the browser end-to-end tests: a real ``tennislab app`` server and headless Chromium.

The tests are marked ``e2e`` and skip cleanly when Playwright or a Chromium
binary is missing (``make test`` without a browser still passes).  The browser
is the system's (Debian ``chromium``; override with ``TENNISLAB_CHROMIUM``),
driven through Playwright's ``executable_path`` (never ``playwright install``).
Screenshots go to ``out/screenshots/`` (kept as CI artifacts).
"""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
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


def chromium_path() -> str | None:
    env = os.environ.get("TENNISLAB_CHROMIUM")
    if env:
        return env if os.path.exists(env) else None
    for name in ("chromium", "chromium-browser"):
        p = shutil.which(name)
        if p:
            return p
    return "/usr/bin/chromium" if os.path.exists("/usr/bin/chromium") else None


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_server(env_extra: dict | None = None):
    """Start ``tennislab app`` on a free loopback port; returns (process, base URL) once it answers."""
    pytest.importorskip("fastapi")
    pytest.importorskip("uvicorn")
    port = _free_port()
    env = {k: v for k, v in os.environ.items() if k != "TENNISLAB_APP_DISABLE"}
    env.update(env_extra or {})
    import tempfile

    log = tempfile.TemporaryFile()
    proc = subprocess.Popen(
        [sys.executable, "-m", "tennislab", "app", "--host", "127.0.0.1", "--port", str(port)],
        stdout=log,
        stderr=subprocess.STDOUT,
        env=env,
    )
    url = f"http://127.0.0.1:{port}"
    deadline = time.time() + 90
    while True:
        try:
            urllib.request.urlopen(url + "/api/meta", timeout=2).read()
            break
        except OSError:
            if proc.poll() is not None or time.time() > deadline:
                proc.kill()
                log.seek(0)
                tail = log.read().decode(errors="replace")[-2000:]
                pytest.fail(f"tennislab app did not start (exit code {proc.poll()}):\n{tail}")
            time.sleep(0.3)
    return proc, url


def stop_server(proc):
    proc.terminate()
    try:
        proc.wait(10)
    except subprocess.TimeoutExpired:
        proc.kill()


@pytest.fixture(scope="session")
def server():
    """``tennislab app`` started as a subprocess on a free loopback port; yields its base URL."""
    proc, url = start_server()
    yield url
    stop_server(proc)


@pytest.fixture(scope="session")
def degraded_server():
    """The same with serve, line calling and the launcher switched off (``TENNISLAB_APP_DISABLE``)."""
    proc, url = start_server({"TENNISLAB_APP_DISABLE": "serve,linecall,launcher"})
    yield url
    stop_server(proc)


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


def _page(browser, base):
    ctx = browser.new_context(viewport={"width": 1300, "height": 1000}, accept_downloads=True)
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
    pg.snap = lambda name: screenshot(pg, name)
    return ctx, pg, errors


@pytest.fixture
def page(browser, server):
    """A fresh page with JS errors collected (a test fails on any uncaught error)."""
    ctx, pg, errors = _page(browser, server)
    yield pg
    ctx.close()
    assert not errors, errors


@pytest.fixture
def degraded_page(browser, degraded_server):
    """A page of the server without serve, line calling and launcher."""
    ctx, pg, errors = _page(browser, degraded_server)
    yield pg
    ctx.close()
    assert not errors, errors


def screenshot(pg, name: str) -> Path:
    SHOTS.mkdir(parents=True, exist_ok=True)
    p = SHOTS / f"{name}.png"
    pg.screenshot(path=str(p), full_page=True)
    return p
