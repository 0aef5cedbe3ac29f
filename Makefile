# tennislab: two commands for a fresh machine with Python 3.11+.
#   make demo   -> creates .venv, installs tennislab, runs the main job
#   make test   -> creates .venv, installs tennislab with test extras, runs lint and the whole test suite
#   make check  -> lint and the fast tests (not slow, not browser end-to-end): under 2 minutes, while you work
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
TSTAMP := $(VENV)/.installed-test

.PHONY: demo test check lint docs bench clean

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip

$(STAMP): pyproject.toml | $(PY)
	$(PY) -m pip install --quiet -e ".[app]"
	touch $@

$(TSTAMP): pyproject.toml | $(PY)
	$(PY) -m pip install --quiet -e ".[test]"
	touch $(STAMP) $@

demo: $(STAMP)
	$(PY) -m tennislab.demo --out out/demo

lint: $(TSTAMP)
	$(PY) -m ruff check src tests benchmarks examples
	$(PY) -m ruff format --check src tests benchmarks examples
	$(PY) -m mypy

test: $(TSTAMP) lint
	$(PY) -m pytest

# The fast tests: everything but the tests marked `slow` (long reproductions, real-data sweeps) and the
# browser end-to-end tests (`e2e`); `make test` runs them all.
check: $(TSTAMP) lint
	$(PY) -m pytest -m "not slow and not e2e"

# Regenerate the outputs the docs show after `$ tennislab ...` (and list quoted numbers gone stale):
# run it after changing what a command prints; CONTRIBUTING.md says how docs quote outputs.
docs: $(TSTAMP)
	$(PY) tests/test_docs.py --update

bench: $(TSTAMP)
	$(PY) benchmarks/run_all.py

clean:
	rm -rf $(VENV) build *.egg-info src/*.egg-info
	find out -mindepth 1 -maxdepth 1 ! -name .gitignore -exec rm -rf {} +
