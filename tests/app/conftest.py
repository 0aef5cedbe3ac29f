"""One running app: helpers of the API and security tests (the `client` fixture is in tests/conftest.py)."""

from __future__ import annotations

import pytest


def start_app(*args: str, timeout: float = 90.0):
    """``tennislab app --port 0 ARGS`` as a subprocess; returns (process, base URL) once it prints its URL."""
    import os
    import re
    import subprocess
    import sys
    import time

    env = dict(os.environ)
    proc = subprocess.Popen(
        [sys.executable, "-m", "tennislab", "app", "--port", "0", *args],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )
    t0 = time.monotonic()
    lines = []
    while time.monotonic() - t0 < timeout:
        line = proc.stderr.readline()
        if not line:
            break
        lines.append(line)
        m = re.search(r"(http://\S+?)/\s", line)
        if m:
            return proc, m.group(1)
    proc.kill()
    raise AssertionError("tennislab app did not start:\n" + "".join(lines))


def stop_app(proc) -> str:
    """Stop the server; returns what it wrote on stderr after its URL."""
    import subprocess

    proc.terminate()
    try:
        _, err = proc.communicate(timeout=15)
    except subprocess.TimeoutExpired:
        proc.kill()
        _, err = proc.communicate()
    return err or ""


@pytest.fixture(scope="module")
def live():
    """A real ``tennislab app`` (uvicorn, worker processes) on a free loopback port: its base URL.
    The test fails if the server wrote a traceback."""
    pytest.importorskip("fastapi")
    pytest.importorskip("uvicorn")
    proc, url = start_app()
    yield url
    err = stop_app(proc)
    assert "Traceback" not in err, err
