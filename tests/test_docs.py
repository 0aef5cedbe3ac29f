"""Every example in README.md and docs/*.md is executed (issue 17: "every README snippet and docs example").

How a fenced block is treated:

* ```` ```python ```` - executed; the blocks of one file share one namespace, in reading order (like a
  reader typing them into one session).
* a block whose info string has ``file=NAME`` (```` ```toml file=me.toml ````) - written to ``NAME``
  for the examples after it (which check it: a file may hold a mistake on purpose).
* ```` ```toml ```` holding a ``[physics]``, ``[court]``, ``[defaults]``, ``[players.*]`` or
  ``[machines.*]`` table - read as a ``tennislab.toml`` (:func:`tennislab.cli.config.load_config`).
* any other block (```` ```sh ````, ```` ```console ````, untagged, ...) - each line that is a
  ``tennislab`` command (``$ `` prompt optional; ``\\`` continues a line) runs through the CLI entry
  point; lines that are not ``tennislab`` commands (``make``, ``source``, ``pip``, output) are not run.
  In a ``console`` block, a command whose next line starts with ``tennislab ...: error:`` is expected to
  fail with exit code 2 and that message; any other command must exit 0.

Not run, automatically:

* usage synopses: a command line with ``[optional]`` parts, ``A|B`` alternatives, ``...``, or
  upper-case placeholders (``FILE``, ``X``, ``FILE.csv``);
* ``tennislab app``, which serves until stopped.

Not run, on purpose: a block preceded by the line ``<!-- no-test -->`` (keep these rare; say why
in the text).

The examples of one page run in one fresh temporary folder (a reader's session), holding a copy of
``examples/`` and a link to ``src/`` (for the shipped data files), so outputs (``--plot fly.png``,
``--out out/demo``) land there; a test fails when an example leaves a file in the folder's root
(outputs go under ``out/``, which the clone ships empty).
Failures in pages that other engineers are rewriting are marked in :data:`KNOWN_FAILURES`
(``xfail``, not strict) with the reason; each is reported to the lead.
"""

from __future__ import annotations

import contextlib
import io
import re
import shlex
import shutil
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
NO_TEST = "<!-- no-test -->"
SERVERS = {"app"}  #: commands that serve until stopped
CONFIG_TABLES = ("physics", "court", "defaults", "players", "machines")

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
    expect_error: str | None  # the message a console block shows, if the command fails on purpose


_PLACEHOLDER = re.compile(r"^[A-Z][A-Z0-9_]*(\.[a-z0-9]+)?$")
_CAPS = re.compile(r"(^|[^A-Za-z])[A-Z]{2,}([^A-Za-z]|$)")


def is_synopsis(tokens: list[str]) -> bool:
    """A usage line rather than an example (module docstring)."""
    for t in tokens:
        if any(c in t for c in "[]") or t == "..." or ("|" in t and t != "|"):
            return True
        if (_PLACEHOLDER.match(t) or _CAPS.search(t)) and not re.match(r"^[0-9.eE+-]+$", t):
            return True
    return False


def _logical_lines(text: str) -> list[str]:
    out, cur = [], ""
    for raw in text.splitlines():
        line = raw.rstrip()
        if line.endswith("\\"):
            cur += line[:-1] + " "
            continue
        out.append(cur + line)
        cur = ""
    if cur:
        out.append(cur)
    return out


def commands(block: Block) -> list[Command]:
    """The runnable ``tennislab`` commands of a shell-like block."""
    lines = _logical_lines(block.text)
    out = []
    console = block.lang == "console"
    for k, line in enumerate(lines):
        s = line.strip()
        if console and not s.startswith("$ "):
            continue
        if s.startswith("$ "):  # the prompt is optional in every block
            s = s[2:].strip()
        if re.match(r"^tennislab( [\w-]+)*: ", s):  # a message the command printed, not a command
            continue
        try:
            tokens = shlex.split(s, comments=True)
        except ValueError:
            continue
        for part in _split_sequence(tokens):
            if not part or part[0] != "tennislab" or is_synopsis(part):
                continue
            if len(part) > 1 and part[1] in SERVERS:
                continue
            argv, stdout_to = _redirect(_before_pipe(part[1:]))
            expect = None
            if console and k + 1 < len(lines):
                nxt = lines[k + 1].strip()
                if re.match(r"^tennislab( [\w-]+)*: error: ", nxt):
                    expect = nxt.split(": error: ", 1)[1]
            out.append(Command(argv, stdout_to, expect))
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


