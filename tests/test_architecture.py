"""The layers of docs/architecture.md, checked on the source: no import circle, no upward arrow,
front-ends that do not import each other, no ``try: import`` of tennislab's own modules."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "tennislab"

#: floor of each top-level part of the package (a module may import its own floor or lower ones)
FLOORS = {
    "errors": 0,
    "units": 0,
    "results": 0,
    "core": 1,
    "io": 1,
    "batch": 2,
    "trajectory": 3,
    "linecall": 3,
    "serve": 3,
    "launcher": 3,
    "calibrate": 3,
    "plot": 4,
    "cli": 5,
    "app": 5,
    "report": 5,
    "demo": 6,
    "__main__": 6,
    "__init__": 0,
    "_lazy": 0,
}
FRONT_ENDS = {"cli", "app", "report"}
#: the only front-end -> front-end arrows: the commands that start the app and build the report
ALLOWED_FRONT = {("cli.app", "app"), ("cli.report", "report"), ("demo", "cli"), ("__main__", "cli")}


def _modules() -> dict[str, Path]:
    out = {}
    for p in SRC.rglob("*.py"):
        rel = p.relative_to(SRC).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__" and len(parts) > 1:
            parts = parts[:-1]
        out[".".join(parts)] = p
    return out


def _typing_only_lines(tree: ast.AST) -> set[int]:
    """Lines inside ``if TYPE_CHECKING:`` blocks (a package stub's declarations: no import at run time)."""
    out: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING":
            for sub in node.body:
                out.update(n.lineno for n in ast.walk(sub) if hasattr(n, "lineno"))
    return out


def _imports(mod: str, path: Path) -> list[tuple[str, int, bool, bool]]:
    """(imported tennislab module, line, inside try/except ImportError, inside ``if TYPE_CHECKING:``) per import."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    guarded: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Try):
            names = []
            for h in node.handlers:
                t = h.type
                names += [getattr(e, "id", "") for e in (t.elts if isinstance(t, ast.Tuple) else [t])] if t else []
            if {"ImportError", "ModuleNotFoundError"} & set(names):
                for sub in node.body:
                    guarded.update(n.lineno for n in ast.walk(sub) if hasattr(n, "lineno"))
    typing_only = _typing_only_lines(tree)
    is_pkg = path.name == "__init__.py"
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = mod.split(".")
                base = base[: len(base) - node.level + (1 if is_pkg else 0)]
                name = ".".join(base + ([node.module] if node.module else []))
            else:
                name = node.module or ""
            cands = [name] + [f"{name}.{a.name}" for a in node.names]
        elif isinstance(node, ast.Import):
            cands = [a.name for a in node.names]
        else:
            continue
        for c in cands:
            if c == "tennislab" or c.startswith("tennislab."):
                ln = node.lineno
                out.append((c.removeprefix("tennislab").lstrip("."), ln, ln in guarded, ln in typing_only))
    return out


MODS = _modules()


def _is_package(mod: str) -> bool:
    return MODS[mod].name == "__init__.py"


#: every import (run time and a stub's declarations): the layers hold for both
EDGES = {m: {(t, ln, g) for t, ln, g, _ in _imports(m, p) if t in MODS and t != m} for m, p in MODS.items()}
#: every import as an edge, a stub's ``if TYPE_CHECKING:`` declarations too (a reader, a type checker and
#: ``python3 ../shared/hooks/import_graph.py`` follow them): ``from tennislab.pkg import sub`` inside ``pkg``
#: is an edge to the stub as well, so write ``import tennislab.pkg.sub as sub`` there
ALL_EDGES = {m: {t for t, _, _, _ in _imports(m, p) if t in MODS and t != m} for m, p in MODS.items()}


def _part(mod: str) -> str:
    return mod.split(".")[0] if mod else "__init__"


def test_no_import_circles():
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    circles = []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in ALL_EDGES.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                circles.append(sorted(comp))

    for v in MODS:
        if v not in index:
            visit(v)
    assert not circles, f"import circles: {circles}"


def test_no_upward_arrows_and_front_ends_apart():
    bad = []
    for m, targets in EDGES.items():
        pm = _part(m)
        for t, line, _ in targets:
            pt = _part(t)
            if pm == pt:
                continue
            if pm in FRONT_ENDS | {"demo", "__main__"} and pt in FRONT_ENDS:
                if not any(m.startswith(a) and pt == b for a, b in ALLOWED_FRONT):
                    bad.append(f"{m}:{line} -> {t} (front-ends do not import each other)")
                continue
            if FLOORS.get(pt, 0) > FLOORS.get(pm, 0) and not (pm == "__init__" and pt == "errors"):
                bad.append(f"{m}:{line} -> {t} (upward)")
    assert not bad, "\n".join(bad)


def test_io_is_a_leaf_and_core_reads_no_file():
    bad = [
        f"{m} -> {t}"
        for m, ts in EDGES.items()
        if _part(m) == "io"
        for t, _, _ in ts
        if _part(t) not in {"io", "errors", "units", "results", "_lazy"}
    ]
    assert not bad, bad
    for m, p in MODS.items():
        if _part(m) != "core":
            continue
        text = p.read_text(encoding="utf-8")
        for word in ("open(", "read_text(", "import csv", "import json", "import matplotlib"):
            if word == "read_text(" and "_core_digest" in text:
                continue  # hashing core's own sources for the Numba cache key is not reading data
            assert word not in text, f"{m} uses {word!r}: core reads no file"


@pytest.mark.parametrize("part", sorted(FRONT_ENDS | {"core", "io", "batch", "linecall", "serve", "launcher"}))
def test_no_try_import_of_own_modules(part):
    bad = [f"{m}:{ln} -> {t}" for m, ts in EDGES.items() if _part(m) == part for t, ln, g in ts if g]
    assert not bad, bad


def test_domain_packages_are_independent():
    """trajectory, serve, launcher, linecall and calibrate each stand on core/batch/io alone."""
    domains = {"trajectory", "serve", "launcher", "linecall", "calibrate"}
    bad = [
        f"{m}:{ln} -> {t}"
        for m, ts in EDGES.items()
        if _part(m) in domains
        for t, ln, _ in ts
        if _part(t) in domains and _part(t) != _part(m)
    ]
    assert not bad, bad


#: the packages below tennislab (the top level only imports its errors and says its version)
PACKAGES = sorted(m for m in MODS if m != "__init__" and "." not in m and _is_package(m))


@pytest.mark.parametrize("pkg", PACKAGES)
def test_every_package_init_is_a_lazy_public_stub(pkg):
    """One style (tennislab._lazy): a docstring, the public names imported under ``if TYPE_CHECKING:``,
    ``__all__`` naming exactly them, the lazy ``attach_stub``; no code, no import that runs."""
    import importlib

    from tennislab._lazy import stub_names

    path = MODS[pkg]
    tree = ast.parse(path.read_text(encoding="utf-8"))
    assert ast.get_docstring(tree), f"{pkg}/__init__.py: no docstring"
    runtime = [t for t, _, _, typing_only in _imports(pkg, path) if not typing_only and _part(t) != "_lazy"]
    assert not runtime, f"{pkg}/__init__.py imports {runtime} when imported (declare them under TYPE_CHECKING)"
    defs = [n.name for n in tree.body if isinstance(n, ast.FunctionDef | ast.ClassDef) and n.name != "__getattr__"]
    assert not defs, f"{pkg}/__init__.py defines {defs}: code lives in the package's modules"
    names = stub_names(f"tennislab.{pkg}", path.read_text(encoding="utf-8"))
    module = importlib.import_module(f"tennislab.{pkg}")
    assert sorted(module.__all__) == sorted(names), f"{pkg}: __all__ and the stub's imports differ"
    assert len(set(module.__all__)) == len(module.__all__), f"{pkg}: a name twice in __all__"
    for name in module.__all__:
        assert getattr(module, name) is getattr(importlib.import_module(names[name]), name)


# ------------------------------------------------------------------ the package APIs are the boundary
#: entry points: they may choose the Matplotlib backend and parse their own arguments
ENTRY_POINTS = {"demo", "__main__"}


def _exported(part: str) -> set[str]:
    """The ``__all__`` of a top-level part of the package (a package's stub, or a module)."""
    path = MODS["__init__" if part == "__init__" else part]
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "__all__" for t in node.targets):
            return {e.value for e in node.value.elts}  # type: ignore[attr-defined]
    return set()


def test_front_ends_import_only_exported_names():
    """cli/, app/ and report/ (and plot/, which draws their results) use a package only through the names
    its ``__all__`` exports."""
    bad = []
    for m, path in MODS.items():
        pm = _part(m)
        if pm not in FRONT_ENDS | ENTRY_POINTS | {"plot"}:
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                bad += [
                    f"{m}:{node.lineno} import {a.name}"
                    for a in node.names
                    if a.name.startswith("tennislab.") and not a.name.startswith(f"tennislab.{pm}.")
                ]
            module = (node.module or "") if isinstance(node, ast.ImportFrom) and not node.level else ""
            if not module.startswith("tennislab"):
                continue
            pt = _part(module.removeprefix("tennislab").lstrip("."))
            if pt == pm or (pt == "_lazy" and MODS[m].name == "__init__.py"):
                continue
            public = _exported(pt)
            bad += [f"{m}:{node.lineno} {node.module}.{a.name}" for a in node.names if a.name not in public]
    assert not bad, "names not in their package's __all__:\n" + "\n".join(bad)


@pytest.mark.parametrize(("library", "home"), [("matplotlib", "plot"), ("argparse", "cli")])
def test_matplotlib_only_in_plot_and_argparse_only_in_cli(library, home):
    """Figures are drawn only in plot/ and flags parsed only in cli/ (and by the entry points)."""
    bad = []
    for m, path in MODS.items():
        if _part(m) in {home} | ENTRY_POINTS:
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else []
            if isinstance(node, ast.ImportFrom) and not node.level:
                names = [node.module or ""]
            bad += [f"{m}:{node.lineno}" for n in names if n == library or n.startswith(library + ".")]
    assert not bad, f"{library} imported outside {home}/: {bad}"


def test_the_backend_is_chosen_only_by_the_entry_points():
    """Only the command line (``cli/_main.py``) and the entry points choose Matplotlib's backend: importing
    ``tennislab.plot`` in a notebook keeps the notebook's."""
    words = ("MPLBACKEND", "matplotlib.use(", "mpl.use(", "switch_backend(")
    bad = [
        f"{m}: {w}"
        for m, path in MODS.items()
        if m != "cli._main" and _part(m) not in ENTRY_POINTS
        for w in words
        if w in path.read_text(encoding="utf-8")
    ]
    assert not bad, bad


def test_the_command_line_loads_no_physics_to_parse():
    """Building every command's parser (``build_parser()``) loads none of the heavy libraries: each
    command imports what it uses when it runs (start-up timed by benchmarks/bench_startup.py)."""
    import subprocess
    import sys

    code = (
        "import sys, tennislab.cli as c; c.build_parser()\n"
        "print(','.join(m for m in ('scipy', 'numba', 'matplotlib', 'pandas', 'pyarrow') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "", f"building the parser imported {out.stdout.strip()}"


def test_help_and_version_load_no_numpy():
    """``tennislab --help`` and ``--version`` import no command's module: the top-level parser names
    the commands from ``cli/_commands.py`` (no NumPy, let alone the physics)."""
    import subprocess
    import sys

    for flag in ("--help", "--version"):
        code = (
            "import contextlib, io, sys\nfrom tennislab.cli import main\n"
            f"with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit): main([{flag!r}])\n"
            "print(','.join(m for m in ('numpy', 'scipy', 'numba', 'matplotlib', 'pandas') if m in sys.modules))"
        )
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
        assert out.stdout.strip() == "", f"tennislab {flag} imported {out.stdout.strip()}"


def test_the_command_table_is_what_the_modules_register():
    """``cli/_commands.py`` names every command with the help and the module that registers it: the
    top-level help without any command built is the full parser's, and a parser built for one command
    has that command's full parser (a command added or renamed in a module: add it to the table)."""
    from tennislab.cli._commands import COMMANDS
    from tennislab.cli._main import _subparsers, build_parser

    full = build_parser()
    assert list(_subparsers(full)) == list(COMMANDS), "cli/_commands.py lists other commands than the modules"
    assert build_parser(commands=()).format_help() == full.format_help()
    for name, sub in _subparsers(full).items():
        assert _subparsers(build_parser(commands=(name,)))[name].format_help() == sub.format_help(), name


#: commands that run without a flight: they must load neither Numba nor SciPy (their arguments)
_NO_FLIGHT_RUNS = (
    ("launcher", "rollers", "--speed-kmh", "80"),
    ("launcher", "power", "--speed-kmh", "80"),
)

#: a child process that asks every command for its --help (and runs the flightless commands), one after the
#: other, and prints the first command after which a heavy library was loaded (or that failed)
_HELP_PROBE = """
import argparse, contextlib, io, os, sys
os.environ["MPLBACKEND"] = "Agg"
from tennislab.cli import build_parser, main

HEAVY = ("numba", "scipy")
def commands(p, path):
    for a in p._actions:
        if isinstance(a, argparse._SubParsersAction):
            for name, sub in a.choices.items():
                yield path + [name]
                yield from commands(sub, path + [name])

todo = [c + ["--help"] for c in commands(build_parser(), [])] + [list(c) for c in RUNS]
for argv in todo:
    with contextlib.redirect_stdout(io.StringIO()):
        try:
            rc = main(argv)
        except SystemExit as exc:  # --help
            rc = exc.code
    heavy = [m for m in HEAVY if m in sys.modules]
    if heavy or rc:
        print(" ".join(argv), "->", ",".join(heavy) or f"exit {rc}")
        break
print("checked", len(todo))
"""


def test_help_and_flightless_commands_load_no_numba_or_scipy(tmp_path):
    """Every command's ``--help`` loads only what its text needs (the aero models' names from
    ``core.names``, not the compiled models), and a command without a flight (``launcher rollers``,
    ``launcher power``: the ball only; ``material``) loads neither Numba nor SciPy.  One process asks them all in turn
    (modules stay loaded, so the first command that loads one is named)."""
    import subprocess
    import sys

    (tmp_path / "ld.csv").write_text("load_n,deformation_m\n10,0.001\n20,0.002\n")
    (tmp_path / "fr.csv").write_text("friction_angle_deg\n60\n62\n")
    runs = (
        *_NO_FLIGHT_RUNS,
        ("material", "young", "--csv", str(tmp_path / "ld.csv")),
        ("material", "friction", "--csv", str(tmp_path / "fr.csv")),
    )
    code = f"RUNS = {runs!r}\n" + _HELP_PROBE
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    lines = out.stdout.strip().splitlines()
    assert lines[-1].startswith("checked ") and int(lines[-1].split()[1]) > 30, out.stdout + out.stderr
    assert len(lines) == 1, f"loaded a heavy library: {lines[0]}"


#: a child process that runs the database commands that only read (or store drills), one after the other,
#: and prints the first one after which a heavy library was loaded (or that failed)
_DB_PROBE = """
import contextlib, io, os, sys
from tennislab.cli import main

HEAVY = ("numba", "scipy", "matplotlib", "pandas")
for argv in RUNS:
    with contextlib.redirect_stdout(io.StringIO()):
        rc = main(list(argv))
    heavy = [m for m in HEAVY if m in sys.modules]
    if heavy or rc:
        print(" ".join(argv), "->", ",".join(heavy) or f"exit {rc}")
        break
print("checked", len(RUNS))
"""


def test_launcher_database_readers_load_no_flight(tmp_path):
    """``launcher drills list | import | export`` read (or store) a database and drill files without flying
    anything: they load neither Numba nor SciPy, Matplotlib or pandas (the court's geometry without its
    compiled net cord, the table's and the drills' modules without the aim).  ``launcher info`` loads no
    Matplotlib or pandas; it does load the flight physics, to name the preset whose physics the file stores
    (``hitsdb.stored_preset`` builds each preset's ``FlightParams``)."""
    import subprocess
    import sys

    from tennislab.cli import main

    db = str(tmp_path / "hits.sqlite")
    grid = ["--height", "1", "--speed-kmh", "90", "110", "--step", "speed", "10", "--spin-rpm", "0", "0"]
    assert main(["launcher", "table", "--db", db, *grid, "--spin-axis-deg", "0", "0", "--no-progress"]) == 0
    runs = (
        ("launcher", "drills", "list"),
        ("launcher", "drills", "import", "--db", db, "baseline_rally"),
        ("launcher", "drills", "list", "--db", db, "--json"),
        ("launcher", "drills", "export", "--db", db, "baseline_rally", str(tmp_path / "out.yaml")),
    )
    code = f"RUNS = {runs!r}\n" + _DB_PROBE
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=tmp_path)
    lines = out.stdout.strip().splitlines()
    assert lines[-1] == f"checked {len(runs)}", out.stdout + out.stderr
    assert len(lines) == 1, f"loaded a heavy library or failed: {lines[0]}"
    assert (tmp_path / "out.yaml").stat().st_size > 0
    info = _DB_PROBE.replace('HEAVY = ("numba", "scipy", "matplotlib", "pandas")', 'HEAVY = ("matplotlib", "pandas")')
    runs = (("launcher", "info", "--db", db), ("launcher", "info", "--db", db, "--check", "--json"))
    out = subprocess.run(
        [sys.executable, "-c", f"RUNS = {runs!r}\n" + info], capture_output=True, text=True, check=True, cwd=tmp_path
    )
    assert out.stdout.strip() == f"checked {len(runs)}", out.stdout + out.stderr


@pytest.mark.slow
def test_the_command_lines_static_names_are_the_registries():
    """The names a command line lists without importing their modules (so that --help loads no
    compiled kernel) are the registries' own."""
    from tennislab import core, serve
    from tennislab.calibrate import registered_models
    from tennislab.cli.calibrate import _models_help
    from tennislab.cli.impact import IMPACT_CHOICES
    from tennislab.cli.report import SECTION_KEYS
    from tennislab.report import SECTION_KEYS as report_keys

    assert IMPACT_CHOICES == {
        "impact_scheme": tuple(serve.IMPACT_SCHEMES),
        "friction_model": tuple(core.FRICTION_MODELS),
        "tangential_damping": tuple(core.TANGENTIAL_DAMPING),
    }
    assert SECTION_KEYS == report_keys
    assert _models_help().endswith(f"(default all: {', '.join(registered_models())})")


#: functions that compute the flight's equations of motion: only core/dynamics.py may define them
_RHS_NAMES = ("derivative", "rhs", "_rhs", "deriv", "_deriv", "accel", "_accel", "eom", "_eom")
#: (module, function) of right-hand sides of other physics (the racket-ball contact), not the flight's
_OTHER_PHYSICS = {("core.impact", "rhs")}


def test_one_definition_of_the_right_hand_side():
    """The flight's right-hand side is written once (core/dynamics.py): no other module defines one
    or evaluates the aero coefficients inside compiled code of its own."""
    bad = []
    for m, path in MODS.items():
        if m == "core.dynamics":
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef) and node.name in _RHS_NAMES and (m, node.name) not in _OTHER_PHYSICS:
                if node.decorator_list or m.startswith("linecall"):
                    bad.append(f"{m}:{node.lineno} def {node.name}")
            if isinstance(node, ast.Call) and getattr(node.func, "id", getattr(node.func, "attr", "")) == (
                "aero_coefficients"
            ):
                bad.append(f"{m}:{node.lineno} calls aero_coefficients")
    assert not bad, "right-hand sides outside core/dynamics.py:\n" + "\n".join(bad)


