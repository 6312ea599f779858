# modbus_edu: every target bootstraps its own virtual environment in .venv from the pinned
# binder/requirements.txt (the same pins Binder uses), so a fresh clone needs only Python 3 and git.

PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: lab test notebooks lint bench requirements coverage clean

$(STAMP): binder/requirements.txt pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -r binder/requirements.txt
	touch $(STAMP)

## lab: install everything and open the course in JupyterLab
lab: $(STAMP)
	$(BIN)/python -m jupyter lab --notebook-dir=notebooks $$([ "$$(id -u)" = 0 ] && echo --allow-root) \
	    notebooks/00_welcome.ipynb

## test: install everything and run the whole test suite (lint, unit, interop, browser, strict nbval)
test: $(STAMP)
	$(BIN)/python -m ruff check modbus_edu tests bench
	$(BIN)/python -m pytest tests notebooks --nbval --nbval-sanitize-with notebooks/sanitize.cfg

## notebooks: re-execute every notebook in place, in order, from a fresh kernel
notebooks: $(STAMP)
	$(BIN)/python -m modbus_edu.course execute notebooks

## bench: the benchmarks against pymodbus (ratios > 1 mean modbus_edu is faster)
bench: $(STAMP)
	$(BIN)/python bench/core.py
	$(BIN)/python bench/roles.py
	$(BIN)/python bench/splitters.py
	$(BIN)/python bench/timeouts.py

## coverage: how much of modbus_edu the notebooks alone exercise: copies of the notebooks are executed
## with coverage started in every kernel (through a start-up hook that exists only while this runs)
coverage: $(STAMP)
	$(BIN)/python -m coverage erase
	rm -rf .coverage-notebooks && cp -r notebooks .coverage-notebooks
	hook=$$($(BIN)/python -c "import sysconfig; print(sysconfig.get_paths()['purelib'])")/modbus_edu_coverage.pth; \
	echo "import coverage; coverage.process_startup()" > $$hook; \
	COVERAGE_PROCESS_START=$(CURDIR)/pyproject.toml COVERAGE_FILE=$(CURDIR)/.coverage \
	    $(BIN)/python -m modbus_edu.course execute .coverage-notebooks; status=$$?; rm -f $$hook; exit $$status
	rm -rf .coverage-notebooks
	$(BIN)/python -m coverage combine -q
	$(BIN)/python -m coverage report

lint: $(STAMP)
	$(BIN)/python -m ruff check modbus_edu tests bench

## requirements: re-pin binder/requirements.txt from binder/requirements.in
requirements:
	$(BIN)/python -m pip install --quiet pip-tools
	$(BIN)/pip-compile --quiet --strip-extras --no-header --no-emit-index-url --no-emit-find-links \
	    --annotation-style=line --output-file binder/requirements.txt binder/requirements.in
	sed -i 's|^-e file:.*|-e .|' binder/requirements.txt

clean:
	rm -rf $(VENV) .pytest_cache .hypothesis .ruff_cache
