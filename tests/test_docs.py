"""Every example in README.md, CONTRIBUTING.md and docs/*.md is executed, and every output and number the docs quote is
compared with what the command prints now.

Regenerate the docs' outputs after changing what a command prints (one command, from the repository)::

    make docs                                   # = .venv/bin/python tests/test_docs.py --update
    .venv/bin/python tests/test_docs.py --update docs/linecall.md      # one page
    .venv/bin/python tests/test_docs.py --update --records             # also re-run the recorded runs

It rewrites the outputs shown after ``$ tennislab ...`` in place and lists the quoted numbers (below) that
no longer match, for you to reword; CONTRIBUTING.md says how to write each kind.

How a fenced block is treated:

* ```` ```python ```` - executed; the blocks of one file share one namespace, in reading order (like a
  reader typing them into one session).
* a block whose info string has ``file=NAME`` (```` ```toml file=me.toml ````) - written to ``NAME``
  for the examples after it (which check it: a file may hold a mistake on purpose).
* ```` ```toml ```` holding a ``[physics]``, ``[court]``, ``[defaults]``, ``[players.*]`` or
  ``[machines.*]`` table - read as a ``tennislab.toml`` (:func:`tennislab.cli.config.load_config`).
* any other block (```` ```sh ````, ```` ```console ````, untagged, ...) - each line that is a
  ``tennislab`` command (``\\`` continues a line) runs through the CLI entry point; lines that are not
  ``tennislab`` commands (``make``, ``source``, ``pip``) are not run. In a block that writes its
  commands after a ``$ `` prompt, the lines after a command, up to the next prompt, are **its output**:
  they must be what the command prints (stdout; or stderr and stdout when the page shows stderr's
  lines), line by line, ``…`` standing for any text (a time, a date: what differs from run to run).
  An output that starts with ``tennislab ...: error:`` is an error the command must give, exit code 2;
  the message may wrap over several lines. Any other command must exit 0. ``| head -N`` and
  ``| tail -N`` after a command are applied.

Numbers in the prose: a span ``<!-- quotes: COMMAND -->...<!-- /quotes -->`` (invisible on the rendered
page) says that the numbers in it are printed by ``COMMAND`` (``tennislab ...``, or ``python ...`` run from
a copy of the clone). Each number of the span (outside backticks) must equal, at the precision it is
written with and sign aside, a number the command prints. A span ``<!-- output: COMMAND -->`` (a line
of its own) ... ``<!-- /output -->`` is exactly what the command prints (a table a script prints), line by
line with ``…`` as above, and is rewritten by ``--update``. A command too slow for the test suite (a
benchmark) is quoted from its record, ``docs/records/NAME.txt`` (first line ``$ COMMAND``, then its
output), which ``--update --records`` re-runs.

Not run, automatically:

* usage synopses: a command line with ``[optional]`` parts, ``A|B`` alternatives, ``...``, or
  upper-case placeholders (``FILE``, ``X``, ``FILE.csv``);
* ``tennislab app``, which serves until stopped.

Not run, on purpose: a block preceded by the line ``<!-- no-test -->`` (keep these rare; say why
in the text).

The examples of one page run in one fresh temporary folder (a reader's session in a fresh clone),
holding a copy of ``examples/``, a link to ``src/`` (for the shipped data files) and an empty ``out/``,
so outputs (``--plot out/fly.png``, ``--out out/demo``) land there; a test fails when an example leaves a
file in the folder's root (outputs go under ``out/``, which the clone ships empty).
Failures in pages that other engineers are rewriting are marked in :data:`KNOWN_FAILURES`
(``xfail``, not strict) with the reason; each is reported to the lead.
"""

from __future__ import annotations

import contextlib
import io
import math
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import textwrap
from dataclasses import dataclass, field
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = [ROOT / "README.md", ROOT / "CONTRIBUTING.md", *sorted((ROOT / "docs").glob("*.md"))]
RECORDS = ROOT / "docs" / "records"
NO_TEST = "<!-- no-test -->"
SERVERS = {"app"}  #: commands that serve until stopped
CONFIG_TABLES = ("physics", "court", "defaults", "players", "machines")
WILDCARD = "…"  #: in a shown output: any text (what differs from run to run)
WRAP = 118  #: width an error message is wrapped to when regenerated

#: (file relative to the repository, a fragment of the block's first line) -> why it fails today
KNOWN_FAILURES: dict[tuple[str, str], str] = {}


@dataclass(frozen=True)
class Block:
    path: Path
    line: int  # 1-based line of the opening fence
    lang: str
    text: str
    skipped: bool
    file: str | None = None  # ``file=NAME`` in the info string: the block is that file's content

    @property
    def rel(self) -> str:
        return self.path.relative_to(ROOT).as_posix()

    @property
    def id(self) -> str:
        return f"{self.rel}:{self.line}"


_FENCE = re.compile(r"^(\s*)(`{3,}|~{3,})\s*([\w+-]*)(.*)$")


