# The README's two commands: `make demo` and `make test`.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
# pyNastran needs numpy < 2: the NASTRAN path is tested in its own environment
NVENV ?= .venv-nastran
NBIN := $(NVENV)/bin

.PHONY: demo test lint bench clean

$(BIN)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $@

$(NBIN)/.installed: pyproject.toml
	$(PYTHON) -m venv $(NVENV)
	$(NBIN)/python -m pip install --quiet --upgrade pip
	$(NBIN)/python -m pip install --quiet -e '.[test,nastran]' 'openseespy>=3.7'
	touch $@

demo: $(BIN)/.installed
	$(BIN)/eigenupdate check examples/paper_beam/study.toml
	$(BIN)/eigenupdate update examples/paper_beam/study.toml

test: $(BIN)/.installed $(NBIN)/.installed
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/python -m pytest -q
	# NASTRAN tests for real: a missing pyNastran or OpenSees is a failure here, not a skip
	EIGENUPDATE_REQUIRE_NASTRAN=1 $(NBIN)/python -m pytest -q -m nastran tests

bench: $(BIN)/.installed
	$(BIN)/python benchmarks/bench_update.py

clean:
	rm -rf $(VENV) $(NVENV) build src/*.egg-info
