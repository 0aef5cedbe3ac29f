"""``tennislab app``: serve the local web application (loopback by default).

The address is resolved and the port bound *before* anything is printed: an unknown host name or a
port in use is one line and exit 2, never a traceback after a URL that does not work.
"""

from __future__ import annotations

import ipaddress
import socket
import sys

from tennislab.errors import InputError, check_range

LOOPBACK_NAMES = ("localhost",)


def register(sub) -> None:
    p = sub.add_parser(
        "app",
        help="run the local web app (serve explorer, launcher planner, line-call replay, flight)",
        description="Run the tennislab web application on this machine. It binds to the loopback "
        "address by default; everything it serves comes from the installed package.",
    )
    p.add_argument(
        "--host", default="127.0.0.1", help="address to bind (default 127.0.0.1: only this machine can connect)"
    )
    p.add_argument("--port", type=int, default=8000, help="TCP port (default 8000; 0 = any free port)")
    p.add_argument(
        "--allow-host",
        action="append",
        default=None,
        metavar="NAME",
        help="extra Host header name to accept (default: loopback names, or any when --host is not loopback)",
    )
    p.add_argument(
        "--workers",
        type=int,
        default=2,
        help="processes that run the physics (default 2; heavy jobs use at most workers-1 of them)",
    )
    p.set_defaults(func=run)


def is_loopback(host: str, addresses=()) -> bool:
    """True if ``host`` is a loopback name or address (127.0.0.0/8, ::1), or resolves only to such."""
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        pass
    if host.lower() in LOOPBACK_NAMES:
        return True
    return bool(addresses) and all(ipaddress.ip_address(a.split("%")[0]).is_loopback for a in addresses)


def allowed_hosts(host: str, extra=None) -> list[str]:
    """Host headers to accept: loopback names when bound to loopback (the server also accepts any
    loopback IP literal), else any."""
    hosts = ["127.0.0.1", "localhost", "[::1]", "::1"] if is_loopback(host) else ["*"]
    if is_loopback(host) and host not in hosts:
        hosts.append(host)
    return hosts + list(extra or [])


def bind(host: str, port: int) -> socket.socket:
    """A listening socket on ``host:port``; one-line :class:`InputError` naming ``host`` or ``port`` otherwise."""
    try:
        infos = socket.getaddrinfo(host.strip("[]"), port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE)
    except (socket.gaierror, UnicodeError) as exc:
        reason = exc.strerror if isinstance(exc, socket.gaierror) else str(exc)
        raise InputError(f"host: cannot resolve {host!r} ({reason})") from None
    infos.sort(key=lambda i: i[0] != socket.AF_INET)  # IPv4 first (what "localhost" users expect)
    family, kind, proto, _, addr = infos[0]
    sock = socket.socket(family, kind, proto)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        if family == socket.AF_INET6:
            sock.setsockopt(socket.IPPROTO_IPV6, socket.IPV6_V6ONLY, 1)
        sock.bind(addr)
        sock.listen(128)
    except OSError as exc:
        sock.close()
        if port and exc.errno in (98, 48, 10048):  # EADDRINUSE (Linux, macOS, Windows)
            raise InputError(
                f"port: {port} is already in use on {host} (choose another port, or 0 for any free port)"
            ) from None
        if exc.errno in (13, 10013):  # EACCES
            raise InputError(f"port: {port} needs privileges on this system (use a port above 1023)") from None
        raise InputError(f"host: cannot listen on {host} port {port} ({exc.strerror})") from None
    sock.set_inheritable(False)
    return sock


def run(args) -> int:
    check_range("port", args.port, 0, 65535)
    check_range("workers", args.workers, 1, 16)
    try:  # the app's third-party extras (optional: every other command works without them)
        import fastapi  # noqa: F401
        import uvicorn
    except ImportError as exc:
        msg = (
            "app: the web app needs the optional dependencies: `make demo` in a clone, "
            f"or pip install '.[app]' there ({exc})"
        )
        raise InputError(msg) from None
    # imported here, not at the top: tennislab.app.server needs fastapi, an optional extra
    from tennislab.app.server import create_app

    sock = bind(args.host, args.port)
    try:
        addrs = [sock.getsockname()[0]]
        if not is_loopback(args.host, addrs):
            print(
                f"tennislab app: warning: binding to {args.host}: other machines can reach this server",
                file=sys.stderr,
            )
        port = sock.getsockname()[1]
        shown = f"[{args.host.strip('[]')}]" if ":" in args.host else args.host

        def ready() -> None:  # the workers answer: now the URL works
            print(f"tennislab app: http://{shown}:{port}/  (Ctrl-C to stop)", file=sys.stderr, flush=True)

        app = create_app(allowed_hosts=allowed_hosts(args.host, args.allow_host), workers=args.workers, ready=ready)
        config = uvicorn.Config(
            app, log_level="warning", timeout_keep_alive=5, limit_concurrency=64, h11_max_incomplete_event_size=16384
        )
        server = uvicorn.Server(config)
        server.run(sockets=[sock])
    finally:
        sock.close()
    if not server.started:
        print("tennislab app: error: the server did not start (see the messages above)", file=sys.stderr)
        return 1
    return 0