def blocks(path: Path) -> list[Block]:
    """The fenced code blocks of a Markdown file."""
    out: list[Block] = []
    lines = path.read_text(encoding="utf-8").splitlines()
    i = 0
    while i < len(lines):
        m = _FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        fence, lang, start = m.group(2), m.group(3).lower(), i
        fm = re.search(r"\bfile=([\w.\-/]+)", m.group(4))
        prev = next((lines[k].strip() for k in range(i - 1, -1, -1) if lines[k].strip()), "")
        body = []
        i += 1
        while i < len(lines) and not lines[i].strip().startswith(fence):
            body.append(lines[i])
            i += 1
        out.append(Block(path, start + 1, lang, "\n".join(body), prev == NO_TEST, fm.group(1) if fm else None))
        i += 1
    return out


# ------------------------------------------------------------------ commands
@dataclass(frozen=True)
class Command:
    argv: list[str]
    stdout_to: str | None
    expect_error: str | None  # the message a block shows, if the command fails on purpose
    shown: tuple[str, ...] | None = None  # the output the block shows after the command
    pipe: tuple[str, ...] = ()  # ``head -1`` of ``| head -1``
    span: tuple[int, int] | None = None  # the block's body lines [start, end) that show its output or error


_PLACEHOLDER = re.compile(r"^[A-Z][A-Z0-9_]*(\.[a-z0-9]+)?$")
_CAPS = re.compile(r"(^|[^A-Za-z])[A-Z]{2,}([^A-Za-z]|$)")
_ERROR = re.compile(r"^tennislab( [\w-]+)*: error: ")


def is_synopsis(tokens: list[str]) -> bool:
    """A usage line rather than an example (module docstring)."""
    for t in tokens:
        if any(c in t for c in "[]") or t == "..." or ("|" in t and t != "|"):
            return True
        if (_PLACEHOLDER.match(t) or _CAPS.search(t)) and not re.match(r"^[0-9.eE+-]+$", t):
            return True
    return False


def _statements(block: Block) -> list[tuple[str, tuple[int, int] | None]]:
    """(command line, span of the lines shown after it) for each logical line of a block.

    In a block with ``$ `` prompts only the prompted lines are commands and the lines after each, to the
    next prompt, are its output; otherwise every line is a command and nothing is shown."""
    raw = block.text.splitlines()
    prompted = any(line.strip().startswith("$ ") for line in raw)
    out: list[tuple[str, tuple[int, int] | None]] = []
    i = 0
    while i < len(raw):
        line = raw[i].rstrip()
        while line.endswith("\\") and i + 1 < len(raw):
            i += 1
            line = line[:-1] + " " + raw[i].strip()
        i += 1
        s = line.strip()
        if not prompted:
            out.append((s, None))
            continue
        if not s.startswith("$ "):
            continue
        end = i
        while end < len(raw) and not raw[end].strip().startswith("$ "):
            end += 1
        last = end
        while last > i and not raw[last - 1].strip():
            last -= 1
        out.append((s[2:].strip(), (i, last)))
    return out


def commands(block: Block) -> list[Command]:
    """The runnable ``tennislab`` commands of a shell-like block, with what the block shows they print."""
    out = []
    body = block.text.splitlines()
    for s, span in _statements(block):
        if _ERROR.match(s):  # a message the command printed, not a command
            continue
        try:
            tokens = shlex.split(s, comments=True)
        except ValueError:
            continue
        parts = _split_sequence(tokens)
        for k, part in enumerate(parts):
            if not part or part[0] != "tennislab" or is_synopsis(part):
                continue
            if len(part) > 1 and part[1] in SERVERS:
                continue
            head, pipe = _split_pipe(part[1:])
            argv, stdout_to = _redirect(head)
            shown_lines = tuple(body[span[0] : span[1]]) if span and k == len(parts) - 1 else ()
            expect = shown = None
            if shown_lines and _ERROR.match(shown_lines[0].strip()):
                expect = " ".join(" ".join(shown_lines).split()).split(": error: ", 1)[1]
            elif any(line.strip() for line in shown_lines):
                shown = tuple(line.rstrip() for line in shown_lines)
            out.append(Command(argv, stdout_to, expect, shown, pipe, span if shown_lines else None))
    return out


def _split_sequence(tokens: list[str]) -> list[list[str]]:
    parts, cur = [], []
    for t in tokens:
        if t in ("&&", ";", "||"):
            parts.append(cur)
            cur = []
        else:
            cur.append(t)
    parts.append(cur)
    return parts


def _split_pipe(tokens: list[str]) -> tuple[list[str], tuple[str, ...]]:
    if "|" not in tokens:
        return tokens, ()
    i = tokens.index("|")
    return tokens[:i], tuple(tokens[i + 1 :])


