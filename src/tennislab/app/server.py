"""The FastAPI application of ``tennislab app``.

Routes (every field validated by :mod:`tennislab.app.fields`):

=========================  ===============================================
``GET  /``                 the page (``static/index.html``)
``GET  /static/...``       scripts and styles shipped in the package (no CDN)
``GET  /api/meta``         version, the forms' field definitions, the court geometry, players, limits
``POST /api/flight``       one flight from a launch (:func:`tennislab.trajectory.fly`)
``POST /api/serve``        one serve (impact + 3-D flight + success and verdict)
``POST /api/serve/window`` the alpha x beta serve window (heat map)
``POST /api/launcher/aim`` quantised machine settings for a target
``POST /api/launcher/drill`` a drill file from several aimed shots
``POST /api/linecall``     a line call from an uploaded track CSV
``GET  /api/linecall/sample`` a synthetic example track (CSV text)
=========================  ===============================================

What the server promises (``docs/security.md``): it answers only its own page.  Every request's
``Host`` must be a loopback name (or one allowed by ``--allow-host``); every state-changing request
and every ``/api/`` request from a browser must come from the page itself (``Origin`` equal to the
server's own, or no ``Origin`` and no cross-site ``Sec-Fetch-Site``); POST bodies must be
``application/json`` (so no HTML form or ``no-cors`` fetch of another site can send one), at most
:data:`~tennislab.app.fields.MAX_BODY_BYTES`, received within :data:`BODY_TIMEOUT_S` and nested at
most :data:`~tennislab.app.fields.MAX_JSON_DEPTH` deep (checked before parsing).  The page cannot
be framed (``frame-ancestors 'none'``, ``X-Frame-Options: DENY``).  The physics runs in a pool of
worker processes (:mod:`tennislab.app.pool`) with per-job deadlines; a job whose client has gone is
cancelled.

Errors are one line of JSON ``{"error": "label: message"}`` naming the field by its label on
screen: 422 bad input, 415 wrong content type, 413 too large, 408 too slow, 403 foreign origin,
400 foreign host, 503 busy or past a deadline.
"""

from __future__ import annotations

import asyncio
import contextlib
import ipaddress
import json
import logging
import re
from collections.abc import Callable
from pathlib import Path

import numpy as np
from fastapi import FastAPI, Request
from fastapi.responses import FileResponse, JSONResponse, PlainTextResponse, Response
from fastapi.staticfiles import StaticFiles
from starlette.datastructures import Headers, MutableHeaders
from starlette.exceptions import HTTPException as StarletteHTTPException

import tennislab.app.features as features
import tennislab.app.fields as F
import tennislab.app.services as S
from tennislab import __version__
from tennislab.app.pool import ClientGone, Pool, PoolError
from tennislab.errors import InputError
from tennislab.io import check_unicode, unique_pairs

STATIC = Path(__file__).parent / "static"
#: Host names accepted when bound to loopback (any loopback IP literal is accepted too)
LOOPBACK_HOSTS = ["127.0.0.1", "localhost", "[::1]", "::1"]
#: a request body must arrive within this time [s]
BODY_TIMEOUT_S = 15.0
log = logging.getLogger("tennislab.app")

SECURITY_HEADERS = {
    "Content-Security-Policy": "default-src 'self'; img-src 'self' data: blob:; style-src 'self'; "
    "script-src 'self'; connect-src 'self'; object-src 'none'; base-uri 'none'; form-action 'none'; "
    "frame-ancestors 'none'",
    "X-Frame-Options": "DENY",
    "X-Content-Type-Options": "nosniff",
    "Referrer-Policy": "no-referrer",
    "Cross-Origin-Opener-Policy": "same-origin",
    "Cross-Origin-Resource-Policy": "same-origin",
}
SAFE_METHODS = {"GET", "HEAD"}
ALLOWED_METHODS = {"GET", "HEAD", "POST"}


class Refused(Exception):
    """A request refused before any work: HTTP ``status`` and a one-line message."""

    def __init__(self, status: int, message: str):
        super().__init__(message)
        self.status = status


def _error(status: int, msg: str) -> JSONResponse:
    return JSONResponse({"error": msg}, status_code=status)


# ---------------------------------------------------------------------- host and origin
def host_name(value: str) -> str | None:
    """The host name of a ``Host`` header (``name``, ``name:port``, ``[v6]:port``), lower case; None if malformed."""
    v = value.strip().lower()
    if v.startswith("["):
        end = v.find("]")
        rest = v[end + 1 :] if end > 0 else "x"
        if rest and not (rest.startswith(":") and rest[1:].isdigit()):
            return None
        return v[1:end]
    name, _, port = v.partition(":")
    if port and not port.isdigit():
        return None
    return name or None


def is_loopback_literal(name: str) -> bool:
    try:
        return ipaddress.ip_address(name).is_loopback
    except ValueError:
        return False


