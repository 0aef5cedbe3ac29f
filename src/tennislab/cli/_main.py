"""The ``tennislab`` command line (:func:`main`): thin (parse, call, print).

Each module of this package with a ``register(subparsers)`` function adds its command group; they
are discovered automatically so that command groups stay independent, and named in
:data:`tennislab.cli._commands.COMMANDS` so that a command line builds (and imports) only the group of
the command it runs (``tennislab --help`` and ``--version``: none).

Before a command runs, the configuration (``--config FILE``, a global flag accepted anywhere on the
line, else ``./tennislab.toml``; ``--no-config`` ignores it) gives its defaults and profiles
(:mod:`tennislab.cli.config`): a flag on the command line beats the configuration, which beats the
built-in default.

User errors (:class:`tennislab.errors.InputError`, a file that cannot be read or written, a number
no model answers) print one line on stderr and exit with code 2, never a traceback; a library error
that starts with a parameter's name is shown with the command's flag (:func:`flag_message`).  Every
message goes through :func:`tennislab.errors.escape_text` (a file name in any encoding, text from a
file with terminal escape codes), and stdout and stderr never fail on a character they cannot encode.

Each command runs inside :func:`tennislab.io.files.command_files`: an output that is one of the
command's inputs is refused, on the command line before any work (:func:`tennislab.cli.common.check_io`)
and again when it would be written.  Every ``float`` flag must be a finite, normal number.
"""

from __future__ import annotations

import argparse
import importlib
import os
import pkgutil
import re
import sys
from collections.abc import Collection

import tennislab.cli.config as cfgmod
from tennislab import __version__
from tennislab.cli._commands import COMMANDS
from tennislab.cli.common import check_io, checked_floats
from tennislab.errors import InputError, escape_text
from tennislab.io.files import command_files

