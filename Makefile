# imunav — the two commands that do everything on a fresh clone:
#   make reproduce   regenerate every paper reproduction and figure into figures/
#   make test        lint, unit tests, and every notebook under strict nbval
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: all install reproduce test lint unit nbval lab bench clean

all: test

# (Re)install when pyproject.toml changes; the stamp records the last good install.
$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[dev]"
	touch $(STAMP)

install: $(STAMP)

reproduce: $(STAMP)
	MPLBACKEND=Agg $(BIN)/imunav reproduce --out figures

lint: $(STAMP)
	$(BIN)/ruff check imunav tests notebooks benchmarks

unit: $(STAMP)
	MPLBACKEND=Agg $(BIN)/python -m pytest -q tests

nbval: $(STAMP)
	MPLBACKEND=Agg $(BIN)/python -m pytest -q --nbval --nbval-current-env notebooks

test: lint unit nbval

# imunav vs a numba-compiled loop, ahrs, Monte Carlo throughput, memory → benchmarks/results.json
bench: $(STAMP)
	$(BIN)/python -m pip install --quiet -e ".[bench]"
	$(BIN)/python benchmarks/bench.py

lab: $(STAMP)
	$(BIN)/jupyter lab notebooks

clean:
	rm -rf $(VENV) .pytest_cache .ruff_cache build *.egg-info