def _redirect(tokens: list[str]) -> tuple[list[str], str | None]:
    argv, target = [], None
    it = iter(tokens)
    for t in it:
        if t in (">", "1>"):
            target = next(it, None)
        elif t.startswith(">") and len(t) > 1:
            target = t[1:]
        elif t in ("2>", "2>&1"):
            if t == "2>":
                next(it, None)
        else:
            argv.append(t)
    return argv, target


def _apply_pipe(text: str, pipe: tuple[str, ...]) -> str:
    """``| head -N`` / ``| tail -N`` after a command, as the shell would; another pipe is not applied."""
    m = re.fullmatch(r"(head|tail) -n ?(\d+)|(head|tail) -(\d+)", " ".join(pipe))
    if m is None:
        return text
    kind, n = (m.group(1), m.group(2)) if m.group(1) else (m.group(3), m.group(4))
    lines = text.splitlines(keepends=True)
    return "".join(lines[: int(n)] if kind == "head" else lines[-int(n) :])


def run_command(cmd: Command) -> tuple[int, str, str]:
    from tennislab.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = main(cmd.argv)
        except SystemExit as exc:
            rc = exc.code if isinstance(exc.code, int) else 2
    if cmd.stdout_to:
        Path(cmd.stdout_to).write_text(out.getvalue())
    return rc, _apply_pipe(out.getvalue(), cmd.pipe), err.getvalue()


# ------------------------------------------------------------------ comparing what a page shows
_FLOAT = re.compile(r"\d+\.\d{9,}(?:e[-+]?\d+)?")  #: a number printed at full precision (JSON)
ROUND_OFF = 1e-9  #: relative difference of two full-precision numbers that is round-off, not a change (a miss
#: of 1.2 mm from a landing at 9.5 m moves in its 12th digit)


def _line_matches(shown: str, actual: str) -> bool:
    """``shown`` is ``actual``, ``…`` matching any text and full-precision numbers compared to round-off
    (summation order across threads moves their last digits)."""
    shown, actual = shown.rstrip(), actual.rstrip()
    if shown == actual:
        return True
    pieces = []
    for k, part in enumerate(shown.split(WILDCARD)):
        pieces.append(".*?" if k else "")
        last = 0
        for m in _FLOAT.finditer(part):
            pieces.append(re.escape(part[last : m.start()]) + r"(\d+\.\d+(?:e[-+]?\d+)?)")
            last = m.end()
        pieces.append(re.escape(part[last:]))
    m = re.fullmatch("".join(pieces), actual, re.S)
    if m is None:
        return False
    want = [float(x) for x in _FLOAT.findall(shown)]
    return all(abs(float(g) - w) <= ROUND_OFF * max(abs(w), 1e-300) for g, w in zip(m.groups(), want))


def _lines(text: str) -> list[str]:
    lines = [line.rstrip() for line in text.splitlines()]
    while lines and not lines[-1]:
        lines.pop()
    return lines


def shown_matches(shown: tuple[str, ...], actual: str) -> bool:
    """Whether the output a page shows is what was printed (line by line; ``…`` matches any text)."""
    lines = _lines(actual)
    return len(lines) == len(shown) and all(_line_matches(s, a) for s, a in zip(shown, lines))


def printed(cmd: Command, out: str, err: str) -> str:
    """What the page means to show of a command's output: stdout, or stderr and stdout when it shows
    a line that only stderr has (estimates and progress go to stderr)."""
    if cmd.shown is None or shown_matches(cmd.shown, out):
        return out
    err_shapes = {_shape(e) for e in _lines(err)}
    if any(line.strip() and any(_line_matches(line, e) for e in _lines(err)) for line in cmd.shown) or any(
        line.strip() and _shape(line) in err_shapes for line in cmd.shown
    ):
        return err + out
    return out


def error_matches(expected: str, err: str) -> bool:
    """A shown error (joined over its lines) against the one-line message on stderr."""
    actual = " ".join(err.split()).split(": error: ", 1)[-1]
    return _line_matches(expected, actual)


def check_command(cmd: Command, rc: int, out: str, err: str) -> None:
    shown = "tennislab " + " ".join(cmd.argv)
    regen = "regenerate the docs' outputs with `make docs`"
    if cmd.expect_error is not None:
        assert rc == 2, f"{shown}: expected the documented error, got exit {rc}"
        assert error_matches(cmd.expect_error, err), (
            f"{shown}: the page shows\n  {cmd.expect_error}\nit prints\n  {err}"
        )
        return
    assert rc == 0, f"{shown} exited {rc}: {err.strip()[-500:]}"
    if cmd.shown is not None:
        actual = printed(cmd, out, err)
        assert shown_matches(cmd.shown, actual), (
            f"{shown}: the page shows\n" + "\n".join(cmd.shown) + "\n-- it prints --\n" + actual + f"\n({regen})"
        )


# ------------------------------------------------------------------ quoted numbers
_QUOTE = re.compile(r"<!--\s*quotes:\s*(.*?)\s*-->(.*?)<!--\s*/quotes\s*-->", re.S)
_NUMBER = re.compile(r"(?<![\w.\-−+^])([-−+]?)(\d{1,3}(?:,\d{3})+|\d+)(\.\d+)?(?:[eE]([-+]?\d+))?(?![\w])")


