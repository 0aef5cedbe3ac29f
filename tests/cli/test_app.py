"""``tennislab app`` command: defaults, bad flags, unknown hosts and busy ports (one line, exit 2,
before any URL), loopback addresses, missing optional dependencies, a real server."""

from __future__ import annotations

import json
import os
import re
import socket
import subprocess
import sys
import urllib.error
import urllib.request

import pytest

from tennislab.cli import build_parser, main


def test_defaults_bind_loopback():
    args = build_parser().parse_args(["app"])
    assert args.host == "127.0.0.1" and args.port == 8000 and args.workers == 2


def test_loopback_addresses():
    from tennislab.cli.app import is_loopback

    for host in ("127.0.0.1", "127.0.0.2", "127.255.255.254", "::1", "[::1]", "localhost", "LocalHost"):
        assert is_loopback(host), host
    for host in ("0.0.0.0", "::", "192.168.1.10", "10.0.0.1", "example.org"):
        assert not is_loopback(host), host
    assert is_loopback("myname", ["127.0.1.1"]) and not is_loopback("myname", ["127.0.1.1", "192.168.1.2"])


def test_allowed_hosts():
    from tennislab.cli.app import allowed_hosts

    assert "127.0.0.1" in allowed_hosts("127.0.0.1") and "*" not in allowed_hosts("127.0.0.1")
    assert "localhost" in allowed_hosts("localhost")
    assert "*" not in allowed_hosts("127.0.0.2")
    assert allowed_hosts("0.0.0.0") == ["*"]
    assert allowed_hosts("127.0.0.1", ["box.local"])[-1] == "box.local"


@pytest.mark.parametrize(
    "args, flag", [(["--port", "70000"], "--port"), (["--port", "-1"], "--port"), (["--workers", "0"], "--workers")]
)
def test_bad_flags(args, flag, capsys):
    assert main(["app", *args]) == 2
    err = capsys.readouterr().err
    assert flag in err and len(err.strip().splitlines()) == 1


def test_unresolvable_host_is_one_line_and_exit_2(capsys):
    assert main(["app", "--host", "no-such-host.invalid", "--port", "0"]) == 2
    out, err = capsys.readouterr()
    assert err.strip().splitlines() == [err.strip()]
    assert err.startswith("tennislab app: error: --host: cannot resolve 'no-such-host.invalid'")
    assert "http://" not in out + err and "Traceback" not in err


def test_busy_port_is_one_line_and_exit_2(capsys):
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen()
        port = s.getsockname()[1]
        assert main(["app", "--port", str(port)]) == 2
    out, err = capsys.readouterr()
    want = f"--port: {port} is already in use on 127.0.0.1 (choose another port, or 0 for any free port)"
    assert err == f"tennislab app: error: {want}\n"
    assert "http://" not in out


def test_address_not_on_this_machine(capsys):
    assert main(["app", "--host", "192.0.2.1", "--port", "0"]) == 2  # TEST-NET-1: never local
    err = capsys.readouterr().err
    assert err.startswith("tennislab app: error: --host: cannot listen on 192.0.2.1") and err.count("\n") == 1


def test_missing_optional_dependencies(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "uvicorn", None)
    assert main(["app", "--port", "8123"]) == 2
    err = capsys.readouterr().err
    assert "make demo" in err and "pip install '.[app]'" in err and "Traceback" not in err


def test_real_server_on_another_loopback_address():
    """``tennislab app --host 127.0.0.2 --port 0``: no warning (loopback), the URL once the workers
    answer, the API on that address only, a foreign Host header refused."""
    pytest.importorskip("fastapi")
    pytest.importorskip("uvicorn")
    proc = subprocess.Popen(
        [sys.executable, "-m", "tennislab", "app", "--host", "127.0.0.2", "--port", "0", "--workers", "1"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        first = proc.stderr.readline()
        m = re.fullmatch(r"tennislab app: (http://127\.0\.0\.2:(\d+))/  \(Ctrl-C to stop\)\n", first)
        assert m, first  # the first line is the URL: no warning before it
        url, port = m.group(1), int(m.group(2))
        meta = json.loads(urllib.request.urlopen(url + "/api/meta", timeout=30).read())
        assert meta["version"] and meta["pool"]["workers"] == 1
        req = urllib.request.Request(url + "/api/meta", headers={"Host": "attacker.example"})
        with pytest.raises(urllib.error.HTTPError) as exc:
            urllib.request.urlopen(req, timeout=5)
        assert exc.value.code == 400
        # bound on 127.0.0.2 only (Linux: LISTEN sockets in /proc/net/tcp, 127.0.0.2 = 0200007F)
        if os.path.exists("/proc/net/tcp"):
            with open("/proc/net/tcp") as f:
                rows = [ln.split() for ln in f.read().splitlines()[1:]]
            conns = [r for r in rows if r[1].endswith(f":{port:04X}") and r[3] == "0A"]
            assert conns and all(r[1].startswith("0200007F") for r in conns)
    finally:
        proc.terminate()
        try:
            _, err = proc.communicate(timeout=15)
        except subprocess.TimeoutExpired:
            proc.kill()
            _, err = proc.communicate()
    assert "Traceback" not in err and "warning" not in err, err