#: core's integrator family and its right-hand side: what only core calls (everyone else calls the paths
#: that wrap them: fly_dense, fly_batch, sweep_positions)
_CORE_STEPPERS = {"derivative", "derivative_call", "rk4_step", "integrate_one", "batch_kernel", "serial_kernel"}


def _is_compiled(node: ast.FunctionDef) -> bool:
    return any("njit" in ast.unparse(d) or "jit" == ast.unparse(d).split(".")[-1] for d in node.decorator_list)


def test_flights_are_integrated_only_by_core():
    """One integrator family: outside ``core/`` no code steps the right-hand side itself (a call of
    ``derivative`` or ``rk4_step``) and no compiled function evaluates an aero model's kernel (a call of
    an argument named ``aero...`` or of ``.kernel``): that is the start of a copy of the equations of motion."""
    bad = []
    for m, path in MODS.items():
        if _part(m) == "core":
            continue
        for fn in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(fn, ast.FunctionDef):
                continue
            args = {a.arg for a in fn.args.args}
            for node in ast.walk(fn):
                if not isinstance(node, ast.Call):
                    continue
                name = getattr(node.func, "id", getattr(node.func, "attr", ""))
                if name in _CORE_STEPPERS:
                    bad.append(f"{m}:{node.lineno} {fn.name} calls {name}")
                elif _is_compiled(fn) and (
                    (isinstance(node.func, ast.Name) and name in args and "aero" in name) or name == "kernel"
                ):
                    bad.append(f"{m}:{node.lineno} compiled {fn.name} evaluates the aero model ({name})")
    assert not bad, "flights integrated outside core:\n" + "\n".join(bad)