@dataclass(frozen=True)
class Quote:
    path: Path
    line: int
    command: str
    text: str

    @property
    def id(self) -> str:
        return f"{self.path.relative_to(ROOT).as_posix()}:{self.line}"


def quotes(path: Path) -> list[Quote]:
    """The ``<!-- quotes: COMMAND -->...<!-- /quotes -->`` spans of a page."""
    text = path.read_text(encoding="utf-8")
    return [
        Quote(path, text.count("\n", 0, m.start()) + 1, " ".join(m.group(1).split()), m.group(2))
        for m in _QUOTE.finditer(text)
    ]


@dataclass(frozen=True)
class Number:
    text: str
    value: float
    decimals: int


def numbers(text: str) -> list[Number]:
    """The numbers of a text: ``−0.6``, ``1,565``, ``2.4e7``, ``0.1–3.5`` (two), not those inside words
    (``p90``, ``x2``, ``stepanek1988``) or code spans."""
    text = re.sub(r"`[^`]*`", " ", text)
    out = []
    for m in _NUMBER.finditer(text):
        sign, whole, frac, exp = m.groups()
        s = whole.replace(",", "") + (frac or "")
        value = float(s) * (10 ** int(exp) if exp else 1)
        decimals = len(frac) - 1 if frac else 0
        if exp:
            decimals = max(0, decimals - int(exp))
        out.append(Number(m.group(0), -value if sign in "-−" and sign else value, decimals))
    return out


def number_in(q: Number, printed_numbers: list[float]) -> bool:
    """``q`` as written is one of the printed numbers rounded to its precision (sign aside)."""
    half = 0.5 * 10.0 ** (-q.decimals)
    return any(math.isfinite(v) and abs(abs(v) - abs(q.value)) <= half * (1 + 1e-9) for v in printed_numbers)


def record(command: str) -> Path | None:
    """The record of a slow command, if it has one."""
    for p in sorted(RECORDS.glob("*.txt")) if RECORDS.is_dir() else ():
        first = p.read_text(encoding="utf-8").split("\n", 1)[0]
        if " ".join(first.removeprefix("$ ").split()) == command:
            return p
    return None


_QUOTED_OUTPUT: dict[str, str] = {}


def quoted_output(command: str) -> str:
    """What a quoted command prints: its record, else a fresh run in a fresh clone's folder (cached)."""
    rec = record(command)
    if rec is not None:
        return rec.read_text(encoding="utf-8").split("\n", 1)[1]
    if command not in _QUOTED_OUTPUT:
        _QUOTED_OUTPUT[command] = _run_fresh(command)
    return _QUOTED_OUTPUT[command]


def _run_fresh(command: str) -> str:
    tokens = shlex.split(command)
    with tempfile.TemporaryDirectory(prefix="docs-quote-") as d:
        folder = make_folder(Path(d))
        if tokens[0] == "tennislab":
            cmd = Command(tokens[1:], None, None)
            with _chdir(folder):
                rc, out, err = run_command(cmd)
        else:
            exe = [sys.executable] if tokens[0] in ("python", "python3") else [tokens[0]]
            env = dict(os.environ, MPLBACKEND="Agg")
            proc = subprocess.run(exe + tokens[1:], cwd=folder, capture_output=True, text=True, env=env, timeout=3600)
            rc, out, err = proc.returncode, proc.stdout, proc.stderr
    if rc != 0:
        raise AssertionError(f"quoted command `{command}` exited {rc}: {err.strip()[-500:]}")
    return out + err


# ------------------------------------------------------------------ generated spans
_GENERATED = re.compile(r"<!--\s*output:\s*(.*?)\s*-->\n(.*?)<!--\s*/output\s*-->", re.S)


def generated(path: Path) -> list[Quote]:
    """The ``<!-- output: COMMAND -->`` ... ``<!-- /output -->`` spans of a page: text that is exactly what
    the command prints (a table a script prints, say), rewritten by ``make docs``."""
    text = path.read_text(encoding="utf-8")
    return [
        Quote(path, text.count("\n", 0, m.start()) + 1, " ".join(m.group(1).split()), m.group(2))
        for m in _GENERATED.finditer(text)
    ]


def generated_matches(g: Quote) -> bool:
    return shown_matches(tuple(_lines(g.text)), quoted_output(g.command))


def update_generated(path: Path) -> int:
    """Rewrite the generated spans of a page that no longer match; returns how many."""
    text = path.read_text(encoding="utf-8")
    changed = 0

    def _new(m: re.Match) -> str:
        nonlocal changed
        g = Quote(path, 0, " ".join(m.group(1).split()), m.group(2))
        if generated_matches(g):
            return m.group(0)
        changed += 1
        return (
            m.group(0)[: m.start(2) - m.start(0)] + "\n".join(_lines(quoted_output(g.command))) + "\n<!-- /output -->"
        )

    path.write_text(_GENERATED.sub(_new, text), encoding="utf-8")
    return changed


