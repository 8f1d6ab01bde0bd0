# Two commands on a fresh machine: `make sweep` (the main job) and `make test` (ruff, then the
# fast tier of the tests); `make test-all` runs every test (the fast tier and the full one),
# `make test-full` the full tier alone.
# Each creates $(VENV) on first use (or anew if another Python made it) and installs the
# project with the versions pinned in constraints.txt. Another Python:
#   make test PYTHON=python3.13 VENV=.venv-3.13
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
# the version of $(PYTHON), e.g. 3.11.7: a .venv made by another one is rebuilt
PYVER := $(shell $(PYTHON) -c 'import platform; print(platform.python_version())' 2>/dev/null)

.PHONY: test test-all test-full sweep bench baselines lock clean check-python

check-python:
	@$(PYTHON) -c 'import sys; sys.exit(0 if (3, 11) <= sys.version_info[:2] <= (3, 13) else \
	"$(PYTHON) is Python %d.%d; batsim needs 3.11, 3.12 or 3.13 (make PYTHON=python3.11)" \
	% sys.version_info[:2])'
	@if [ -x $(PY) ] && [ "$$($(PY) -c 'import platform; print(platform.python_version())')" \
	    != "$(PYVER)" ]; then echo "$(VENV) was made by another Python: rebuilding it"; \
	    rm -rf $(VENV); fi

$(STAMP): pyproject.toml constraints.txt | check-python
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -c constraints.txt -e '.[test]'
	touch $(STAMP)

# The linter first (rules in pyproject.toml), then the tests on WORKERS processes (pytest-xdist;
# a batched engine's tests share one, see tests/conftest.py), the slowest listed at the end.
# TESTS: a part of the suite (paths, -k ...); HYPOTHESIS: the hypothesis profile (fast or ci;
# test-all and test-full use ci). test-full: the full tier alone (CI runs it beside make test
# on another Python, so that each test runs once).
TESTS ?=
WORKERS ?= auto
HYPOTHESIS ?= fast
PYTEST = $(PY) -m pytest -q -n $(WORKERS) --dist loadgroup --durations=15
test: check-python $(STAMP)
	$(PY) -m ruff check .
	$(PY) -m ruff format --check .
	$(PYTEST) --hypothesis-profile=$(HYPOTHESIS) -m "not full" $(TESTS)

test-all: check-python $(STAMP)
	$(PY) -m ruff check .
	$(PY) -m ruff format --check .
	$(PYTEST) --hypothesis-profile=ci $(TESTS)

test-full: check-python $(STAMP)
	$(PY) -m ruff check .
	$(PY) -m ruff format --check .
	$(PYTEST) --hypothesis-profile=ci -m full $(TESTS)

sweep: check-python $(STAMP)
	$(PY) -m experiments.sweep --engine mujoco

bench: check-python $(STAMP)
	$(PY) -m experiments.bench_analytic
	$(PY) -m experiments.bench_engines

baselines: check-python $(STAMP)
	$(PY) -m experiments.baselines

# Refresh constraints.txt: resolve the newest versions pyproject.toml allows in a scratch
# environment and pin them (then run `make test` on 3.11 and 3.13 before committing).
lock:
	rm -rf .venv-lock && $(PYTHON) -m venv .venv-lock
	.venv-lock/bin/python -m pip install --quiet --upgrade pip
	.venv-lock/bin/python -m pip install --quiet '.[test]'
	.venv-lock/bin/python -m pip freeze --exclude-editable | grep -v '^batsim' > constraints.txt
	rm -rf .venv-lock

clean:
	rm -rf $(VENV) .venv-* build *.egg-info