def _before_pipe(tokens: list[str]) -> list[str]:
    return tokens[: tokens.index("|")] if "|" in tokens else tokens


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
    return rc, out.getvalue(), err.getvalue()


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


_SANDBOXES: dict[Path, Path] = {}


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
def sandbox(block, tmp_path_factory, monkeypatch):
    """The page's folder: examples/ (copied) and src/ (linked, for shipped data), shared by its blocks."""
    d = _SANDBOXES.get(block.path)
    if d is None:
        d = tmp_path_factory.mktemp("docs-" + block.path.stem)
        if (ROOT / "examples").is_dir():
            shutil.copytree(ROOT / "examples", d / "examples")
        (d / "src").symlink_to(ROOT / "src", target_is_directory=True)
        (d / "out").mkdir()  # the clone ships it empty (out/.gitignore): examples write there
        _SANDBOXES[block.path] = d
    for b in RUNNABLE:  # files the page wrote before this block (also when a block is run alone)
        if b.path == block.path and b.file and b.line < block.line:
            (d / b.file).parent.mkdir(parents=True, exist_ok=True)
            (d / b.file).write_text(b.text + "\n")
    monkeypatch.chdir(d)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    return d


_NAMESPACES: dict[Path, tuple[int, dict]] = {}


def _namespace_before(block: Block) -> dict:
    """The namespace of ``block``'s file after running every earlier Python block of it."""
    done, ns = _NAMESPACES.get(block.path, (0, {"__name__": "__docs__"}))
    earlier = [b for b in RUNNABLE if b.path == block.path and _kind(b) == "python" and b.line < block.line]
    if done > block.line:  # run out of order (e.g. -k): start again
        done, ns = 0, {"__name__": "__docs__"}
    for b in earlier:
        if b.line > done and not b.skipped:
            exec(compile(b.text, f"{b.id}", "exec"), ns)
    return ns


#: what a page's folder holds besides what its examples write: the clone's examples/, src/ and out/
SANDBOX_ROOT = {"examples", "src", "out"}


def _root_allowed(block: Block) -> set[str]:
    """Names the examples of ``block``'s page may leave in the folder's root: the clone's own entries, the
    files the page tells the reader to write (``file=NAME``) and the ``tennislab.toml`` it shows."""
    own = {Path(b.file).parts[0] for b in RUNNABLE if b.path == block.path and b.file}
    toml = {"tennislab.toml"} if any(b.path == block.path and _kind(b) == "toml" for b in RUNNABLE) else set()
    return SANDBOX_ROOT | own | toml


@pytest.mark.parametrize("block", list(_params()))
def test_docs_example(block: Block, sandbox):
    _run_block(block, sandbox)
    stray = sorted(set(p.name for p in sandbox.iterdir()) - _root_allowed(block))
    assert not stray, f"{block.id}: the examples leave {stray} in the clone's root; write outputs under out/"


def _run_block(block: Block, sandbox: Path) -> None:
    kind = _kind(block)
    if kind == "file":
        (sandbox / block.file).parent.mkdir(parents=True, exist_ok=True)
        (sandbox / block.file).write_text(block.text + "\n")  # the commands after it use (and check) it
        return
    if kind == "python":
        ns = _namespace_before(block)
        try:
            exec(compile(block.text, block.id, "exec"), ns)
        finally:
            _NAMESPACES[block.path] = (block.line, ns)
        return
    if kind == "toml":
        from tennislab.cli.config import load_config

        (sandbox / "tennislab.toml").write_text(block.text)
        load_config("tennislab.toml")
        return
    for cmd in commands(block):
        rc, out, err = run_command(cmd)
        shown = "tennislab " + " ".join(cmd.argv)
        if cmd.expect_error is not None:
            assert rc == 2, f"{shown}: expected the documented error, got exit {rc}"
            assert cmd.expect_error.rstrip(".…") in " ".join(err.split()), f"{shown}: {err}"
        else:
            assert rc == 0, f"{shown} exited {rc}: {err.strip()[-500:]}"


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


def test_console_blocks_expect_documented_errors(tmp_path):
    b = Block(
        tmp_path / "x.md",
        1,
        "console",
        "$ tennislab fly --velocity 1e9 0 7\ntennislab fly: error: --velocity: |v| = 1e+09 m/s is outside",
        False,
    )
    (cmd,) = commands(b)
    assert cmd.expect_error.startswith("--velocity: |v|")
    rc, _, err = run_command(cmd)
    assert rc == 2 and cmd.expect_error in err


def test_no_test_markers_stay_rare():
    skipped = [b.id for b in ALL if b.skipped]
    assert len(skipped) <= 5, skipped
