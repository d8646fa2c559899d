# The README's two commands: `make demo` and `make test`.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin

.PHONY: demo test lint bench clean

$(BIN)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $@

demo: $(BIN)/.installed
	$(BIN)/eigenupdate check examples/paper_beam/study.toml
	$(BIN)/eigenupdate update examples/paper_beam/study.toml

test: $(BIN)/.installed
	$(BIN)/ruff check src tests benchmarks tools
	$(BIN)/python -m pytest -q

bench: $(BIN)/.installed
	$(BIN)/python benchmarks/bench_update.py

clean:
	rm -rf $(VENV) build src/*.egg-info
