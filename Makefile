# imunav — the two commands that do everything on a fresh clone:
#   make reproduce   regenerate every paper reproduction and figure into figures/, and re-execute
#                    every notebook with its figures (make notebooks)
#   make test        lint, unit tests, and every notebook under strict nbval
#   make test-browser  the notebooks in JupyterLab and the book, in headless Chromium
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: all install install-book install-browser reproduce test lint unit nbval notebooks book test-browser lab bench mutation clean

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
	$(MAKE) notebooks

lint: $(STAMP)
	$(BIN)/ruff check imunav tests notebooks benchmarks

# The unit tests on both cores (pytest-xdist; JOBS=1 for one process).
JOBS ?= 2
unit: $(STAMP)
	MPLBACKEND=Agg $(BIN)/python -m pytest -q -n $(JOBS) tests

# The stored notebooks re-run under nbval with the inline backend (figures drawn and checked by
# the figure check, not compared): all of them, or NB="01 02".
nbval: $(STAMP)
	env -u MPLBACKEND $(BIN)/python -m pytest -q -n $(JOBS) --dist loadfile --nbval --nbval-current-env \
	  $(if $(strip $(NB)),$(foreach n,$(NB),$(wildcard notebooks/$(n)*.ipynb)),notebooks)

# Sync notebooks/src/*.py into the paired notebooks/*.ipynb (jupytext) and execute them in place
# with the inline backend and the figure check, so outputs and figures are stored: all of them,
# or NB="00 05" (name prefixes). One line per cell with its time; a stalled kernel is reported
# (STALL, and counted on the last line), never silently retried. Two runs on one machine write
# identical files (no timestamps; widget and HTML ids renumbered): re-running on a fresh clone
# leaves the stored notebooks unchanged. See notebooks/run.py.
NB ?=
notebooks: $(STAMP)
	env -u MPLBACKEND $(BIN)/python notebooks/run.py $(NB)

test: lint unit nbval

# imunav vs a numba-compiled loop, ahrs, Monte Carlo throughput, memory → benchmarks/results.json
bench: $(STAMP)
	$(BIN)/python -m pip install --quiet -e ".[bench]"
	$(BIN)/python benchmarks/bench.py

# Mutation testing of imunav/core and imunav/analysis with mutmut 3 (an hour or more on 2 cores:
# not part of make test). Prints the score, writes the survivors to build/mutation/survivors.txt,
# fails below 90 % or when a survivor is not listed in tests/MUTATION.md. Results are cached in
# mutants/: a second run re-checks only what changed (delete mutants/ to start over).
MUTATION_STAMP := $(VENV)/.installed-mutation
$(MUTATION_STAMP): $(STAMP) pyproject.toml
	$(BIN)/python -m pip install --quiet -e ".[mutation]"
	touch $(MUTATION_STAMP)

mutation: $(MUTATION_STAMP)
	$(BIN)/python benchmarks/mutation.py run

# The rendered book: stored notebooks (not re-executed) + landing page + API reference → build/book/
BOOK_STAMP := $(VENV)/.installed-book
$(BOOK_STAMP): $(STAMP) pyproject.toml
	$(BIN)/python -m pip install --quiet -e ".[dev,book]"
	touch $(BOOK_STAMP)
install-book: $(BOOK_STAMP)

book: $(BOOK_STAMP)
	rm -rf build/book-src build/book
	mkdir -p build/book-src
	cp docs/* build/book-src/
	cp notebooks/[0-9]*.ipynb build/book-src/
	$(BIN)/sphinx-build -W --keep-going -q -b html build/book-src build/book
	@echo "book: build/book/index.html"

# Browser tests: every notebook Run-All'd in JupyterLab (widgets dragged, figures must change),
# every book page checked (console errors, images, math). Needs the Debian chromium package.
CHROMIUM ?= /usr/lib/chromium/chromium
BROWSER_STAMP := $(VENV)/.installed-browser
$(BROWSER_STAMP): $(STAMP) pyproject.toml
	$(BIN)/python -m pip install --quiet -e ".[dev,browser]"
	touch $(BROWSER_STAMP)
install-browser: $(BROWSER_STAMP)

test-browser: $(BROWSER_STAMP) book
	test -x $(CHROMIUM) || { SUDO=$$(test "$$(id -u)" = 0 || echo sudo); \
	  DEBIAN_FRONTEND=noninteractive $$SUDO apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq chromium; }
	env -u MPLBACKEND CHROMIUM=$(CHROMIUM) $(BIN)/python tests/browser/run.py

lab: $(STAMP)
	$(BIN)/jupyter lab notebooks

clean:
	rm -rf $(VENV) .pytest_cache .ruff_cache build mutants *.egg-info
