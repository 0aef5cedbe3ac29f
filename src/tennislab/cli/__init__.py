"""The ``tennislab`` command line: thin (parse, call, print).

Each module of this package with a ``register(subparsers)`` function adds its
command group; they are discovered automatically so that command groups stay
independent.  User errors (:class:`tennislab.errors.InputError`) print one line
on stderr and exit with code 2, never a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import os
import pkgutil
import re
import sys

from tennislab import __version__
from tennislab.errors import InputError


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2 (argparse's own convention)
        self.exit(2, f"{self.prog}: error: {message}\n")


def _subparsers(parser: argparse.ArgumentParser) -> dict:
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="tennislab", description="Physics of a tennis ball.")
    parser.add_argument("--version", action="version", version=f"tennislab {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for mod in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
        if mod.name.startswith("_") or mod.name == "common":
            continue
        module = importlib.import_module(f"{__name__}.{mod.name}")
        if hasattr(module, "register"):
            module.register(sub)
    return parser


def _option_strings(parser: argparse.ArgumentParser) -> set[str]:
    """Every option string of ``parser`` and of its sub-commands."""
    out: set[str] = set()
    for action in parser._actions:
        out.update(action.option_strings)
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                out |= _option_strings(sub)
    return out


_PARAM = re.compile(r"^([a-z][a-z0-9_]*)(\[\d+\])?(?=[: ])")


def flag_message(message: str, options: set[str]) -> str:
    """A library error names its parameter (``speed_kmh: ...``); the CLI says its flag (``--speed-kmh: ...``)."""
    m = _PARAM.match(message)
    if m:
        flag = "--" + m.group(1).replace("_", "-")
        if flag in options:
            return flag + message[len(m.group(1)) :]
    return message


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        rc = args.func(args)
    except InputError as exc:
        sub = _subparsers(parser).get(args.command)
        msg = flag_message(_one_line(exc), _option_strings(sub) if sub else set())
        print(f"tennislab {args.command}: error: {msg}", file=sys.stderr)
        return 2
    except (FileNotFoundError, IsADirectoryError, PermissionError) as exc:
        print(f"tennislab {args.command}: error: {exc.filename}: {exc.strerror}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # output piped into `head` etc.
        try:
            sys.stdout = open(os.devnull, "w")
        except OSError:
            pass
        return 0
    return int(rc or 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