class Guard:
    """ASGI middleware: Host, Origin and method checks before the app; security headers on every answer."""

    def __init__(self, app, allowed_hosts: list[str]) -> None:
        self.app = app
        self.any_host = "*" in allowed_hosts
        self.names = {h.strip("[]").lower() for h in allowed_hosts}

    def host_ok(self, name: str | None) -> bool:
        return name is not None and (self.any_host or name in self.names or is_loopback_literal(name))

    def check(self, method: str, path: str, headers: Headers) -> tuple[int, str] | None:
        hosts = headers.getlist("host")
        if len(hosts) > 1:
            return 400, "host: the request has more than one Host header"
        host = hosts[0] if hosts else ""
        if not self.host_ok(host_name(host)):
            return 400, f"host: {F.short(host)} is not a name of this server (start it with --allow-host NAME)"
        if method not in ALLOWED_METHODS:
            return 405, f"method: {method} is not allowed"
        origins = headers.getlist("origin")
        if len(origins) > 1:  # which one a browser or a proxy meant is a guess: refused
            return 403, "origin: the request has more than one Origin header"
        if len(headers.getlist("content-type")) > 1:  # the body's type would be a guess too
            return 415, "request: the request has more than one Content-Type header"
        if method in SAFE_METHODS and not path.startswith("/api/"):
            return None  # the page and its files may be opened from anywhere (they cannot be framed)
        origin = origins[0] if origins else None
        # every copy, and every value of a folded one (``same-origin, cross-site`` is two copies in one line)
        sites = {v.strip().lower() for line in headers.getlist("sec-fetch-site") for v in line.split(",")}
        if origin is not None:
            if origin.strip().lower() != f"http://{host.strip().lower()}":
                return 403, f"origin: requests from {F.short(origin)} are refused (the app answers only its own page)"
        elif sites & {"cross-site", "same-site"}:
            site = sorted(sites & {"cross-site", "same-site"})[0]
            return 403, f"origin: {site} requests are refused (the app answers only its own page)"
        return None

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        path = scope["path"]

        async def send_with_headers(message):
            if message["type"] == "http.response.start":
                h = MutableHeaders(scope=message)
                for k, v in SECURITY_HEADERS.items():
                    if k not in h:
                        h[k] = v
                if path.startswith("/api/"):
                    h["Cache-Control"] = "no-store"
            await send(message)

        problem = self.check(scope["method"], path, Headers(scope=scope))
        if problem is not None:
            await _error(*problem)(scope, receive, send_with_headers)
            return
        await self.app(scope, receive, send_with_headers)


# ---------------------------------------------------------------------- JSON bodies
_JSON_STRING = re.compile(rb'"[^"\\]*(?:\\.[^"\\]*)*"', re.S)


def json_depth(raw: bytes) -> int:
    """Nesting depth of a JSON text (brackets inside strings ignored), without parsing it."""
    a = np.frombuffer(_JSON_STRING.sub(b'""', raw), dtype=np.uint8)
    if a.size == 0:
        return 0
    step = ((a == 0x5B) | (a == 0x7B)).astype(np.int32) - ((a == 0x5D) | (a == 0x7D)).astype(np.int32)
    return int(np.cumsum(step).max(initial=0))


def check_content_type(value: str | None) -> None:
    """Only ``application/json`` (optionally ``; charset=utf-8``): what no HTML form or simple request sends."""
    media, *params = [p.strip().lower() for p in (value or "").split(";")]
    ok = media == "application/json" and all(p in ("charset=utf-8", 'charset="utf-8"', "") for p in params)
    if not ok:
        got = F.short(value) if value else "none"
        raise Refused(415, f"request: expected Content-Type application/json, got {got}")


async def read_json(request: Request, limit: int = F.MAX_BODY_BYTES):
    """The request body parsed as JSON: content type, size, time and depth checked first."""
    check_content_type(request.headers.get("content-type"))
    cl = request.headers.get("content-length")
    if cl is not None and (not cl.isdigit() or int(cl) > limit):
        raise Refused(413, f"request: the body is larger than the limit of {limit // 1000} kB")

    async def _read() -> bytes:
        buf = bytearray()
        async for chunk in request.stream():
            buf += chunk
            if len(buf) > limit:
                raise Refused(413, f"request: the body is larger than the limit of {limit // 1000} kB")
        return bytes(buf)

    try:
        raw = await asyncio.wait_for(_read(), BODY_TIMEOUT_S)
    except TimeoutError:
        raise Refused(408, f"request: the body did not arrive within {BODY_TIMEOUT_S:g} s") from None
    if not raw.strip():
        raise InputError("request: expected a JSON object, got an empty body")
    depth = json_depth(raw)
    if depth > F.MAX_JSON_DEPTH:
        raise InputError(f"request: JSON nested {depth} levels deep; at most {F.MAX_JSON_DEPTH} are accepted")
    try:
        text = raw.decode("utf-8")  # json.loads(bytes) would also take UTF-16 and UTF-32: refused here
    except UnicodeDecodeError:
        raise InputError("request: the body is not UTF-8 text (JSON bodies are UTF-8)") from None
    try:
        return check_unicode(text, json.loads(text, object_pairs_hook=unique_pairs("request")), "request")
    except InputError:
        raise
    except (ValueError, RecursionError):
        raise InputError("request: not valid JSON (UTF-8)") from None


