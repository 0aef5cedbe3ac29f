"""The app answers only its own page: Host, Origin, content type, JSON depth and size, frame headers,
time limits (docs/security.md lists these promises; each is checked here)."""

from __future__ import annotations

import json
import logging
import threading
import time

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("fastapi")
pytest.importorskip("httpx")
from fastapi.testclient import TestClient
from starlette.datastructures import Headers

from tennislab.app import fields as F
from tennislab.app.server import LOOPBACK_HOSTS, Guard, create_app, host_name, json_depth

POSTS = ["/api/flight", "/api/serve", "/api/serve/window", "/api/launcher/aim", "/api/launcher/drill", "/api/linecall"]


def done(client) -> int:
    return client.get("/api/meta").json()["pool"]["done"]


def one_line_error(r, status: int) -> str:
    assert r.status_code == status, (r.status_code, r.text)
    msg = r.json()["error"]
    assert "\n" not in msg and "Traceback" not in msg and len(msg) < 300
    return msg


# ------------------------------------------------------------------ cross-site requests
@pytest.mark.parametrize("path", POSTS)
@pytest.mark.parametrize(
    "origin",
    [
        "http://evil.example",
        "null",
        "http://testserver.evil.example",
        "https://testserver",
        "http://testserver:8080",
        "http://127.0.0.1",
    ],
)
def test_foreign_origin_refused_before_any_work(client, path, origin):
    before = done(client)
    r = client.post(path, json={}, headers={"Origin": origin})
    assert one_line_error(r, 403).startswith("origin:")
    assert done(client) == before


@pytest.mark.parametrize("site", ["cross-site", "same-site"])
def test_cross_site_fetch_without_origin_refused(client, site):
    r = client.post("/api/flight", json={}, headers={"Sec-Fetch-Site": site})
    assert one_line_error(r, 403).startswith("origin:")
    assert client.get("/api/meta", headers={"Sec-Fetch-Site": site}).status_code == 403
    assert client.get("/api/linecall/sample", headers={"Sec-Fetch-Site": site}).status_code == 403


def test_the_page_itself_is_served(client):
    assert client.post("/api/flight", json={}, headers={"Origin": "http://testserver"}).status_code == 200
    r = client.post("/api/flight", json={}, headers={"Origin": "http://testserver", "Sec-Fetch-Site": "same-origin"})
    assert r.status_code == 200
    assert client.get("/api/meta", headers={"Sec-Fetch-Site": "same-origin"}).status_code == 200
    # a link to the app from elsewhere opens it (it cannot be framed)
    r = client.get("/", headers={"Sec-Fetch-Site": "cross-site"})
    assert r.status_code == 200 and r.headers["x-frame-options"] == "DENY"


def test_foreign_origin_refused_on_get_api(client):
    assert one_line_error(client.get("/api/meta", headers={"Origin": "http://evil.example"}), 403)


@pytest.mark.parametrize("path", POSTS)
@pytest.mark.parametrize(
    "ctype",
    [
        "text/plain",
        "text/plain; charset=utf-8",
        "application/x-www-form-urlencoded",
        "multipart/form-data; boundary=xyz",
        "application/json; charset=latin-1",
        "application/jsonp",
        "application/json, text/plain",
        None,
    ],
)
def test_only_json_bodies(client, path, ctype):
    """The simple content types a foreign page can send without a CORS preflight are refused."""
    headers = {} if ctype is None else {"Content-Type": ctype}
    r = client.post(path, content=b"{}", headers=headers)
    assert one_line_error(r, 415).startswith("request: expected Content-Type application/json")


def test_form_posts_refused(client):
    assert client.post("/api/flight", data={"speed_kmh": "100"}).status_code == 415
    r = client.post("/api/linecall", files={"csv": ("t.csv", b"t,x,y,z\n")})
    assert r.status_code == 415


def test_json_with_charset_accepted(client):
    r = client.post("/api/flight", content=b"{}", headers={"Content-Type": "application/json; charset=UTF-8"})
    assert r.status_code == 200


def test_cors_preflight_gets_no_permission(client):
    h = {
        "Origin": "http://evil.example",
        "Access-Control-Request-Method": "POST",
        "Access-Control-Request-Headers": "content-type",
    }
    r = client.options("/api/flight", headers=h)
    assert r.status_code in (403, 405)
    assert not any(k.lower().startswith("access-control-") for k in r.headers)
    assert client.options("/api/flight").status_code == 405
    for method in ("PUT", "DELETE", "PATCH"):
        assert client.request(method, "/api/flight", json={}).status_code == 405


