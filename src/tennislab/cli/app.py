"""``tennislab app``: serve the local web application (loopback by default)."""

from __future__ import annotations

import ipaddress
import sys

from tennislab.errors import InputError, check_range


def register(sub) -> None:
    p = sub.add_parser(
        "app",
        help="run the local web app (serve explorer, launcher planner, line-call replay)",
        description="Run the tennislab web application on this machine. It binds to the loopback "
        "address by default; everything it serves comes from the installed package.",
    )
    p.add_argument(
        "--host", default="127.0.0.1", help="address to bind (default 127.0.0.1: only this machine can connect)"
    )
    p.add_argument("--port", type=int, default=8000, help="TCP port (default 8000)")
    p.add_argument(
        "--allow-host",
        action="append",
        default=None,
        metavar="NAME",
        help="extra Host header name to accept (default: loopback names, or any when --host is not loopback)",
    )
    p.set_defaults(func=run)


def allowed_hosts(host: str, extra=None) -> list[str]:
    """Host headers to accept: loopback names when bound to loopback, else any."""
    from tennislab.app.server import LOOPBACK_HOSTS

    try:
        loop = ipaddress.ip_address(host).is_loopback
    except ValueError:
        loop = host == "localhost"
    hosts = list(LOOPBACK_HOSTS) if loop else ["*"]
    return hosts + list(extra or [])


def run(args) -> int:
    check_range("--port", args.port, 1, 65535)
    try:
        import uvicorn

        from tennislab.app.server import create_app
    except ImportError as exc:
        msg = f"app: the web app needs the optional dependencies: pip install 'tennislab[app]' ({exc})"
        raise InputError(msg) from None
    if args.host not in ("127.0.0.1", "localhost", "::1"):
        print(f"tennislab app: warning: binding to {args.host}: other machines can reach this server", file=sys.stderr)
    app = create_app(allowed_hosts=allowed_hosts(args.host, args.allow_host))
    print(f"tennislab app: http://{args.host}:{args.port}/  (Ctrl-C to stop)", file=sys.stderr)
    uvicorn.run(app, host=args.host, port=args.port, log_level="warning")
    return 0