# ---------------------------------------------------------------------- the application
#: path -> (form validated, job run, request keys passed to the job as they are)
POSTS = {
    "/api/flight": ("flight", "flight", ()),
    "/api/serve": ("serve", "serve", ()),
    "/api/serve/window": ("window", "window", ()),
    "/api/launcher/aim": ("aim", "aim", ()),
    "/api/launcher/drill": (None, "drill", ("shots", "name")),
    "/api/linecall": ("linecall", "linecall", ("csv",)),
}


def create_app(
    allowed_hosts: list[str] | None = None,
    *,
    workers: int = 2,
    spares: int = 1,
    deadline_s: float | None = None,
    max_waiting: int = 32,
    ready: Callable[[], None] | None = None,
) -> FastAPI:
    """Build the application.

    ``allowed_hosts``: Host names accepted besides loopback literals (default :data:`LOOPBACK_HOSTS`;
    ``["*"]`` for any), a guard against DNS rebinding.  ``workers``: processes of the physics pool
    (plus ``spares`` started ahead to replace a stopped one);
    ``deadline_s``: one time limit for every job (default: per job, :data:`tennislab.app.pool.DEADLINES_S`);
    ``ready``: called once the workers answer (``tennislab app`` prints its URL then).
    """
    pool = Pool(workers, spares=spares, deadline_s=deadline_s, max_waiting=max_waiting)

    @contextlib.asynccontextmanager
    async def lifespan(app):
        await pool.start()
        if ready is not None:
            ready()
        try:
            yield
        finally:
            await pool.close()

    app = FastAPI(
        title="tennislab", version=__version__, docs_url=None, redoc_url=None, openapi_url=None, lifespan=lifespan
    )
    app.state.pool = pool

    @app.exception_handler(InputError)
    async def _input_error(request, exc):
        return _error(422, " ".join(str(exc).split()))

    @app.exception_handler(Refused)
    async def _refused(request, exc):
        return _error(exc.status, str(exc))

    @app.exception_handler(ClientGone)
    async def _gone(request, exc):
        return Response(status_code=499)  # nobody reads it

    @app.exception_handler(PoolError)
    async def _pool_error(request, exc):
        return _error(exc.status, str(exc))

    @app.exception_handler(StarletteHTTPException)
    async def _http_error(request, exc):
        what = {404: "not found", 405: "method not allowed"}.get(exc.status_code, str(exc.detail))
        return _error(exc.status_code, f"{F.short(request.url.path)}: {what}")

    @app.exception_handler(Exception)
    async def _internal(request, exc):  # pragma: no cover - a bug
        log.exception("internal error")
        return _error(500, f"internal error: {type(exc).__name__}")

    app.mount("/static", StaticFiles(directory=str(STATIC)), name="static")

    @app.get("/", include_in_schema=False)
    async def index():
        return FileResponse(STATIC / "index.html", media_type="text/html")

    @app.get("/api/meta")
    async def meta():
        return JSONResponse(
            {
                "version": __version__,
                "forms": F.forms_spec(),
                "court": S.court_geometry(),
                "players": features.players(),
                "limits": {
                    "track_bytes": F.MAX_TRACK_BYTES,
                    "drill_shots": F.MAX_DRILL_SHOTS,
                    "body_bytes": F.MAX_BODY_BYTES,
                    "json_depth": F.MAX_JSON_DEPTH,
                },
                "pool": pool.snapshot(),
            }
        )

    async def run(request: Request, form: str | None, job: str, vals: dict, extra: dict):
        try:
            return await pool.run(job, vals, extra, gone=request.is_disconnected)
        except InputError as exc:
            raise InputError(F.label_message(form, str(exc))) from None

    def post(path: str, form: str | None, job: str, extra_keys: tuple):
        async def handler(request: Request):
            body = await read_json(request)
            if not isinstance(body, dict):
                raise InputError("request: expected a JSON object")
            extra = {k: body.pop(k) for k in extra_keys if k in body}
            if form:
                vals = F.validate(form, body)
            elif body:
                raise InputError(f"{F.field_label(sorted(body)[0])}: unknown field (allowed: {', '.join(extra_keys)})")
            else:
                vals = {}
            return JSONResponse(await run(request, form, job, vals, extra))

        handler.__name__ = "post_" + path.strip("/").replace("/", "_")
        app.post(path)(handler)

    for path, (form, job, extra_keys) in POSTS.items():
        post(path, form, job, extra_keys)

    @app.get("/api/linecall/sample")
    async def sample(request: Request):
        text = await run(request, None, "sample", {}, {})
        return PlainTextResponse(text, media_type="text/csv")

    app.add_middleware(Guard, allowed_hosts=allowed_hosts or LOOPBACK_HOSTS)
    return app
