# Two entry points do all the set-up on a fresh machine: `make demo` and `make test`.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: demo test setup

$(STAMP): pyproject.toml
	$(PY) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[test]'
	cd viewer && npm ci --no-audit --no-fund --loglevel=error && npm run build --silent
	touch $(STAMP)

setup: $(STAMP)

demo: $(STAMP)
	$(BIN)/mura demo

test: $(STAMP)
	$(BIN)/python -m pytest
