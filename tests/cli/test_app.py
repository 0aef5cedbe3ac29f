"""``tennislab app`` command: defaults, bad flags, missing optional dependencies, a real server."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request

import pytest

from tennislab.cli import build_parser, main


def test_defaults_bind_loopback():
    args = build_parser().parse_args(["app"])
    assert args.host == "127.0.0.1" and args.port == 8000


def test_allowed_hosts():
    pytest.importorskip("fastapi")
    from tennislab.cli.app import allowed_hosts

    assert "127.0.0.1" in allowed_hosts("127.0.0.1") and "*" not in allowed_hosts("127.0.0.1")
    assert "localhost" in allowed_hosts("localhost")
    assert allowed_hosts("0.0.0.0") == ["*"]
    assert allowed_hosts("127.0.0.1", ["box.local"])[-1] == "box.local"


@pytest.mark.parametrize("port", ["0", "70000", "-1"])
def test_bad_port(port, capsys):
    assert main(["app", "--port", port]) == 2
    assert "--port" in capsys.readouterr().err


def test_missing_optional_dependencies(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "uvicorn", None)
    assert main(["app", "--port", "8123"]) == 2
    err = capsys.readouterr().err
    assert "tennislab[app]" in err and "Traceback" not in err


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_real_server_on_loopback():
    """Start ``tennislab app`` for real; the API answers on 127.0.0.1 and refuses a foreign Host header."""
    pytest.importorskip("fastapi")
    pytest.importorskip("uvicorn")
    port = _free_port()
    proc = subprocess.Popen(
        [sys.executable, "-m", "tennislab", "app", "--port", str(port)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    try:
        url = f"http://127.0.0.1:{port}"
        deadline = time.time() + 60
        while True:
            try:
                meta = json.loads(urllib.request.urlopen(url + "/api/meta", timeout=2).read())
                break
            except OSError:
                assert proc.poll() is None and time.time() < deadline, "server did not start"
                time.sleep(0.2)
        assert meta["version"]
        req = urllib.request.Request(url + "/api/meta", headers={"Host": "attacker.example"})
        with pytest.raises(urllib.error.HTTPError) as exc:
            urllib.request.urlopen(req, timeout=5)
        assert exc.value.code == 400
        # the port is bound on loopback only (Linux: LISTEN sockets in /proc/net/tcp, 127.0.0.1 = 0100007F)
        if os.path.exists("/proc/net/tcp"):
            conns = [
                ln
                for ln in open("/proc/net/tcp").read().splitlines()[1:]
                if ln.split()[1].endswith(f":{port:04X}") and ln.split()[3] == "0A"
            ]
            assert conns and all(ln.split()[1].startswith("0100007F") for ln in conns)
    finally:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
