# The two set-up commands of README.md: `make run` and `make test`.
# Both create the virtual environment on first use, so a fresh clone needs nothing else.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: run test lint bench clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[test,bench]'
	touch $(STAMP)

run: $(STAMP)
	$(BIN)/polynav run

test: $(STAMP)
	bash tools/system_deps.sh
	$(BIN)/ruff check polynav tests benchmarks tools
	$(BIN)/mypy polynav
	@# bytecode written once here: with PYTHONDONTWRITEBYTECODE set, every worker and every
	@# `polynav run` a test starts would otherwise compile polynav from source (~0.6 s each)
	$(BIN)/python -m compileall -q polynav tests benchmarks >/dev/null
	@# numba's kernels compiled once, on both cores, rather than by each worker at once
	$(BIN)/python tools/warm_kernels.py
	$(BIN)/python -m pytest -q -n 2

bench: $(STAMP)
	$(BIN)/polynav bench planner
	$(BIN)/polynav bench sim
	$(BIN)/polynav bench nav
	$(BIN)/polynav bench api

clean:
	rm -rf $(VENV) .pytest_cache