def test_one_name_one_thing_across_the_package_apis():
    """A function or class exported by two packages is one object (a re-export), never two doing different
    things (``core.flight.fly`` is ``fly_dense``: ``trajectory.fly`` is the workflow).  (Tables of words,
    such as each package's ``REASONS``, may share a name.)"""
    import importlib

    seen: dict[str, tuple[str, object]] = {}
    bad = []
    for pkg in PACKAGES:
        module = importlib.import_module(f"tennislab.{pkg}")
        for name in module.__all__:
            obj = getattr(module, name)
            if not callable(obj):
                continue
            if name in seen and seen[name][1] is not obj:
                bad.append(f"{name}: tennislab.{seen[name][0]} and tennislab.{pkg}")
            seen.setdefault(name, (pkg, obj))
    assert not bad, bad


@pytest.mark.parametrize(
    ("module", "old", "new"),
    [
        ("core.flight", "fly", "fly_dense"),
        ("core.impact", "impact", "impact_single"),
        ("launcher.machine", "launch_states", "machine_states"),
        ("launcher", "launch_states", "machine_states"),
        ("calibrate.aim", "launch_states", "serve_states"),
        ("serve.pipeline", "fly", "fly_serves"),
        ("calibrate.aim", "spin_components", "spin_from_fractions"),
        ("launcher.preferences", "spin_components", "spin_rpm_components"),
    ],
)
def test_the_old_names_of_the_primitives_still_work(module, old, new):
    import importlib

    mod = importlib.import_module(f"tennislab.{module}")
    with pytest.warns(DeprecationWarning, match=f"is now {new}"):
        assert getattr(mod, old) is getattr(mod, new)


