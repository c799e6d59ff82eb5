# projtrack: the two commands are `make book` and `make test` (see README.md).
SHELL := /bin/bash
.SHELLFLAGS := -eu -o pipefail -c
.DEFAULT_GOAL := help

PYTHON_BASE ?= python3.11
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.projtrack-installed
BOOK_HTML := book/_build/html
# Notebooks must not pick up a user's matplotlib or IPython settings.
export MPLCONFIGDIR := $(CURDIR)/.cache/matplotlib
export IPYTHONDIR := $(CURDIR)/.cache/ipython
export PYTHONHASHSEED := 0
export PYDEVD_DISABLE_FILE_VALIDATION := 1
# One BLAS/OpenMP thread per process: the notebooks' numbers then do not depend on the
# machine's core count, and parallel test processes do not oversubscribe the cores.
export OPENBLAS_NUM_THREADS := 1
export OMP_NUM_THREADS := 1
export MKL_NUM_THREADS := 1

.PHONY: help book test figures bench lock clean env unit nbval nbval-second-kernel crosscheck bookcheck \
	browsercheck browser-deps html kl-data

help:
	@echo "make book     create .venv from environment.lock, execute every notebook, build the HTML book"
	@echo "make test     import layers, unit + property tests, nbval over every notebook (under two BLAS kernels),"
	@echo "              figure regression, strict book build, the built book checked in headless Chromium"
	@echo "make figures  execute every notebook in place (refreshes stored outputs and figures/)"
	@echo "make crosscheck  nbval under every OpenBLAS kernel x numpy SIMD level this CPU can run, with a report"
	@echo "make bench    run the benchmarks in benchmarks/"
	@echo "make lock     regenerate environment.lock from pyproject.toml"
	@echo "make kl-data  re-create the KL chapter's committed video excerpt from Debian's opencv-doc"
	@echo "make clean    remove build products and caches (keeps .venv)"

# The environment: (re)created whenever environment.lock or pyproject.toml is newer.
env: $(STAMP)
$(STAMP): environment.lock pyproject.toml
	@echo "==> creating $(VENV) from environment.lock"
	rm -rf $(VENV)
	$(PYTHON_BASE) -m venv $(VENV)
	$(PY) -m pip install --quiet --require-hashes --only-binary :all: --no-deps -r environment.lock 2> >(grep -v "is ignored: it is neither a file nor a directory" >&2)
	$(PY) -m pip install --quiet --no-deps --no-build-isolation -e . 2> >(grep -v "is ignored: it is neither a file nor a directory" >&2)
	$(PY) -m pip check
	@mkdir -p $(MPLCONFIGDIR) $(IPYTHONDIR)
	touch $(STAMP)

figures: $(STAMP)
	@echo "==> executing every notebook in a fresh kernel (outputs stored in place, figures/ regenerated)"
	$(PY) tools/run_notebooks.py

html: $(STAMP)
	@echo "==> building the HTML book from the stored outputs"
	$(VENV)/bin/jupyter-book build book --keep-going
	@echo "The book is at $(CURDIR)/$(BOOK_HTML)/index.html"

book: figures
	@$(MAKE) --no-print-directory html

unit: $(STAMP)
	@echo "==> the package's import layers (lint-imports, contracts in pyproject.toml)"
	$(VENV)/bin/lint-imports --no-cache
	@echo "==> unit and property tests (with the wheel installed in a clean venv)"
	$(PY) -m pytest tests -q -p no:cacheprovider --ignore=tests/test_figure_regression.py \
		--ignore=tests/browser
	@echo "==> the examples in the docstrings of the algorithm packages (doctest)"
	$(PY) -m pytest -q -p no:cacheprovider --doctest-modules src/projtrack/ellipsoids src/projtrack/dma \
		src/projtrack/correlators src/projtrack/hough src/projtrack/jpda src/projtrack/neuralnet \
		src/projtrack/novelty

NBVAL = $(PY) -m pytest -p no:cacheprovider --nbval --nbval-current-env \
	--nbval-sanitize-with tests/nbval_sanitize.cfg --nbval-cell-timeout=600 \
	--ignore=book/_build -v book tests/test_figure_regression.py

nbval: $(STAMP)
	@echo "==> nbval over every notebook (OpenBLAS kernel: $$($(PY) tools/blas_kernels.py default)), then figure regression against figures/"
	$(NBVAL)