# ------------------------------------------------------------------ Host header (DNS rebinding)
@pytest.mark.parametrize(
    "host, ok",
    [
        ("127.0.0.1:8000", True),
        ("localhost", True),
        ("LOCALHOST:8000", True),
        ("[::1]:8000", True),
        ("127.0.0.2:8000", True),
        ("127.255.1.9", True),
        ("evil.example", False),
        ("127.0.0.1.evil.example", False),
        ("localhost.evil.example:8000", False),
        ("", False),
        ("[::1", False),
        ("a:b:c", False),
        ("10.0.0.1", False),
    ],
)
def test_host_header(host, ok):
    guard = Guard(None, LOOPBACK_HOSTS)
    problem = guard.check("GET", "/", Headers({"host": host}))
    assert (problem is None) == ok, (host, problem)
    if not ok:
        assert problem[0] == 400 and problem[1].startswith("host:")


def _raw(*pairs: tuple[str, str]) -> Headers:
    return Headers(raw=[(k.encode(), v.encode()) for k, v in pairs])


@pytest.mark.parametrize(
    "pairs, status",
    [
        ((("host", "127.0.0.1"), ("host", "evil.example")), 400),
        ((("host", "127.0.0.1"), ("host", "127.0.0.1")), 400),
        ((("host", "127.0.0.1"), ("origin", "http://127.0.0.1"), ("origin", "http://evil.example")), 403),
        ((("host", "127.0.0.1"), ("origin", "http://evil.example"), ("origin", "http://127.0.0.1")), 403),
        ((("host", "127.0.0.1"), ("sec-fetch-site", "Cross-Site")), 403),
        ((("host", "127.0.0.1"), ("sec-fetch-site", "SAME-SITE")), 403),
        ((("host", "127.0.0.1"), ("sec-fetch-site", " cross-site ")), 403),
        ((("host", "127.0.0.1"), ("sec-fetch-site", "same-origin"), ("sec-fetch-site", "cross-site")), 403),
        # one line folding two copies (what a proxy may make of them): was served
        ((("host", "127.0.0.1"), ("sec-fetch-site", "same-origin, cross-site")), 403),
        ((("host", "127.0.0.1"), ("content-type", "application/json"), ("content-type", "text/plain")), 415),
        ((("host", "127.0.0.1"), ("origin", "HTTP://127.0.0.1")), None),
        ((("host", "127.0.0.1"), ("sec-fetch-site", "Same-Origin")), None),
    ],
)
def test_repeated_and_mixed_case_headers(pairs, status):
    """Issue 24 point 14: two Origin headers (own first, a foreign second) were served, and Sec-Fetch-Site
    was compared case-sensitively.  More than one Host or Origin is refused; fetch metadata and origins
    are compared without regard to case."""
    problem = Guard(None, LOOPBACK_HOSTS).check("POST", "/api/flight", _raw(*pairs))
    assert (problem and problem[0]) == status, problem


def test_two_origin_headers_refused_before_any_work(client):
    before = done(client)
    headers = [("Origin", "http://testserver"), ("Origin", "http://evil.example"), ("Content-Type", "application/json")]
    r = client.post("/api/flight", content=b"{}", headers=headers)
    assert one_line_error(r, 403).startswith("origin:")
    assert done(client) == before


@pytest.mark.parametrize("encoding", ["utf-16", "utf-16-le", "utf-32", "latin-1"])
def test_json_bodies_are_utf8_only(client, encoding):
    """A JSON body in UTF-16 or UTF-32 (which json.loads would guess from the bytes) is refused: 422."""
    body = json.dumps({"speed_kmh": 100, "name": "\u00e9"}, ensure_ascii=False).encode(encoding)
    r = client.post("/api/flight", content=body, headers={"Content-Type": "application/json"})
    assert one_line_error(r, 422).startswith("request:")


def test_half_a_utf16_pair_is_refused(client):
    """``"\\ud800"`` is valid JSON but no character (a UTF-8 writer cannot take it): 422, like the files."""
    r = client.post(
        "/api/flight", content=b'{"speed_kmh": 100, "x": "\\ud800"}', headers={"Content-Type": "application/json"}
    )
    assert "lone surrogate" in one_line_error(r, 422)


def test_a_key_given_twice_is_refused(client):
    """One duplicate-key rule for every reader: refused, not the last value taken."""
    r = client.post(
        "/api/flight", content=b'{"speed_kmh": 100, "speed_kmh": 5}', headers={"Content-Type": "application/json"}
    )
    assert "duplicate key" in one_line_error(r, 422)


def test_host_name_parsing():
    assert host_name("[::1]:80") == "::1" and host_name("Example.ORG") == "example.org"
    assert host_name("x:80x") is None and host_name("[::1]x") is None


def test_foreign_host_refused(client):
    assert one_line_error(client.get("/api/meta", headers={"host": "evil.example"}), 400).startswith("host:")


# ------------------------------------------------------------------ headers
@pytest.mark.parametrize(
    "method, path, body",
    [
        ("GET", "/", None),
        ("GET", "/static/app.js", None),
        ("GET", "/api/meta", None),
        ("GET", "/nope", None),
        ("POST", "/api/flight", {"speed_kmh": -1}),
        ("POST", "/api/flight", "text"),
    ],
)
def test_every_answer_forbids_framing(client, method, path, body):
    if body == "text":
        r = client.post(path, content=b"{}", headers={"Content-Type": "text/plain"})
    else:
        r = client.request(method, path, json=body)
    assert "frame-ancestors 'none'" in r.headers["content-security-policy"]
    assert r.headers["x-frame-options"] == "DENY"
    assert r.headers["x-content-type-options"] == "nosniff"
    assert "access-control-allow-origin" not in r.headers