def test_one_name_for_the_json_of_an_object():
    """``to_dict()`` everywhere: no package exports a ``*_dict`` converter, no exported class has its own
    ``as_dict`` (the old name lives only in ``results.OldAsDict``, with a DeprecationWarning)."""
    import importlib

    from tennislab.results import OldAsDict

    bad = []
    for pkg in PACKAGES:
        module = importlib.import_module(f"tennislab.{pkg}")
        for name in module.__all__:
            obj = getattr(module, name)
            if name.endswith("_dict"):
                bad.append(f"tennislab.{pkg}.{name}")
            if isinstance(obj, type) and "as_dict" in vars(obj) and obj is not OldAsDict:
                bad.append(f"tennislab.{pkg}.{name}.as_dict")
    assert not bad, bad


#: modules that state a model or a formula: each cites its sources in a numpydoc ``References`` section
MODEL_MODULES = (
    "core.aero",
    "core.atmosphere",
    "core.ball",
    "core.bounce",
    "core.court",
    "core._net",
    "core.dynamics",
    "core.haake2003",
    "core.impact",
    "core.impact_3d",
    "core.integrators",
    "core.mark",
    "core.surfaces",
    "core.launch",
    "linecall.closed_form",
    "linecall.model",
    "linecall.fit",
    "linecall.cameras",
    "linecall.decide",
    "serve.pipeline",
    "serve.racket_impact",
    "serve.mc",
    "launcher.machine",
    "launcher.rollers",
    "launcher.power",
    "launcher.materials",
    "calibrate.family",
    "calibrate.identify",
    "calibrate.stats",
    "calibrate.surface",
)


