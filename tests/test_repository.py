"""What a scientist looks for in the repository: a license, how to cite it, its history, a quick test target,
and a README that opens with the two commands of a fresh machine."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]


def test_the_license_is_the_one_pyproject_declares():
    assert PYPROJECT["license"] == "MIT"
    text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert text.startswith("MIT License") and "Permission is hereby granted, free of charge" in text


def test_citation_cff_names_this_version_and_the_seed_papers():
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
    assert cff["cff-version"] == "1.2.0" and cff["license"] == PYPROJECT["license"]
    assert str(cff["version"]) == PYPROJECT["version"]
    assert cff["authors"] and cff["title"].startswith("tennislab")
    names = {a["family-names"] for ref in cff["references"] for a in ref["authors"]}
    assert {"Grosen", "Deng", "Wójcicki"} <= names


def test_the_changelog_has_an_unreleased_section_in_keep_a_changelog_form():
    text = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    assert text.startswith("# Changelog")
    heads = re.findall(r"^## \[([^\]]+)\]", text, re.M)
    assert heads and heads[0] == "Unreleased"
    kinds = set(re.findall(r"^### (\w+)", text, re.M))
    assert kinds <= {"Added", "Changed", "Deprecated", "Removed", "Fixed", "Security"}, kinds


def test_the_readme_opens_with_the_two_commands_and_names_make_check():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    first = re.search(r"```\w*\n(.*?)```", text, re.S)
    assert first is not None
    commands = [line.split("#")[0].strip() for line in first.group(1).splitlines() if line.strip()]
    assert commands == ["make demo", "make test"]
    assert "make check" in text[first.end() :]


def test_make_check_is_lint_and_the_fast_tests():
    makefile = (ROOT / "Makefile").read_text(encoding="utf-8")
    rule = re.search(r"^check:(.*)\n((?:\t.*\n)+)", makefile, re.M)
    assert rule is not None and "lint" in rule.group(1)
    assert '-m "not slow and not e2e"' in rule.group(2)


def test_out_ships_empty_and_ignored():
    assert (ROOT / "out" / ".gitignore").read_text(encoding="utf-8").splitlines()[-2:] == ["*", "!.gitignore"]


def test_the_slow_list_names_existing_tests():
    import importlib.util

    spec = importlib.util.spec_from_file_location("_conftest_for_check", ROOT / "tests" / "conftest.py")
    assert spec is not None and spec.loader is not None
    conftest = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(conftest)
    for path in conftest.SLOW_PATHS:
        file, _, func = path.partition("::")
        assert (ROOT / file).exists(), path
        assert not func or f"def {func}(" in (ROOT / file).read_text(encoding="utf-8"), path
    for test in conftest.SLOW_TESTS:
        file, func = test.split("::")
        assert f"def {func}(" in (ROOT / file).read_text(encoding="utf-8"), f"{test}: no such test"
