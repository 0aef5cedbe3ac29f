# tennislab: two commands for a fresh machine with Python 3.11+.
#   make demo   -> creates .venv, installs tennislab, runs the main job
#   make test   -> creates .venv, installs tennislab with test extras, runs pytest
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
TSTAMP := $(VENV)/.installed-test

.PHONY: demo test lint bench clean

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

bench: $(TSTAMP)
	$(PY) benchmarks/run_all.py

clean:
	rm -rf $(VENV) out build *.egg-info src/*.egg-info