def stale_numbers(q: Quote) -> list[str]:
    """The numbers of a quote that the command does not print."""
    printed_numbers = [n.value for n in numbers(quoted_output(q.command).replace("`", ""))]
    return [n.text for n in numbers(q.text) if not number_in(n, printed_numbers)]


# ------------------------------------------------------------------ a reader's folder
def make_folder(d: Path) -> Path:
    """A fresh clone's folder as the examples see it: examples/ copied, src/ and benchmarks/ linked, out/ empty."""
    if (ROOT / "examples").is_dir():
        shutil.copytree(ROOT / "examples", d / "examples")
    (d / "src").symlink_to(ROOT / "src", target_is_directory=True)
    (d / "benchmarks").symlink_to(ROOT / "benchmarks", target_is_directory=True)
    (d / "out").mkdir()  # the clone ships it empty (out/.gitignore): examples write there
    return d


#: what a page's folder holds besides what its examples write
FOLDER_ROOT = {"examples", "src", "benchmarks", "out"}


@contextlib.contextmanager
def _chdir(d: Path):
    old = os.getcwd()
    os.chdir(d)
    try:
        yield
    finally:
        os.chdir(old)


# ------------------------------------------------------------------ collection
def _kind(b: Block) -> str | None:
    if b.file:
        return "file"
    if b.lang in ("python", "py"):
        return "python"
    if b.lang == "toml":
        head = re.findall(r"^\s*\[+\s*([\w-]+)", b.text, re.M)
        return "toml" if head and all(h in CONFIG_TABLES for h in head) else None
    if b.lang in ("", "sh", "bash", "shell", "console", "zsh") and commands(b):
        return "shell"
    return None


ALL = [b for path in DOCS for b in blocks(path)]
RUNNABLE = [b for b in ALL if _kind(b)]
QUOTES = [q for path in DOCS for q in quotes(path)]
GENERATED = [g for path in DOCS for g in generated(path)]


def _params():
    for b in RUNNABLE:
        marks = []
        first = b.text.strip().splitlines()[0] if b.text.strip() else ""
        for (rel, fragment), why in KNOWN_FAILURES.items():
            if rel == b.rel and fragment in first:
                marks.append(pytest.mark.xfail(reason=why, strict=False))
        if b.skipped:
            marks.append(pytest.mark.skip(reason=f"{NO_TEST} in {b.rel}"))
        yield pytest.param(b, id=b.id, marks=marks)


def _root_allowed(block: Block) -> set[str]:
    """Names the examples of ``block``'s page may leave in the folder's root: the clone's own entries, the
    files the page tells the reader to write (``file=NAME``) and the ``tennislab.toml`` it shows."""
    own = {Path(b.file).parts[0] for b in RUNNABLE if b.path == block.path and b.file}
    toml = {"tennislab.toml"} if any(b.path == block.path and _kind(b) == "toml" for b in RUNNABLE) else set()
    return FOLDER_ROOT | own | toml


@dataclass
class Page:
    """One page's session: its folder and the Python namespace its blocks share."""

    folder: Path
    namespace: dict = field(default_factory=lambda: {"__name__": "__docs__"})
    done: int = 0  # line of the last block run


def run_block(block: Block, page: Page) -> list[tuple[Command, int, str, str]]:
    """Run one block in its page's session; the commands it ran with (exit code, stdout, stderr)."""
    kind = _kind(block)
    folder = page.folder
    for b in RUNNABLE:  # files the page wrote before this block (also when a block is run alone)
        if b.path == block.path and b.file and b.line < block.line:
            (folder / b.file).parent.mkdir(parents=True, exist_ok=True)
            (folder / b.file).write_text(b.text + "\n")
    if kind == "file":
        (folder / block.file).parent.mkdir(parents=True, exist_ok=True)
        (folder / block.file).write_text(block.text + "\n")  # the commands after it use (and check) it
        return []
    if kind == "python":
        if page.done > block.line:  # run out of order (e.g. -k): start again
            page.namespace, page.done = {"__name__": "__docs__"}, 0
        for b in RUNNABLE:
            if b.path == block.path and _kind(b) == "python" and page.done < b.line < block.line and not b.skipped:
                exec(compile(b.text, b.id, "exec"), page.namespace)
        try:
            exec(compile(block.text, block.id, "exec"), page.namespace)
        finally:
            page.done = block.line
        return []
    if kind == "toml":
        from tennislab.cli.config import load_config

        (folder / "tennislab.toml").write_text(block.text)
        load_config("tennislab.toml")
        return []
    return [(cmd, *run_command(cmd)) for cmd in commands(block)]


# ------------------------------------------------------------------ tests
_PAGES: dict[Path, Page] = {}


