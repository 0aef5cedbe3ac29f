"""Lazy public APIs for the packages' ``__init__.py`` (after scikit-image's ``lazy_loader.attach_stub``).

A package's ``__init__.py`` is its public stub: a docstring, the public names as relative or absolute
imports inside ``if TYPE_CHECKING:`` (what type checkers, IDEs and ``tests/test_architecture.py``
read), ``__all__`` (the same names: the API), and one call::

    from typing import TYPE_CHECKING

    from tennislab._lazy import attach_stub

    if TYPE_CHECKING:
        from tennislab.linecall.calls import TrackCall, call_track

    __all__ = ["TrackCall", "call_track"]
    __getattr__, __dir__ = attach_stub(__name__, __file__)

Nothing is imported until a name is used: ``import tennislab.serve`` costs nothing, and
``tennislab.serve.simulate`` (or ``from tennislab.serve import simulate``) imports the module that
defines it, once.  A submodule not imported yet is imported on first access too, as a package that
imported it eagerly would have it (``tennislab.launcher.db``); a submodule that is part of the API is
declared as ``from tennislab.serve import published``.  A public name that is also the name
of a submodule (``tennislab.launcher.aim``, the function, defined in the module ``launcher/aim.py``)
stays the public name when the submodule is imported, as after an eager import.
"""

from __future__ import annotations

import importlib
import sys
import types
from collections.abc import Callable

__all__ = ["attach_stub", "stub_names"]


def stub_names(package: str, source: str) -> dict[str, str]:
    """{public name: defining module} of the ``if TYPE_CHECKING:`` imports in a stub's ``source``."""
    import ast  # (only when a name is first looked up)

    out: dict[str, str] = {}
    for node in ast.parse(source).body:
        if not (isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING"):
            continue
        for imp in node.body:
            if not isinstance(imp, ast.ImportFrom):
                continue
            base = package.split(".")[: len(package.split(".")) - imp.level + 1] if imp.level else []
            module = ".".join(base + ([imp.module] if imp.module else []))
            for alias in imp.names:
                out[alias.asname or alias.name] = module
    return out


def attach_stub(package: str, file: str) -> tuple[Callable[[str], object], Callable[[], list[str]]]:
    """``(__getattr__, __dir__)`` for the package ``package`` whose stub is the file ``file``."""
    table: dict[str, str] = {}

    def names() -> dict[str, str]:
        if not table:
            with open(file, encoding="utf-8") as fh:
                table.update(stub_names(package, fh.read()))
        return table

    def __getattr__(name: str) -> object:
        if name.startswith("__"):
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        module = names().get(name)
        if module is None:
            try:
                return importlib.import_module(f"{package}.{name}")
            except ModuleNotFoundError as exc:
                if exc.name != f"{package}.{name}":
                    raise
                raise AttributeError(f"module {package!r} has no attribute {name!r}") from None
        if module == package:  # a public submodule (``from tennislab.serve import published``)
            return importlib.import_module(f"{package}.{name}")
        value = getattr(importlib.import_module(module), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(names()))

    module = sys.modules[package]
    module._stub_names = names  # type: ignore[attr-defined]
    module.__class__ = _Stub
    return __getattr__, __dir__


class _Stub(types.ModuleType):
    """A package stub: importing a submodule does not hide a public name it shares."""

    def __setattr__(self, name: str, value: object) -> None:
        if isinstance(value, types.ModuleType) and value.__name__ == f"{self.__name__}.{name}":
            if name in self._stub_names():
                return
        super().__setattr__(name, value)
