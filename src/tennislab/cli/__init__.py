"""The ``tennislab`` command line: thin (parse, call a workflow, print).

Each module of this package with a ``register(subparsers)`` function adds its command group; they are
discovered automatically (:func:`build_parser`), so that command groups stay independent, and each
imports what its command uses only when it runs (``tennislab --help`` loads no NumPy: ``cli/_commands.py``).
:func:`main` is the entry point; :func:`flag_message` turns a library error naming a parameter into
one naming the command's flag.

The flags of batch work are public helpers for users' scripts too: :func:`add_scheduler_flag` adds
``--scheduler``, ``--out-dir``, ``--workers``, ``--chunk-size`` and ``--progress`` to an argparse
parser, :func:`batch_options_from_args` reads them back as :func:`tennislab.batch.map_chunks`
keywords.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from tennislab._lazy import attach_stub

if TYPE_CHECKING:
    from tennislab.cli._main import build_parser, flag_message, main
    from tennislab.cli.batch_flags import add_scheduler_flag, batch_options_from_args

__all__ = ["add_scheduler_flag", "batch_options_from_args", "build_parser", "flag_message", "main"]
__getattr__, __dir__ = attach_stub(__name__, __file__)
