# Two commands on a fresh machine: `make demo` and `make test`.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
export MUJOCO_GL ?= egl

.PHONY: demo test lint venv bench clean

$(STAMP): pyproject.toml Makefile
	bash .ci/system-deps
	test -x $(BIN)/python || $(PY) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[all]'
	# test oracle only (tests/unitree_oracle.py), never a runtime dependency: Unitree's SDK wheel, no deps
	$(BIN)/python -m pip install --quiet --no-deps --upgrade --target $(VENV)/oracle unitree-sdk2==1.0.1
	touch $(STAMP)

venv: $(STAMP)

demo: $(STAMP)
	$(BIN)/gaitshift demo --out out/demo

test: $(STAMP)
	$(BIN)/python -m pytest

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/ruff format --check src tests benchmarks
	$(BIN)/mypy

bench: $(STAMP)
	$(BIN)/gaitshift bench

clean:
	rm -rf out build *.egg-info src/*.egg-info
