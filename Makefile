# planerel: two commands do everything on a fresh Debian machine.
#   make demo   set up, then run the main job end to end (writes out/)
#   make test   set up, then run the whole test suite
SHELL := /bin/bash
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: setup demo test bench clean swipl chromium coverage

setup: swipl $(STAMP)

# SWI-Prolog from Debian when it is missing; as non-root, say the exact command instead.
swipl:
	@if command -v swipl >/dev/null 2>&1; then :; \
	elif [ "$$(id -u)" = "0" ] && command -v apt-get >/dev/null 2>&1; then \
		echo "installing SWI-Prolog (swi-prolog-nox) with apt-get"; \
		apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends swi-prolog-nox; \
	else \
		echo "SWI-Prolog is missing; install it with: sudo apt-get install swi-prolog-nox" >&2; exit 1; \
	fi

# Chromium (Debian's package) lets the report test check the HTML page in a real headless
# browser. Best effort: without it that one test is skipped with its reason, nothing fails.
chromium:
	@if command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1; then :; \
	elif [ "$$(id -u)" = "0" ] && command -v apt-get >/dev/null 2>&1; then \
		echo "installing Chromium with apt-get (for the report's headless-browser test)"; \
		(apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends chromium) \
			|| echo "Chromium could not be installed; the headless-browser test will be skipped" >&2; \
	else \
		echo "Chromium is missing (sudo apt-get install chromium); the headless-browser test will be skipped" >&2; \
	fi

$(STAMP): pyproject.toml
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[dev]'
	@touch $(STAMP)

demo: setup
	$(PY) examples/demo.py --out out

# the suite runs on PYTEST_WORKERS processes (pytest-xdist; 2 = the CI machine's cores)
PYTEST_WORKERS ?= 2

test: setup chromium
	$(PY) -m pytest -q -n $(PYTEST_WORKERS)

bench: setup
	$(PY) benchmarks/run_all.py

clean:
	rm -rf out .pytest_cache build *.egg-info

# Branch coverage (docs/testing.md): the whole suite, then the kernel tests again with the numba
# kernels run as plain Python (NUMBA_DISABLE_JIT=1: Python checks every index), combined. Both
# runs must pass.
PURE_PY_TESTS := tests/test_segment_kernels.py tests/test_segment_post_kernels.py \
	tests/test_segment_reference.py tests/test_segment_paper.py tests/test_segment_graph.py \
	tests/test_normals.py

coverage: setup
	rm -f .coverage .coverage.*
	$(PY) -m coverage run --rcfile=.coveragerc -m pytest -q
	NUMBA_DISABLE_JIT=1 $(PY) -m coverage run --rcfile=.coveragerc -m pytest -q $(PURE_PY_TESTS)
	$(PY) -m coverage combine --rcfile=.coveragerc -q
	$(PY) -m coverage report --rcfile=.coveragerc
