"""``tennislab report --out DIR``: write the HTML report (index.html + PNG figures)."""

from __future__ import annotations


def register(sub) -> None:
    p = sub.add_parser(
        "report",
        help="write the coach-facing HTML report (serve windows, line call, drill)",
        description="Compute the report's studies and write DIR/index.html with PNG figures "
        "beside it (self-contained: open it offline). Progress goes to stderr.",
    )
    p.add_argument("--out", required=True, metavar="DIR", help="output directory (created if missing)")
    p.add_argument(
        "--section",
        action="append",
        metavar="KEY",
        help="build only this section (repeatable); keys: serve-windows, peak-spin, "
        "optimum-serves, line-calling, launcher-drill, flight",
    )
    p.add_argument(
        "--strict",
        action="store_true",
        help="fail (exit 1) if a section fails instead of marking it failed in the report",
    )
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    p.set_defaults(func=run)


def run(args) -> int:
    from tennislab.errors import InputError
    from tennislab.report.build import SECTIONS, build_report

    keys = [k for k, _, _ in SECTIONS]
    for s in args.section or []:
        if s not in keys:
            raise InputError(f"--section: unknown section {s!r}; allowed: {', '.join(keys)}")
    if os_path_is_file(args.out):
        raise InputError(f"--out: {args.out} is a file, expected a directory")
    kw = {"progress": None} if args.quiet else {}
    summary = build_report(args.out, strict=args.strict, only=args.section, **kw)
    print(summary["index"])
    return 1 if args.strict and any(v == "failed" for v in summary["sections"].values()) else 0


def os_path_is_file(p: str) -> bool:
    import os

    return os.path.isfile(p)