@pytest.fixture(autouse=True)
def _restore_player_registry():
    """Player profiles registered by the examples must not leak into other tests."""
    from tennislab.serve import players

    saved = dict(players._PLAYERS), dict(players._ALIASES)
    yield
    players._PLAYERS.clear()
    players._PLAYERS.update(saved[0])
    players._ALIASES.clear()
    players._ALIASES.update(saved[1])


@pytest.fixture
def docs_page(block, tmp_path_factory, monkeypatch):
    """The page's session, shared by its blocks (a reader's folder in a fresh clone)."""
    p = _PAGES.get(block.path)
    if p is None:
        p = _PAGES[block.path] = Page(make_folder(tmp_path_factory.mktemp("docs-" + block.path.stem)))
    monkeypatch.chdir(p.folder)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    return p


@pytest.mark.parametrize("block", list(_params()))
def test_docs_example(block: Block, docs_page: Page):
    for cmd, rc, out, err in run_block(block, docs_page):
        check_command(cmd, rc, out, err)
    stray = sorted({p.name for p in docs_page.folder.iterdir()} - _root_allowed(block))
    assert not stray, f"{block.id}: the examples leave {stray} in the clone's root; write outputs under out/"


@pytest.mark.parametrize("quote", QUOTES, ids=[q.id for q in QUOTES])
def test_quoted_numbers(quote: Quote):
    stale = stale_numbers(quote)
    assert not stale, (
        f"{quote.id}: {stale} are not printed by `{quote.command}`; it prints:\n{quoted_output(quote.command)}"
    )


@pytest.mark.parametrize("span", GENERATED, ids=[g.id for g in GENERATED])
def test_generated_spans(span: Quote):
    assert generated_matches(span), (
        f"{span.id}: the page shows\n{span.text}\n-- `{span.command}` prints --\n{quoted_output(span.command)}\n"
        "(regenerate the docs' outputs with `make docs`)"
    )


def test_generated_spans_are_found_and_rewritten(tmp_path):
    from tennislab import __version__

    page = tmp_path / "p.md"
    page.write_text("a\n<!-- output: tennislab --version -->\ntennislab 0.0.1\n<!-- /output -->\nb\n")
    (g,) = generated(page)
    assert g.command == "tennislab --version" and not generated_matches(g)
    assert update_generated(page) == 1 and update_generated(page) == 0
    assert (
        page.read_text() == f"a\n<!-- output: tennislab --version -->\ntennislab {__version__}\n<!-- /output -->\nb\n"
    )


def test_the_harness_finds_the_readme_examples():
    readme = [b for b in RUNNABLE if b.rel == "README.md"]
    assert any(_kind(b) == "python" for b in readme)
    assert sum(len(commands(b)) for b in readme if _kind(b) == "shell") >= 4


@pytest.mark.parametrize(
    "line,synopsis",
    [
        ("tennislab fly --speed-kmh 120 --elevation-deg 6", False),
        ("tennislab call --track FILE.csv [--json]", True),
        ("tennislab launcher aim --target X Y --speed-kmh S", True),
        ("tennislab launcher drill FILE|NAME", True),
        ("tennislab serve-window --player pro --json", False),
        ("tennislab fly --position -11.885 0 1 --velocity 30 0 5 --wind 1e-3 0 0", False),
        ("tennislab serve-mc --scheduler tcp://HOST:PORT", True),
    ],
)
def test_synopsis_lines_are_recognised(line, synopsis):
    assert is_synopsis(shlex.split(line)) is synopsis


def _block(text: str, lang: str = "console") -> Block:
    return Block(ROOT / "docs" / "x.md", 1, lang, text, False)


def test_console_blocks_expect_documented_errors():
    b = _block("$ tennislab fly --velocity 1e9 0 7\ntennislab fly: error: --velocity: |v| = 1e+09 m/s is\n  outside …")
    (cmd,) = commands(b)
    assert cmd.expect_error == "--velocity: |v| = 1e+09 m/s is outside …" and cmd.shown is None
    rc, out, err = run_command(cmd)
    check_command(cmd, rc, out, err)
    with pytest.raises(AssertionError, match="the page shows"):
        check_command(Command(cmd.argv, None, "--velocity: |v| = 2e+09 m/s …"), rc, out, err)


def test_shown_outputs_are_compared_line_by_line_with_wildcards():
    b = _block("$ tennislab fly --velocity 30 0 5 | head -1\nlaunch: …\n\n$ tennislab --version\ntennislab …")
    first, second = commands(b)
    assert first.pipe == ("head", "-1") and first.shown == ("launch: …",) and first.span == (1, 2)
    rc, out, err = run_command(first)
    assert rc == 0 and out.count("\n") == 1
    check_command(first, rc, out, err)
    with pytest.raises(AssertionError, match="make docs"):
        check_command(Command(first.argv, None, None, ("landing: …",)), rc, out, err)
    assert shown_matches(("a 1 … s", "b"), "a 1 2.5 s\nb\n\n") and not shown_matches(("a 1 … s",), "a 2 2.5 s")
    assert shown_matches(('{"x":9.500848224017659}',), '{"x":9.500848224017663}')  # round-off
    assert not shown_matches(('{"x":9.500848224017659}',), '{"x":9.500848234017659}')
    assert not shown_matches(("x 9.5008",), "x 9.5009")  # a printed, rounded number is exact
    assert second.shown == ("tennislab …",) and second.span == (4, 5)


