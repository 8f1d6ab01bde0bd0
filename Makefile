# Two commands on a fresh machine: `make sweep` (the main job) and `make test`.
# Each creates .venv on first use and installs the project from pyproject.toml.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: test sweep bench baselines clean

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet -e '.[test]'
	touch $(STAMP)

test: $(STAMP)
	$(PY) -m pytest -q

sweep: $(STAMP)
	$(PY) -m experiments.sweep --engine mujoco

bench: $(STAMP)
	$(PY) -m experiments.bench_analytic
	$(PY) -m experiments.bench_engines

baselines: $(STAMP)
	$(PY) -m experiments.baselines

clean:
	rm -rf $(VENV) build *.egg-info
