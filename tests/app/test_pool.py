"""A real server (``tennislab app`` in a subprocess): work whose client has gone is cancelled, and
abandoned requests do not starve the next ones (issue: after 16 abandoned 1 MB line calls the next
flight waited 17 s)."""

from __future__ import annotations

import json
import socket
import time
import urllib.request
from urllib.parse import urlsplit

import numpy as np

from tennislab.app import features


def big_track(n_bytes: int = 990_000) -> str:
    """The example track resampled to about ``n_bytes`` of CSV (a 1 MB line call)."""
    data, _ = features.synthetic_track()
    row = "0.000000,0.00000,0.00000,0.00000,0.003\n"
    n = n_bytes // len(row)
    t = np.linspace(data[0, 0], data[-1, 0], n)
    cols = [np.interp(t, data[:, 0], data[:, i]) for i in (1, 2, 3)]
    return "t,x,y,z,sigma\n" + "".join(
        f"{a:.6f},{b:.5f},{c:.5f},{d:.5f},0.003\n" for a, b, c, d in zip(t, *cols, strict=True)
    )


def send(url: str, path: str, body: dict) -> socket.socket:
    """POST ``body`` on a raw socket and return the socket without reading the answer."""
    u = urlsplit(url)
    data = json.dumps(body).encode()
    s = socket.create_connection((u.hostname, u.port), timeout=10)
    head = (
        f"POST {path} HTTP/1.1\r\nHost: {u.netloc}\r\nContent-Type: application/json\r\n"
        f"Content-Length: {len(data)}\r\nConnection: close\r\n\r\n"
    )
    s.sendall(head.encode() + data)
    return s


def get_json(url: str, path: str, body: dict | None = None, timeout: float = 60):
    req = urllib.request.Request(
        url + path,
        data=None if body is None else json.dumps(body).encode(),
        headers={"Content-Type": "application/json"},
    )
    with urllib.request.urlopen(req, timeout=timeout) as r:
        return json.loads(r.read())


def drill(n: int) -> dict:
    return {"name": "slow", "shots": [{"target_x": 8 - 0.05 * i, "target_y": 0.1 * (i % 20) - 1} for i in range(n)]}


def test_abandoned_requests_are_cancelled_and_do_not_starve_others(live):
    track = big_track()
    socks = [send(live, "/api/launcher/drill", drill(50)) for _ in range(8)]
    socks += [send(live, "/api/linecall", {"csv": track}) for _ in range(8)]
    time.sleep(0.5)  # the bodies are in
    for s in socks:
        s.close()  # the clients go away
    t0 = time.monotonic()
    out = get_json(live, "/api/flight", {})
    flight_s = time.monotonic() - t0
    assert out["landing"]["x"] > 0
    assert flight_s < 5, flight_s
    deadline = time.monotonic() + 20
    while True:
        pool = get_json(live, "/api/meta")["pool"]
        if (pool["waiting"] == 0 and not pool["running"]) or time.monotonic() > deadline:
            break
        time.sleep(0.2)
    assert pool["waiting"] == 0 and pool["running"] == [], pool
    assert pool["cancelled"] >= 12, pool  # (16 requests, a few may finish before they are noticed)
    assert pool["done"] <= 1 + 4 + 2, pool
    # the server is free: a new 50-shot drill is computed at once, not after 15 abandoned jobs
    t0 = time.monotonic()
    assert get_json(live, "/api/launcher/drill", drill(50))["check"]["ok"] in (True, False)
    assert time.monotonic() - t0 < 30
    assert get_json(live, "/api/meta")["pool"]["free"] >= 1


def test_a_workers_first_job_of_a_kind_may_load_its_kernels():
    """The first aim of a fresh install compiles its Numba kernels (over 20 s on a loaded machine): a
    worker's first job of each kind gets FIRST_RUN_EXTRA_S more; later ones keep their deadline."""
    from types import SimpleNamespace

    from tennislab.app import pool as P

    p = P.Pool.__new__(P.Pool)  # the deadline rule only: no processes
    p.deadline_s, p.deadlines_s = None, dict(P.DEADLINES_S)
    w = SimpleNamespace(seen=set())
    assert p.deadline_of("aim", w) == P.DEADLINES_S["aim"] + P.FIRST_RUN_EXTRA_S
    w.seen.add("aim")
    assert p.deadline_of("aim", w) == P.DEADLINES_S["aim"] == p.deadline_of("aim")
    assert p.deadline_of("serve", w) == P.DEADLINES_S["serve"] + P.FIRST_RUN_EXTRA_S
    p.deadline_s = 0.3  # one deadline for every job (the tests' setting) stays exact
    assert p.deadline_of("serve", SimpleNamespace(seen=set())) == 0.3