def test_numbers_are_read_as_written():
    got = [(n.value, n.decimals) for n in numbers("−0.6 mm, p_in 0.410, 1,565 hits, 2.4e7, 0.1–3.5 m, p90 `x 7`")]
    assert got == [(-0.6, 1), (0.41, 3), (1565, 0), (2.4e7, 0), (0.1, 1), (3.5, 1)]
    assert number_in(numbers("1.3")[0], [1.2999]) and not number_in(numbers("1.3")[0], [1.36, -0.6])
    assert number_in(numbers("0.6")[0], [-0.6]) and number_in(numbers("92.6")[0], [92.58])


def test_a_stale_quote_is_found(tmp_path):
    from tennislab import __version__

    page = tmp_path / "p.md"
    page.write_text(
        f"x\n<!-- quotes: tennislab --version -->tennislab {__version__}<!-- /quotes -->\n"
        "<!-- quotes: tennislab  --version -->\nversion 97.5 <!-- /quotes -->"
    )
    good, bad = quotes(page)
    assert good.line == 2 and bad.command == "tennislab --version"
    assert stale_numbers(good) == [] and stale_numbers(bad) == ["97.5"]


def test_what_varies_between_runs_becomes_a_wildcard():
    got = _volatile(["fit: 4.56 mm, 199 ms; (9.07 ms)", "x"], ["fit: 4.56 mm, 201 ms; (9.11 ms)", "x"])
    assert got == ["fit: 4.56 mm, … ms; (… ms)", "x"]
    assert _volatile(["created 2026-12-01T18:27:38Z by"], ["created 2026-12-01T18:27:40Z by"]) == ["created … by"]
    assert _volatile(["a b"], ["a b c"]) == ["a b"] and _volatile(["a", "b"], ["a"]) == ["a", "b"]
    # lines of one shape share what varies, also where the two runs agreed by chance
    assert _volatile(["1 hit; 0.2 s", "2 hits; 0.4 s"], ["1 hit; 0.3 s", "2 hits; 0.4 s"]) == [
        "1 hit; … s",
        "2 hits; 0.4 s",
    ]
    assert _volatile(["hit 1; 0.2 s", "hit 2; 0.4 s"], ["hit 1; 0.3 s", "hit 2; 0.4 s"]) == ["hit 1; … s", "hit 2; … s"]


def test_no_test_markers_stay_rare():
    skipped = [b.id for b in ALL if b.skipped]
    assert len(skipped) <= 5, skipped


def test_records_are_quoted():
    quoted = {q.command for q in QUOTES}
    for p in sorted(RECORDS.glob("*.txt")) if RECORDS.is_dir() else ():
        first = p.read_text(encoding="utf-8").split("\n", 1)[0]
        assert first.startswith("$ "), f"{p.name}: the first line is `$ COMMAND`"
        assert " ".join(first[2:].split()) in quoted, f"{p.name}: no page quotes it"


# ------------------------------------------------------------------ regenerating (make docs)
def _shape(line: str) -> str:
    return re.sub(r"\d+", "#", line)


def _varying(a: str, b: str) -> set[int]:
    """The positions of the words of line ``a`` that differ in ``b`` (the same line of a second run)."""
    wa, wb = a.split(" "), b.split(" ")
    return {i for i, (x, y) in enumerate(zip(wa, wb)) if x != y} if len(wa) == len(wb) else set()


def _wildcarded(line: str, positions: set[int]) -> str:
    """``line`` with the number-like part of the words at ``positions`` replaced by ``…``."""
    words = line.split(" ")
    for i in sorted(positions):
        if i >= len(words):
            continue
        m = re.fullmatch(r"(\W*?)([\w.,:+\-−/]*\w)(\W*)", words[i])
        words[i] = (m.group(1) + WILDCARD + m.group(3)) if m else WILDCARD
    return re.sub(f"{WILDCARD}( {WILDCARD})+", WILDCARD, " ".join(words))


def _volatile(first: list[str], second: list[str]) -> list[str]:
    """The lines of a first run with what differs in a second run replaced by ``…``; lines of one shape
    (the same but for their digits) share their varying positions (a time the two runs happened to agree on)."""
    if len(first) != len(second):
        return first
    varying = [_varying(a, b) for a, b in zip(first, second)]
    by_shape: dict[str, set[int]] = {}
    for line, v in zip(first, varying):
        by_shape.setdefault(_shape(line), set()).update(v)
    return [_wildcarded(line, by_shape[_shape(line)]) if by_shape[_shape(line)] else line for line in first]