# ------------------------------------------------------------------ JSON depth and size
@pytest.mark.parametrize("depth", [F.MAX_JSON_DEPTH + 1, 1_000, 100_000, 500_000])
@pytest.mark.parametrize("kind", ["array", "object"])
def test_deep_json_is_a_4xx_not_a_traceback(client, caplog, depth, kind):
    if kind == "array":
        text = "[" * depth + "]" * depth
    else:
        text = '{"a":' * depth + "1" + "}" * depth
    with caplog.at_level(logging.WARNING):
        r = client.post("/api/flight", content=text.encode(), headers={"Content-Type": "application/json"})
    assert r.status_code in (413, 422)
    msg = one_line_error(r, r.status_code)
    assert msg.startswith("request:")
    assert not [rec for rec in caplog.records if rec.levelno >= logging.ERROR]


def test_brackets_inside_strings_do_not_count(client):
    text = json.dumps({"csv": '"[[[[[[[[[[[[[[[[\\"{{{{{{{{{{{{{' * 10})
    r = client.post("/api/linecall", content=text.encode(), headers={"Content-Type": "application/json"})
    assert one_line_error(r, 422).startswith("track file:")


json_values = st.recursive(
    st.none() | st.booleans() | st.integers() | st.text(alphabet='[]{}"\\ ab\n', max_size=8),
    lambda inner: (
        st.lists(inner, max_size=3) | st.dictionaries(st.text(alphabet='[]{}"\\a', max_size=3), inner, max_size=3)
    ),
    max_leaves=12,
)


def true_depth(v) -> int:
    if isinstance(v, list):
        return 1 + max((true_depth(x) for x in v), default=0)
    if isinstance(v, dict):
        return 1 + max((true_depth(x) for x in v.values()), default=0)
    return 0


@settings(max_examples=300, deadline=None)
@given(json_values)
def test_json_depth_counts_like_the_parser(v):
    assert json_depth(json.dumps(v).encode()) == true_depth(v)


def test_body_size_limits(client):
    big = b'{"csv": "' + b"a" * (F.MAX_BODY_BYTES + 10) + b'"}'
    r = client.post("/api/linecall", content=big, headers={"Content-Type": "application/json"})
    assert one_line_error(r, 413).startswith("request:")

    def chunks():  # no Content-Length: the limit holds while reading
        yield b'{"csv": "'
        for _ in range(20):
            yield b"a" * 100_000
        yield b'"}'

    r = client.post("/api/linecall", content=chunks(), headers={"Content-Type": "application/json"})
    assert one_line_error(r, 413).startswith("request:")


# ------------------------------------------------------------------ time limits and a slow neighbour
def drill_body(n: int) -> dict:
    return {"name": "slow", "shots": [{"target_x": 8 - 0.05 * i, "target_y": 0.1 * (i % 20) - 1} for i in range(n)]}


def test_a_job_past_its_deadline_is_stopped_and_the_next_works():
    with TestClient(create_app(allowed_hosts=["testserver"], workers=1, spares=0, deadline_s=0.3)) as c:
        t0 = time.monotonic()
        r = c.post("/api/launcher/drill", json=drill_body(40))
        assert time.monotonic() - t0 < 5
        assert one_line_error(r, 503) == "drill: stopped after 0.3 s (the time limit of this computation)"
        assert c.post("/api/flight", json={}).status_code == 200
        pool = c.get("/api/meta").json()["pool"]
        assert pool["timed_out"] == 1 and pool["replaced"] == 1


def test_a_slow_request_does_not_block_a_fast_one(client):
    """Six 50-shot drills (the app's largest heavy job) queue on the heavy workers; a flight sent meanwhile
    answers at once, long before the last drill.

    One drill alone is no longer slow enough to show this (0.3 s since the search got faster), so the heavy
    work is six of them in a row: a light job that waited for a heavy one, or queued behind them, would fail.
    """
    ends: list[float] = []
    codes: list[int] = []
    t_start = time.monotonic()

    def run_slow():
        codes.append(client.post("/api/launcher/drill", json=drill_body(50)).status_code)
        ends.append(time.monotonic())

    threads = [threading.Thread(target=run_slow) for _ in range(6)]
    for th in threads:
        th.start()
    time.sleep(0.3)
    t0 = time.monotonic()
    assert client.post("/api/flight", json={}).status_code == 200
    t_fast = time.monotonic()
    for th in threads:
        th.join(120)
    assert codes == [200] * 6
    heavy_s = max(ends) - t_start
    fast_s = t_fast - t0
    assert t_fast < max(ends) and fast_s < 5, (fast_s, heavy_s)
    assert fast_s < 0.5 * (max(ends) - t0), (fast_s, heavy_s)