# The stored outputs must not depend on the last bits of one CPU: run nbval once more under
# another OpenBLAS kernel (OPENBLAS_CORETYPE) and numpy's next SIMD level down
# (NPY_DISABLE_CPU_FEATURES), both chosen by tools/crosscheck.py among what this CPU can run.
nbval-second-kernel: $(STAMP)
	@second="$$($(PY) tools/crosscheck.py second)"; \
	echo "==> nbval again under $$second (another BLAS kernel and SIMD level)"; \
	eval "export $$second"; \
	[ -n "$$OPENBLAS_CORETYPE" ] || unset OPENBLAS_CORETYPE; \
	[ -n "$$NPY_DISABLE_CPU_FEATURES" ] || unset NPY_DISABLE_CPU_FEATURES; \
	$(NBVAL)

# nbval under every OpenBLAS kernel this CPU can run times numpy's SIMD levels, each in its
# own process (two at a time), with a report of every compared number that moved and by
# how much against its declared tolerance (.cache/crosscheck/report.md). Run it before
# submitting a change to notebooks or numerics.
crosscheck: $(STAMP)
	$(PY) tools/crosscheck.py run --jobs 2

bookcheck: $(STAMP)
	@echo "==> strict book build (warnings and broken references are errors)"
	rm -rf book/_build
	$(VENV)/bin/jupyter-book build book -W -n --keep-going
	@echo "strict book build passed"

# Debian's chromium and its driver for the browser check. On CI (CI=true, as root, with
# apt-get) they are installed when missing; elsewhere the check says how to install them.
browser-deps:
	@if command -v chromium >/dev/null && command -v chromedriver >/dev/null; then :; \
	elif [ "$${CI:-}" = "true" ] && [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
		echo "==> installing Debian's chromium and chromium-driver for the browser check"; \
		{ apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium chromium-driver >/dev/null; } \
		|| echo "!! could not install chromium and chromium-driver with apt-get"; \
	fi

# The built book opened from disk with no network, in headless Chromium: math typeset,
# images loaded, internal links resolve, no console errors, nothing fetched from the network.
browsercheck: $(STAMP) browser-deps
	@echo "==> the built book in a real browser (tests/browser)"
	@if ! command -v chromium >/dev/null || ! command -v chromedriver >/dev/null; then \
		echo "!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!"; \
		echo "!! Chromium is not installed: the browser checks are SKIPPED (static checks still run)."; \
		echo "!! Install Debian's chromium and chromium-driver: apt-get install chromium chromium-driver"; \
		echo "!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!"; \
	fi
	@rm -f .cache/reading.txt; status=0; $(PY) -m pytest -p no:cacheprovider -q -rs tests/browser || status=$$?; \
	if [ -f .cache/reading.txt ]; then echo "==> how the book reads (visible words, code lines, first figure):"; \
	cat .cache/reading.txt; fi; exit $$status

# The two nbval runs are independent (each kernel uses one BLAS thread, each run writes
# its figures to its own temporary folder), so they run side by side on two cores; their
# logs are printed one after the other.
test: $(STAMP)
	@$(MAKE) --no-print-directory unit
	@$(MAKE) --no-print-directory -j2 --output-sync=target nbval nbval-second-kernel
	@$(MAKE) --no-print-directory bookcheck
	@$(MAKE) --no-print-directory browsercheck

bench: $(STAMP)
	@set -e; for f in benchmarks/bench_*.py; do echo "==> $$f"; $(PY) $$f; done

# Re-create the committed plaza excerpt of the KL chapter from Debian's opencv-doc
# package (needs apt access; the book itself never does this).
kl-data: $(STAMP)
	@echo "==> re-creating src/projtrack/data/plaza-excerpt.npz from Debian's opencv-doc"
	$(PY) tools/fetch_plaza_video.py

lock:
	@echo "==> regenerating environment.lock (uv pip compile --universal, Python 3.11, with hashes)"
	$(PYTHON_BASE) -m venv .cache/lockenv
	.cache/lockenv/bin/pip install --quiet uv 2> >(grep -v "is ignored" >&2)
	.cache/lockenv/bin/uv pip compile pyproject.toml --all-extras --python-version 3.11 \
		--universal --generate-hashes --no-header -o environment.lock

clean:
	rm -rf book/_build .cache .pytest_cache .hypothesis .benchmarks
	find . -name __pycache__ -type d -prune -not -path "./$(VENV)/*" -exec rm -rf {} +
