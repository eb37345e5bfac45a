# Two entry points, each doing its own set-up on a fresh machine:
#   make run   - the main job: train SAC on BeachballSail-v2 with the quick preset
#                (configs/beachball_sail_v2_quick.yaml: under 10 minutes on two CPU cores),
#                evaluate it beside random play and the VMG autopilot, and write the run
#                folder runs/main (model, results table, learning curve, animation)
#   make test  - lint, the test suite and the strict build of the documentation site
#   make docs  - the documentation site (docs/mkdocs.yml) into runs/site
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
# The main job needs only the train, plots and render extras: without Ray and RL Zoo its
# set-up on a fresh machine is shorter. A full install (make test) covers it too.
RUN_STAMP := $(VENV)/.installed-run

.PHONY: run test docs setup demo polar bench clean

# torch goes in first, pinned to the CPU wheel this project's machines carry: left to
# resolve `torch` itself, pip would fetch a multi-GB CUDA build. Elsewhere, PyTorch's CPU
# wheel index gives the CPU build: make setup TORCH_INDEX=https://download.pytorch.org/whl/cpu
TORCH ?= torch==2.13.0
TORCH_INDEX ?=
TORCH_PIP := $(if $(TORCH_INDEX),--index-url $(TORCH_INDEX),)

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet $(TORCH_PIP) "$(TORCH)"
	$(PY) -m pip install --quiet -e ".[dev,train,torch,torchrl,rllib,zoo,docs,jax,rejax]"
	touch $(STAMP) $(RUN_STAMP)

$(RUN_STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet $(TORCH_PIP) "$(TORCH)"
	$(PY) -m pip install --quiet -e ".[train,plots,render]"
	touch $(RUN_STAMP)

setup: $(STAMP)

run: $(RUN_STAMP)
	SDL_VIDEODRIVER=dummy $(VENV)/bin/bbgym baseline --env BeachballSail-v2 --preset beachball_sail_v2_quick --seeds 1 --torch-threads 2 --out runs/main

demo: $(STAMP)
	SDL_VIDEODRIVER=dummy $(VENV)/bin/bbgym demo --out runs/demo

test: $(STAMP)
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .
	SDL_VIDEODRIVER=dummy $(VENV)/bin/pytest -q
	NO_MKDOCS_2_WARNING=1 $(VENV)/bin/mkdocs build --strict -f docs/mkdocs.yml

docs: $(STAMP)
	NO_MKDOCS_2_WARNING=1 $(VENV)/bin/mkdocs build --strict -f docs/mkdocs.yml

polar: $(STAMP)
	$(VENV)/bin/bbgym polar --out runs/polar

bench: $(STAMP)
	$(VENV)/bin/bbgym bench

clean:
	rm -rf $(VENV) runs
