"""The FastAPI application of ``tennislab app``.

Routes (all JSON; every field validated by :mod:`tennislab.app.fields`):

=========================  ===============================================
``GET  /``                 the page (``static/index.html``)
``GET  /static/...``       scripts and styles shipped in the package (no CDN)
``GET  /api/meta``         version, which modules are available, the forms'
                           field definitions, the court geometry, players
``POST /api/flight``       one flight from a launch
``POST /api/serve``        one serve (impact + 3-D flight + success)
``POST /api/serve/window`` the alpha x beta serve window (heat map)
``POST /api/launcher/aim`` quantised machine settings for a target
``POST /api/launcher/drill`` a drill file from several aimed shots
``POST /api/linecall``     a line call from an uploaded track CSV
``GET  /api/linecall/sample`` a synthetic example track (CSV text)
=========================  ===============================================

Errors: bad input -> 422 ``{"error": "field: message"}`` (the messages of
:class:`tennislab.errors.InputError`); a module that is not installed -> 503
``{"error": ...}``; a body over the size limit -> 413.  Nothing in a request
is executed: values are parsed as numbers or checked against fixed choices
and passed to the physics functions.
"""

from __future__ import annotations

import json
import logging
import math
import threading
from pathlib import Path

import numpy as np
from fastapi import FastAPI, Request
from fastapi.responses import FileResponse, JSONResponse, PlainTextResponse
from fastapi.staticfiles import StaticFiles
from starlette.concurrency import run_in_threadpool
from starlette.middleware.trustedhost import TrustedHostMiddleware

from tennislab import __version__
from tennislab.app import fields as F
from tennislab.app import services as S
from tennislab.errors import InputError

STATIC = Path(__file__).parent / "static"
#: One physics call at a time: the compiled kernels already use every core, and Numba's
#: ``workqueue`` threading layer (the fallback when neither TBB nor OpenMP is present) must not
#: be entered from two threads at once.
PHYSICS_LOCK = threading.Lock()
LOOPBACK_HOSTS = ["127.0.0.1", "localhost", "[::1]", "::1"]
log = logging.getLogger("tennislab.app")

SECURITY_HEADERS = {
    "Content-Security-Policy": "default-src 'self'; img-src 'self' data: blob:; style-src 'self'; "
    "script-src 'self'; connect-src 'self'; object-src 'none'; base-uri 'none'",
    "X-Content-Type-Options": "nosniff",
    "Referrer-Policy": "no-referrer",
}


class TooLarge(Exception):
    pass


def clean(obj):
    """JSON-safe copy: numpy -> python, NaN/inf -> None."""
    if isinstance(obj, dict):
        return {str(k): clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return clean(obj.tolist())
    if isinstance(obj, (float, np.floating)):
        f = float(obj)
        return f if math.isfinite(f) else None
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    return obj


async def read_json(request: Request, limit: int = F.MAX_BODY_BYTES):
    """The request body parsed as JSON, refusing bodies over ``limit`` bytes."""
    cl = request.headers.get("content-length")
    if cl is not None and cl.isdigit() and int(cl) > limit:
        raise TooLarge()
    buf = bytearray()
    async for chunk in request.stream():
        buf += chunk
        if len(buf) > limit:
            raise TooLarge()
    if not buf:
        raise InputError("body: expected a JSON object, got an empty body")
    try:
        return json.loads(bytes(buf))
    except (ValueError, UnicodeDecodeError):
        raise InputError("body: not valid JSON") from None


def _locked(fn, *args, **kw):
    with PHYSICS_LOCK:
        return fn(*args, **kw)


def _error(status: int, msg: str) -> JSONResponse:
    return JSONResponse({"error": msg}, status_code=status)


def create_app(allowed_hosts: list[str] | None = None) -> FastAPI:
    """Build the application.  ``allowed_hosts``: Host headers accepted (default loopback names;
    ``["*"]`` for any), a guard against DNS rebinding when bound to loopback."""
    app = FastAPI(title="tennislab", version=__version__, docs_url=None, redoc_url=None, openapi_url=None)
    app.add_middleware(TrustedHostMiddleware, allowed_hosts=allowed_hosts or LOOPBACK_HOSTS)

    @app.middleware("http")
    async def _headers(request: Request, call_next):
        try:
            resp = await call_next(request)
        except TooLarge:  # pragma: no cover - handled below; kept for streaming edge cases
            resp = _error(413, "body: larger than the limit")
        for k, v in SECURITY_HEADERS.items():
            resp.headers.setdefault(k, v)
        if request.url.path.startswith("/api/"):
            resp.headers["Cache-Control"] = "no-store"
        return resp

    @app.exception_handler(InputError)
    async def _input_error(request, exc):
        return _error(422, str(exc))

    @app.exception_handler(S.Unavailable)
    async def _unavailable(request, exc):
        return _error(503, str(exc))

    @app.exception_handler(TooLarge)
    async def _too_large(request, exc):
        return _error(413, f"body: larger than the limit of {F.MAX_BODY_BYTES // 1000} kB")

    @app.exception_handler(Exception)
    async def _internal(request, exc):  # pragma: no cover - defensive
        log.exception("internal error")
        return _error(500, f"internal error: {type(exc).__name__}")

    app.mount("/static", StaticFiles(directory=str(STATIC)), name="static")

    @app.get("/", include_in_schema=False)
    async def index():
        return FileResponse(STATIC / "index.html", media_type="text/html")

    @app.get("/api/meta")
    async def meta():
        from tennislab.app import features

        return clean(
            {
                "version": __version__,
                "modules": S.availability(),
                "forms": F.forms_spec(),
                "court": S.court_geometry(),
                "players": features.players(),
                "limits": {"track_bytes": F.MAX_TRACK_BYTES, "drill_shots": F.MAX_DRILL_SHOTS},
            }
        )

    def post(path: str, form: str | None, fn, *, extra: tuple = ()):
        """Register a POST route: parse JSON, validate ``form`` (keeping ``extra`` raw keys), call ``fn``."""

        async def handler(request: Request):
            body = await read_json(request)
            if not isinstance(body, dict):
                raise InputError("body: expected a JSON object")
            raw = {k: body.pop(k) for k in extra if k in body}
            if form:
                vals = F.validate(form, body)
            elif body:
                raise InputError(f"{F.field_label(sorted(body)[0])}: unknown field (allowed: {', '.join(extra)})")
            else:
                vals = {}
            result = await run_in_threadpool(_locked, fn, vals, **raw)
            return JSONResponse(clean(result))

        handler.__name__ = "post_" + path.strip("/").replace("/", "_")
        app.post(path)(handler)

    from tennislab.app import features

    post("/api/flight", "flight", lambda v: S.flight(v))
    post("/api/serve", "serve", features.serve)
    post("/api/serve/window", "window", features.serve_window)
    post("/api/launcher/aim", "aim", features.aim)
    post("/api/launcher/drill", None, features.drill, extra=("shots", "name"))
    post("/api/linecall", "linecall", features.linecall, extra=("csv",))

    @app.get("/api/linecall/sample")
    async def sample():
        text = await run_in_threadpool(_locked, features.sample_track)
        return PlainTextResponse(text, media_type="text/csv")

    return app