def _new_lines(cmd: Command, runs: list[tuple[int, str, str]]) -> list[str] | None:
    """The lines a page should show for ``cmd`` after runs of it (None: leave the page as it is)."""
    rc, out, err = runs[0]
    if cmd.expect_error is not None:
        if rc != 2 or error_matches(cmd.expect_error, err):
            return None
        line = err.strip().splitlines()[-1] if err.strip() else ""
        if len(runs) > 1 and runs[1][2].strip():
            line = _volatile([line], [runs[1][2].strip().splitlines()[-1]])[0]
        return textwrap.wrap(line, WRAP, break_long_words=False, break_on_hyphens=False)
    if rc != 0 or cmd.shown is None or shown_matches(cmd.shown, printed(cmd, out, err)):
        return None
    new = _lines(printed(cmd, out, err))
    if len(runs) > 1:
        again = _lines(printed(cmd, runs[1][1], runs[1][2]))
        new = _volatile(new, again)
    old = list(cmd.shown)
    return [
        o if i < len(old) and _line_matches(o, n) else n for i, (o, n) in enumerate(zip(old + [""] * len(new), new))
    ]


def _run_page(path: Path) -> dict[tuple[int, int], tuple[int, str, str]]:
    """Run every example of a page in a fresh folder, in order: (block line, command index) -> result."""
    from tennislab.serve import players

    saved = dict(players._PLAYERS), dict(players._ALIASES)
    results: dict[tuple[int, int], tuple[int, str, str]] = {}
    with tempfile.TemporaryDirectory(prefix="docs-" + path.stem + "-") as d, _chdir(Path(d)):
        page = Page(make_folder(Path(d)))
        for b in (b for b in RUNNABLE if b.path == path and not b.skipped):
            try:
                with contextlib.redirect_stdout(io.StringIO()):  # what the page's Python prints
                    ran = run_block(b, page)
            except Exception as exc:  # report and go on: the page is regenerated as far as it runs
                print(f"{b.id}: {type(exc).__name__}: {exc}", file=sys.stderr)
                continue
            for k, (_, rc, out, err) in enumerate(ran):
                results[(b.line, k)] = (rc, out, err)
    players._PLAYERS.clear()
    players._PLAYERS.update(saved[0])
    players._ALIASES.clear()
    players._ALIASES.update(saved[1])
    return results


def update_page(path: Path, twice: bool = True) -> int:
    """Rewrite the outputs a page shows from fresh runs; returns how many changed."""
    runs = [_run_page(path)] + ([_run_page(path)] if twice else [])
    lines = path.read_text(encoding="utf-8").split("\n")
    changed = 0
    for b in sorted((b for b in RUNNABLE if b.path == path and _kind(b) == "shell"), key=lambda b: -b.line):
        for k, cmd in sorted(enumerate(commands(b)), key=lambda kc: -kc[0]):
            got = [r[(b.line, k)] for r in runs if (b.line, k) in r]
            new = _new_lines(cmd, got) if got and cmd.span else None
            if new is None:
                continue
            start, end = b.line + cmd.span[0], b.line + cmd.span[1]  # body line i is file line b.line + i
            if lines[start:end] != new:
                lines[start:end] = new
                changed += 1
    path.write_text("\n".join(lines), encoding="utf-8")
    return changed


def update_records() -> None:
    for p in sorted(RECORDS.glob("*.txt")) if RECORDS.is_dir() else ():
        first = p.read_text(encoding="utf-8").split("\n", 1)[0]
        print(f"re-running {first}", file=sys.stderr)
        p.write_text(first + "\n" + _run_fresh(" ".join(first[2:].split())), encoding="utf-8")


def main(argv: list[str]) -> int:
    import argparse

    ap = argparse.ArgumentParser(description="Check or regenerate the outputs and numbers the docs quote.")
    ap.add_argument("pages", nargs="*", help="pages (default: README.md and docs/*.md)")
    ap.add_argument("--update", action="store_true", help="rewrite the outputs shown after `$ tennislab ...`")
    ap.add_argument("--records", action="store_true", help="re-run the records in docs/records/ (slow) first")
    ap.add_argument("--once", action="store_true", help="run each page once (no `…` for what varies)")
    args = ap.parse_args(argv)
    os.environ.setdefault("MPLBACKEND", "Agg")
    pages = [Path(p).resolve() for p in args.pages] or DOCS
    if args.records and args.update:
        update_records()
    if args.update:
        for path in pages:
            n = update_page(path, twice=not args.once) + update_generated(path)
            print(f"{path.relative_to(ROOT)}: {n} output(s) rewritten", file=sys.stderr)
    stale = 0
    for path in pages:
        for q in quotes(path):
            bad = stale_numbers(q)
            if bad:
                stale += 1
                print(f"{q.id}: `{q.command}` does not print {', '.join(bad)}: reword the span", file=sys.stderr)
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
