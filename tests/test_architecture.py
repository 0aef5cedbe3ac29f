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
#: the imports that run: a package stub's declarations import nothing (tennislab._lazy), and ``from
#: tennislab.pkg import sub`` from inside ``pkg`` runs only the lazy stub of ``pkg``
RUN_EDGES = {
    m: {
        t
        for t, _, _, typing_only in _imports(m, p)
        if t in MODS and t != m and not typing_only and not (_is_package(t) and m.startswith(t + "."))
    }
    for m, p in MODS.items()
}


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
        for w in RUN_EDGES.get(v, ()):
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
