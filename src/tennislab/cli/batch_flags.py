"""CLI flags for batch work: ``--scheduler``, ``--out-dir`` (+ ``--workers``, ``--chunk-size``, ``--progress``).

Commands add them with :func:`add_scheduler_flag` and pass
``**batch_options_from_args(args)`` to :func:`tennislab.batch.map_chunks`.  Both are public
helpers for users' own scripts too (``from tennislab.cli import add_scheduler_flag``); they lived in
``tennislab.batch`` before flags moved to the CLI layer, and ``tennislab.batch.add_scheduler_flag``
still works (with a :class:`DeprecationWarning`).
"""

from __future__ import annotations

import argparse

from tennislab.batch.schedulers import check_scheduler
from tennislab.errors import InputError
from tennislab.io.files import check_output_dir


def _scheduler_arg(text: str) -> str:
    try:
        return str(check_scheduler(text))
    except InputError as exc:
        raise argparse.ArgumentTypeError(str(exc).partition(": ")[2]) from None


def _positive_int(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"{v} is outside the allowed range [1, inf]")
    return v


def _out_dir_arg(text: str) -> str:
    """``--out-dir``: refused at parse time (before any work) when it cannot be a writable directory."""
    try:
        return check_output_dir("out_dir", text)
    except InputError as exc:
        raise argparse.ArgumentTypeError(str(exc).partition(": ")[2]) from None


_out_dir_arg.is_output = True  # type: ignore[attr-defined]  # checked against the other outputs (check_io)


def add_scheduler_flag(parser) -> None:
    """Add ``--scheduler`` (default ``local``) and ``--out-dir DIR`` to an argparse parser.

    Also ``--workers N`` (processes scheduler), ``--chunk-size N`` and
    ``--progress/--no-progress`` unless the parser already has those options.
    """
    existing = set(getattr(parser, "_option_string_actions", {}))
    g = parser.add_argument_group("batch execution")
    g.add_argument(
        "--scheduler",
        default="local",
        type=_scheduler_arg,
        metavar="local|processes|tcp://HOST:PORT",
        help="where to run: in process (local, default), a local cluster of worker processes "
        "(processes), or a running Dask scheduler (tcp://HOST:PORT)",
    )
    g.add_argument(
        "--out-dir",
        metavar="DIR",
        default=None,
        type=_out_dir_arg,
        help="also stream results to DIR/part-*.parquet; rerunning resumes (finished chunks skipped)",
    )
    if "--workers" not in existing:
        g.add_argument(
            "--workers",
            type=_positive_int,
            default=None,
            metavar="N",
            help="worker processes for --scheduler processes (default: number of cores)",
        )
    if "--chunk-size" not in existing:
        g.add_argument(
            "--chunk-size",
            type=_positive_int,
            default=None,
            metavar="N",
            help="rows per chunk (default ~N/64 in [1024, 65536]; kept when resuming)",
        )
    if "--progress" not in existing and "--no-progress" not in existing:
        add_progress_flag(g)


#: help of ``--progress/--no-progress`` (every command that shows progress)
PROGRESS_HELP = (
    "progress on stderr in the command's units (serves/s, flights/s, calls/s): --progress on any stream "
    "(a log gets a line every few seconds), --no-progress never; default: on a terminal for work over ~5 s"
)


def add_progress_flag(group) -> None:
    """``--progress/--no-progress`` (:func:`progress_from_args` reads it back)."""
    group.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None, help=PROGRESS_HELP)


def progress_from_args(args):
    """The ``progress`` of :mod:`tennislab.batch.progress` from ``--progress/--no-progress``: ``"always"``,
    False, or ``"auto"`` when neither was given."""
    p = getattr(args, "progress", None)
    return "auto" if p is None else ("always" if p else False)


def batch_options_from_args(args) -> dict:
    """Keyword arguments for :func:`map_chunks` from parsed batch flags."""
    return {
        "scheduler": getattr(args, "scheduler", "local"),
        "out": getattr(args, "out_dir", None),
        "n_workers": getattr(args, "workers", None),
        "chunk_size": getattr(args, "chunk_size", None),
        "progress": progress_from_args(args),
    }