def _has_references(doc: str | None) -> bool:
    lines = [ln.strip() for ln in (doc or "").splitlines()]
    return any(a == "References" and b.startswith("----") for a, b in zip(lines, lines[1:]))


@pytest.mark.parametrize("module", MODEL_MODULES)
def test_every_model_cites_its_sources(module):
    """numpydoc with References for every model and formula (after pvlib's temperature.py)."""
    assert _has_references(ast.get_docstring(ast.parse(MODS[module].read_text(encoding="utf-8")))), module


def test_every_registered_aero_model_cites_its_sources():
    import inspect

    from tennislab.core import aero

    for name in aero.aero_model_names():
        factory = inspect.unwrap(aero._REGISTRY[name])
        if factory.__module__ != aero.__name__:
            continue  # registered by a user (or a test), not one of tennislab's models
        assert _has_references(factory.__doc__), f"aero model {name!r}: no References in {factory.__name__}'s docstring"


def test_the_launcher_s_old_spin_vector_is_core_s_launch_spin():
    """``tennislab.launcher.spin_vector`` (rate, elevation, heading, axis angle) was a second public
    ``spin_vector`` beside ``core.launch.spin_vector`` (launch-frame components): it is now core's
    ``launch_spin``, exported by both packages; the old name still works."""
    import tennislab.core
    import tennislab.launcher

    assert tennislab.launcher.launch_spin is tennislab.core.launch_spin
    assert "spin_vector" not in tennislab.launcher.__all__
    with pytest.warns(DeprecationWarning, match="is now launch_spin"):
        assert tennislab.launcher.spin_vector is tennislab.core.launch_spin
    with pytest.warns(DeprecationWarning, match="is now launch_spin"):
        assert tennislab.launcher.machine.spin_vector is tennislab.core.launch_spin


def test_one_launch_state_builder():
    """``core.launch.launch_states`` (launch-frame spin components) is the only ``launch_states`` any module
    defines, and ``core.launch.spin_vector`` the only ``spin_vector``: the launcher's settings
    (``machine_states``) and the serve calibration's axis fractions (``serve_states``) build through
    them."""
    bad = []
    for m, path in MODS.items():
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            named = isinstance(node, ast.FunctionDef) and node.name in ("launch_states", "spin_vector")
            if named and m != "core.launch":
                bad.append(f"{m}:{node.lineno} def {node.name}")
    assert not bad, bad
