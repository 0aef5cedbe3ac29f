"""``tennislab report --out DIR``: write the report, one self-contained HTML file (``DIR/index.html``)."""

from __future__ import annotations

import argparse

from tennislab.cli.config import load_player_file
from tennislab.errors import InputError
from tennislab.io.files import check_output_dir, check_output_path

#: The report's sections as ``--section`` accepts them, without importing the sections (and the physics
#: they run): :data:`tennislab.report.SECTION_KEYS` (tests/test_architecture.py checks that they are).
SECTION_KEYS = ("serve-windows", "peak-spin", "optimum-serves", "line-calling", "launcher-drill", "flight")


def _out_path(value: str) -> str:
    """argparse type of ``--out``: a directory (created if missing) or a file ending in .html."""
    from tennislab.report import index_path

    try:
        if index_path(value) == value:
            return check_output_path("out", value)
        return check_output_dir("out", value)
    except InputError as exc:
        raise argparse.ArgumentTypeError(str(exc).split(": ", 1)[1]) from None


def register(sub) -> None:
    p = sub.add_parser(
        "report",
        help="write the coach-facing HTML report (serve windows, line call, drill)",
        description="Compute the report's studies and write one self-contained HTML file (figures embedded): "
        "DIR/index.html, or FILE.html. Open it offline, mail it or serve it. Progress goes to stderr.",
    )
    p.add_argument(
        "--out",
        required=True,
        metavar="DIR|FILE.html",
        type=_out_path,
        help="output directory (created if missing; the report is DIR/index.html) or an .html file",
    )
    p.add_argument(
        "--player",
        action="append",
        metavar="FILE.toml|NAME",
        help="study this player beside the paper's three (a TOML file with one player, a [players.NAME] "
        "profile of tennislab.toml, or a built-in name); repeatable",
    )
    p.add_argument(
        "--section",
        action="append",
        metavar="KEY",
        choices=SECTION_KEYS,
        help=f"build only this section (repeatable); keys: {', '.join(SECTION_KEYS)}",
    )
    p.add_argument(
        "--strict",
        action="store_true",
        help="fail (exit 1) if a section fails instead of marking it failed in the report",
    )
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    p.set_defaults(func=run)


def run(args) -> int:
    from tennislab.report import build_report
    from tennislab.serve import SEED_PLAYERS, get_player

    own = args.player or ([args.config_defaults["player"]] if "player" in getattr(args, "config_defaults", {}) else [])
    players = None
    if own:  # one's own players first, then the paper's three for comparison
        names = [load_player_file(p).name if p.lower().endswith(".toml") else p for p in own]
        players = list(dict.fromkeys([get_player(n).name for n in names] + list(SEED_PLAYERS)))
    kw = {"progress": None} if args.quiet else {}
    summary = build_report(args.out, strict=args.strict, only=args.section, players=players, **kw)
    print(summary["index"])
    return 1 if args.strict and any(v == "failed" for v in summary["sections"].values()) else 0