#: modules of this package that are not command groups
_NOT_COMMANDS = {"batch_flags", "common", "config"}


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2 (argparse's own convention)
        # "argument --plot: ..." -> "--plot: ...": the same form as the errors the commands raise
        # and "argument --velocity: [0]: ..." (a value of a flag of several numbers) -> "--velocity[0]: ..."
        text = _ARGUMENT.sub(r"\1\2: ", " ".join(str(message).split()))
        self.exit(2, f"{self.prog}: error: {escape_text(text)}\n")


_ARGUMENT = re.compile(r"^argument (--[\w-]+)(?:/-\w)?: (?:(\[\d+\]): )?")


def _subparsers(parser: argparse.ArgumentParser) -> dict:
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


def _config_flags(p: argparse.ArgumentParser, top: bool) -> None:
    default = None if top else argparse.SUPPRESS  # sub-commands must not overwrite the top-level value
    g = p.add_argument_group("configuration") if not top else p
    g.add_argument(
        "--config",
        metavar="FILE",
        default=default,
        help="configuration file (default ./tennislab.toml if present; docs/config.md)",
    )
    g.add_argument(
        "--no-config",
        action="store_true",
        default=False if top else argparse.SUPPRESS,
        help="ignore ./tennislab.toml",
    )


def build_parser(
    config: cfgmod.Config | None = None, commands: Collection[str] | None = None
) -> argparse.ArgumentParser:
    """The full parser; with ``config``, its values are the defaults of the matching flags.

    ``commands``: build only the groups of these commands (default: every group); each other command
    is only named, with its help (:data:`~tennislab.cli._commands.COMMANDS`), as ``tennislab --help``
    lists it, so that a command line imports only the module of the command it runs."""
    parser = _Parser(prog="tennislab", description="Physics of a tennis ball.")
    parser.add_argument("--version", action="version", version=f"tennislab {__version__}")
    _config_flags(parser, top=True)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    if commands is None:
        for mod in sorted(pkgutil.iter_modules([os.path.dirname(__file__)]), key=lambda m: m.name):
            if not mod.name.startswith("_") and mod.name not in _NOT_COMMANDS:
                _register(sub, mod.name)
    else:
        wanted = {COMMANDS[c][0] for c in commands if c in COMMANDS}
        for name, (module, text) in COMMANDS.items():
            if module in wanted:  # the whole group, in the place of its first command
                wanted.discard(module)
                _register(sub, module)
            elif name not in sub.choices:
                sub.add_parser(name, help=text, add_help=False)  # named only (its flags: when it runs)
    for p in list(cfgmod._walk(parser))[1:]:
        if not _subparsers(p):  # leaf commands accept --config too
            _config_flags(p, top=False)
    checked_floats(parser)
    if config is not None:
        cfgmod.apply_defaults(parser, config)
    return parser


def _register(sub, module: str) -> None:
    mod = importlib.import_module(f"tennislab.cli.{module}")
    if hasattr(mod, "register"):
        mod.register(sub)


def _command_of(argv: list[str]) -> tuple[str, ...]:
    """The command ``argv`` runs, found as the full parse finds it, by a parser that names every command
    without building any: ``tennislab --help`` and a usage error before the command end here, having
    imported no command's module."""
    known, _ = build_parser(commands=()).parse_known_args(argv)
    return (known.command,)


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
_INNER = re.compile(r"(?<![\w.\-/])([a-z][a-z0-9]*(?:_[a-z0-9]+)+)(?![\w\-/])")


#: library parameters whose flag is not their name (``--out-dir`` writes the batch store ``out``)
#: a parameter whose flag has another name, tried first (``ball_window``'s ``elevation_deg=(lo, hi)`` is
#: ``serve-window --elevation-range LO HI``), then the flag of the parameter's own name
_ALIASES = {
    "out": "out_dir",
    "elevation_deg": "elevation_range",
    "heading_deg": "heading_range",
    "flat_max_rpm": "spin_bands",
    "topspin_min_rpm": "spin_bands",
}


#: a library message's advice to set a parameter: ``method="numeric"``
_SETTING = re.compile(r'\b([a-z][a-z0-9_]*)="([^"\s]*)"')


def flag_message(message: str, options: set[str]) -> str:
    """A library error names its parameter (``speed_kmh: ...``); the CLI says its flag (``--speed-kmh: ...``).

    The leading name is rewritten when the command has that flag; so are other parameter names with
    an underscore in the text (``give spin_rpm and spin_axis together`` -> ``--spin-rpm``, ``--spin-axis``),
    but not in a text that names a file's columns or keys (``missing column(s) spin_rpm``): those are
    the file's words, not the command's.  Advice to set a parameter (``use method="numeric"``) is said
    with the command's flag (``use --method numeric``).
    """
    first = message.partition(": ")[0]
    if "." in first or "/" in first:  # about a file's content (``d.yaml: shots.a.spin_axis: ...``): its words
        return message
    m = _PARAM.match(message)
    if m:
        for name in (_ALIASES.get(m.group(1), m.group(1)), m.group(1)):
            flag = "--" + name.replace("_", "-")
            if flag in options:
                message = flag + message[len(m.group(1)) :]
                break

    def inner(mm: re.Match) -> str:
        flag = "--" + mm.group(1).replace("_", "-")
        return flag if flag in options else mm.group(1)

    head, sep, rest = message.partition(": ")
    if not sep or re.search(r"\b(column|columns|column\(s\)|header|key|keys|field|fields)\b", rest):
        return message

    def setting(mm: re.Match) -> str:  # the library's `method="numeric"` is the command's `--method numeric`
        flag = "--" + mm.group(1).replace("_", "-")
        return f"{flag} {mm.group(2)}" if flag in options else mm.group(0)

    return head + sep + _INNER.sub(inner, _SETTING.sub(setting, rest))


def _one_line(text: object) -> str:
    return escape_text(" ".join(str(text).split()))


class _PreParser(argparse.ArgumentParser):
    def error(self, message):
        raise InputError(f"config: {message}")


def _pre_config(argv: list[str]) -> tuple[str | None, bool]:
    """``--config FILE`` / ``--no-config`` wherever they are on the line (read before the full parse,
    whose defaults depend on the file)."""
    pre = _PreParser(add_help=False)
    pre.add_argument("--config")
    pre.add_argument("--no-config", action="store_true")
    known, _ = pre.parse_known_args([a for a in argv if a != "--"])
    return known.config, known.no_config


def _command_name(args: argparse.Namespace) -> str:
    return getattr(args, "command", None) or "tennislab"


def _file_backend() -> None:
    """The command line writes figures to files only: Matplotlib's Agg backend, chosen here (the entry
    point) and never by the library, and only when nothing has imported Matplotlib yet (a notebook
    calling :func:`main` keeps its own backend).  An environment variable, so that no Matplotlib is
    loaded at start-up."""
    if "matplotlib" not in sys.modules:
        os.environ["MPLBACKEND"] = "Agg"


def _tolerant_streams() -> None:
    """stdout/stderr write what they cannot encode as escapes instead of failing (a strict ASCII or
    UTF-8 terminal and a file name that is not UTF-8)."""
    for stream in (sys.stdout, sys.stderr):
        reconfigure = getattr(stream, "reconfigure", None)
        if reconfigure is not None and getattr(stream, "errors", "strict") == "strict":
            try:
                reconfigure(errors="backslashreplace")
            except (ValueError, OSError, TypeError):  # pragma: no cover - a stream that cannot be changed
                pass


class _EscapingStdout:
    """``sys.stdout`` while a command runs: what it prints passes through the one escaper
    (:func:`tennislab.errors.escape_text`; lines and tabs kept), so a shot name, a point name or a
    file name from a file can neither drive the terminal (escape codes) nor break a line, and prints
    whatever its encoding."""

    def __init__(self, stream) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        if not text.isprintable():
            text = "\n".join("\t".join(escape_text(p) for p in line.split("\t")) for line in text.split("\n"))
        return self._stream.write(text)

    def __getattr__(self, name: str):
        return getattr(self._stream, name)


def main(argv=None) -> int:
    _tolerant_streams()
    out = sys.stdout
    sys.stdout = _EscapingStdout(out)
    try:
        with command_files():
            return _main(argv)
    finally:
        if isinstance(sys.stdout, _EscapingStdout):
            sys.stdout = out


def _main(argv) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    _file_backend()
    if argv == ["--version"]:  # what argparse's version action prints, without building every command
        print(f"tennislab {__version__}")
        return 0
    wants_help = any(a in ("-h", "--help", "--version") for a in argv)
    try:
        path, no_config = _pre_config(argv)
        cfg = cfgmod.load_config(None if no_config else cfgmod.find_config(path))
        cfgmod.register_profiles(cfg)
    except (InputError, OSError) as exc:
        if not wants_help:
            msg = f"{exc.filename}: {exc.strerror}" if isinstance(exc, OSError) and exc.filename else exc
            print(f"tennislab: error: {_one_line(msg).replace('config: ', '--config: ', 1)}", file=sys.stderr)
            return 2
        cfg = cfgmod.Config()
    parser = build_parser(cfg, commands=_command_of(argv))  # only the group of the command run
    args = parser.parse_args(argv)
    args.config_defaults = cfg.flag_defaults()
    command = _command_name(args)
    try:
        check_io(parser, args)
        cfgmod.resolve_profiles(args, cfg)
        rc = args.func(args)
    except InputError as exc:
        sub = _subparsers(parser).get(args.command)
        msg = flag_message(_one_line(exc), _option_strings(sub) if sub else set())
        print(f"tennislab {command}: error: {msg}", file=sys.stderr)
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
    except OSError as exc:  # a file that cannot be read or written: missing, a directory, no space, ...
        where = _one_line(exc.filename) if exc.filename is not None else ""
        reason = exc.strerror or type(exc).__name__
        print(f"tennislab {command}: error: {where}{': ' if where else ''}{reason}", file=sys.stderr)
        return 2
    except ArithmeticError as exc:  # a division by zero or an overflow the input checks did not foresee
        print(
            f"tennislab {command}: error: the computation failed ({_one_line(exc) or type(exc).__name__}): "
            "an input is outside the range the model answers",
            file=sys.stderr,
        )
        return 2
    return int(rc or 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
