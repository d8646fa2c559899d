# The README's two commands: `make demo` and `make test`.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
# pyNastran needs numpy < 2: the NASTRAN path is tested in its own environment
NVENV ?= .venv-nastran
NBIN := $(NVENV)/bin

.PHONY: demo test lint test-core test-nastran test-kernels bench clean

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

# Every step runs even when an earlier one fails (one failure must not hide another);
# the summary names each failed step and the command that reruns it alone.
test: $(BIN)/.installed $(NBIN)/.installed
	@failed=""; \
	$(MAKE) --no-print-directory lint || failed="$$failed lint"; \
	$(MAKE) --no-print-directory test-core || failed="$$failed test-core"; \
	$(MAKE) --no-print-directory test-nastran || failed="$$failed test-nastran"; \
	if [ -n "$$failed" ]; then \
		echo "make test: FAILED:$$failed"; \
		for s in $$failed; do echo "  rerun that step alone: make $$s"; done; \
		exit 1; \
	fi; \
	echo "make test: lint, core suite and NASTRAN suite passed"

lint: $(BIN)/.installed
	$(BIN)/ruff check src tests benchmarks tools

test-core: $(BIN)/.installed
	$(BIN)/python -m pytest -q

# NASTRAN tests for real: a missing pyNastran or OpenSees is a failure here, not a skip
test-nastran: $(NBIN)/.installed
	EIGENUPDATE_REQUIRE_NASTRAN=1 $(NBIN)/python -m pytest -q -m nastran tests

# Both suites again under each OpenBLAS kernel this CPU can run (tools/openblas_kernels.sh:
# Prescott, Nehalem, Sandybridge, Zen where the instruction sets allow); CI runs it. The
# core suite's slow tests (Monte Carlo statistics, Dask clusters, the browser: 300 of its
# 525 s) run once, in `make test`: four more rounds would take CI past its time limit.
# KERNELS="Prescott Zen" make test-kernels picks some.
KERNELS ?= $(shell sh tools/openblas_kernels.sh)
test-kernels: $(BIN)/.installed $(NBIN)/.installed
	@failed=""; \
	for k in $(KERNELS); do \
		echo "== OPENBLAS_CORETYPE=$$k"; \
		OPENBLAS_CORETYPE=$$k $(BIN)/python -m pytest -q -p no:cacheprovider -m "not slow" \
			|| failed="$$failed $$k:core"; \
		OPENBLAS_CORETYPE=$$k EIGENUPDATE_REQUIRE_NASTRAN=1 $(NBIN)/python -m pytest -q \
			-p no:cacheprovider -m nastran tests || failed="$$failed $$k:nastran"; \
	done; \
	if [ -n "$$failed" ]; then \
		echo "make test-kernels: FAILED:$$failed"; \
		echo "  rerun one: KERNELS=<kernel> make test-kernels"; \
		exit 1; \
	fi; \
	echo "make test-kernels: passed under $(KERNELS)"

bench: $(BIN)/.installed
	$(BIN)/python benchmarks/bench_update.py

clean:
	rm -rf $(VENV) $(NVENV) build src/*.egg-info
