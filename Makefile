# modbus_edu: every target bootstraps its own virtual environment in .venv from pinned requirements, so a
# fresh clone needs only Python (3.10 or newer) and git.
#
#   binder/requirements.txt       the learner's pins (the course, JupyterLab, widgets, plots): what Binder
#                                 and `make lab` install
#   binder/requirements-test.txt  the learner's pins plus the test tools: what `make test` and CI install
#
# .venv remembers what it was built from (.venv/modbus-edu-stamp: the Python's version and path and a hash
# of the pins and pyproject.toml). Another Python, changed pins or an install that never finished rebuild
# it from scratch, with one line saying why. PYTHON=python3.12 picks the interpreter, VENV=.venv-3.12 a
# second environment beside the first.

PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/modbus-edu-stamp
LEARNER_PINS := binder/requirements.txt
TEST_PINS    := binder/requirements-test.txt
# the oldest supported Python, read from pyproject.toml (the one place that says it)
MIN_PYTHON := $(shell sed -n 's/^requires-python = ">=\([0-9.]*\)".*/\1/p' pyproject.toml)
UV     := uv==0.13.9
RELEASE ?= release
SUBMISSIONS ?= submissions
OUT ?= grades
EXPORT ?=
NOTEBOOKS ?=
# one shell word, whatever it holds: a Moodle zip's name has spaces ('$(SUBMISSIONS)' stays whole)
quote = '$(subst ','\'',$(1))'

LITE_VENV := .venv-lite
LITE_WHEELS := build/lite/wheels
OFFLINE ?=

.PHONY: help install lab test test-unit test-library notebooks lint bench requirements coverage release grade lite clean

## help: list these targets
help:
	@sed -n 's/^## //p' Makefile

# stamp(pins...): what a .venv built now by $(PYTHON) from these pins would record
stamp = $(shell $(PYTHON) -c 'import hashlib, platform, sys; h = hashlib.sha256(); \
    [h.update(open(f, "rb").read()) for f in sys.argv[1:]]; \
    print(platform.python_implementation(), platform.python_version(), sys.executable, h.hexdigest()[:16])' \
    $(1) pyproject.toml 2>/dev/null)

# venv(pins, also-accepted pins): build .venv from the pins unless its stamp says that this Python built
# it, to the end, from them (or from the also-accepted pins, a superset: the test pins serve `make lab`)
define venv
	@want='$(call stamp,$(1))'; also='$(call stamp,$(2))'; have="$$(cat $(STAMP) 2>/dev/null)"; \
	if [ -z "$$want" ]; then echo "$(PYTHON) does not run: install Python $(MIN_PYTHON) or newer, or give make PYTHON=..."; exit 1; fi; \
	if [ "$$have" != "$$want" ] && [ "$$have" != "$$also" ]; then \
	    if [ -d $(VENV) ]; then \
	        if [ -z "$$have" ]; then why="its install never finished"; \
	        elif [ "$${have% *}" = "$${want% *}" ]; then \
	            why="it was built from other pins than $(1) (the learner's pins of make lab lack the test tools, or the pins changed)"; \
	        else why="it was built by $${have% *}, now $${want% *}"; fi; \
	        echo "rebuilding $(VENV) from $(1): $$why"; \
	    fi; \
	    rm -rf $(VENV) && $(PYTHON) -m venv $(VENV) && \
	    $(BIN)/python -m pip install --quiet --upgrade pip && \
	    $(BIN)/python -m pip install --quiet $(foreach pins,$(1),-r $(pins)) && \
	    $(BIN)/python -m pip install --quiet --no-deps --editable . && \
	    echo "$$want" > $(STAMP); \
	fi
endef

## install: build .venv from the test pins (every other target does it too)
install:
	$(call venv,$(TEST_PINS))

## lab: install the course (binder/requirements.txt) and open it in JupyterLab, in notebooks/
lab:
	$(call venv,$(LEARNER_PINS),$(TEST_PINS))
	$(BIN)/python -m jupyter lab --notebook-dir=notebooks $$([ "$$(id -u)" = 0 ] && echo --allow-root) \
	    notebooks/00_welcome.ipynb

## test: install the test pins and run the whole test suite (lint, unit, interop, browser, strict nbval)
test:
	$(call venv,$(TEST_PINS))
	$(BIN)/python -m ruff check modbus_edu tests bench
	$(BIN)/python -m pytest tests notebooks --nbval --nbval-sanitize-with notebooks/sanitize.cfg

## test-unit: the test suite without the browser test, strict nbval and the slow packaging tests (for a
##     second Python: make test-unit PYTHON=python3.10 VENV=.venv-3.10)
test-unit:
	$(call venv,$(TEST_PINS))
	$(BIN)/python -m pytest tests --ignore=tests/test_browser.py -m "not slow" -p no:cacheprovider -q

## test-library: the library's own tests (protocol, links, devices, command line, peers), what a second
##     Python must pass: the course's tooling (gradebook, checkers, notebooks, browsers, the Lite site,
##     packaging) is left to `make test` (CI: .ci/run runs this on the oldest and the newest Python)
COURSE_TESTS := test_browser* test_widgets* test_pictures.py test_lite* test_pyodide.py test_course.py \
    test_grade* test_exercise* test_checker_* test_procedures.py test_heldout.py test_slips.py \
    test_teaching.py test_inventory.py test_packaging.py test_bench_day.py test_architecture.py
test-library:
	$(call venv,$(TEST_PINS))
	$(BIN)/python -m pytest tests $(foreach t,$(COURSE_TESTS),--ignore-glob='tests/$(t)') -m "not slow" \
	    -p no:cacheprovider -q

## notebooks: re-execute every notebook in place, in order, from a fresh kernel
notebooks:
	$(call venv,$(TEST_PINS))
	$(BIN)/python -m modbus_edu.course execute notebooks

## bench: the benchmarks against pymodbus (ratios > 1 mean modbus_edu is faster)
bench:
	$(call venv,$(TEST_PINS))
	$(BIN)/python bench/core.py
	$(BIN)/python bench/roles.py
	$(BIN)/python bench/splitters.py
	$(BIN)/python bench/timeouts.py
	$(BIN)/python bench/grade.py --quick

## coverage: how much of modbus_edu the notebooks alone exercise: copies of the notebooks are executed
##     with coverage started in every kernel (through a start-up hook that exists only while this runs)
coverage:
	$(call venv,$(TEST_PINS))
	$(BIN)/python -m coverage erase
	rm -rf .coverage-notebooks && cp -r notebooks .coverage-notebooks
	hook=$$($(BIN)/python -c "import sysconfig; print(sysconfig.get_paths()['purelib'])")/modbus_edu_coverage.pth; \
	echo "import coverage; coverage.process_startup()" > $$hook; \
	COVERAGE_PROCESS_START=$(CURDIR)/pyproject.toml COVERAGE_FILE=$(CURDIR)/.coverage \
	    $(BIN)/python -m modbus_edu.course execute .coverage-notebooks; status=$$?; rm -f $$hook; exit $$status
	rm -rf .coverage-notebooks
	$(BIN)/python -m coverage combine -q
	$(BIN)/python -m coverage report

## lint: ruff over the library, the tests and the benchmarks
lint:
	$(call venv,$(TEST_PINS))
	$(BIN)/python -m ruff check modbus_edu tests bench

## requirements: re-pin both files for every supported Python and platform (one universal lock each,
##     with environment markers) from pyproject.toml and binder/requirements.in; the test pins keep the
##     learner's versions
requirements:
	$(call venv,$(TEST_PINS))
	$(BIN)/python -m pip install --quiet $(UV)
	UV_PYTHON_DOWNLOADS=never $(BIN)/python -m uv pip compile --quiet --universal --python-version $(MIN_PYTHON) \
	    --annotation-style line --no-header --extra course \
	    --output-file $(LEARNER_PINS) pyproject.toml binder/requirements.in
	UV_PYTHON_DOWNLOADS=never $(BIN)/python -m uv pip compile --quiet --universal --python-version $(MIN_PYTHON) \
	    --annotation-style line --no-header --extra course --extra test --constraint $(LEARNER_PINS) \
	    --output-file $(TEST_PINS) pyproject.toml binder/requirements.in

## release: write a copy of the course for a class repository into $(RELEASE)/ (RELEASE=dir to change it):
##     everything but the worked solutions, the tests and the tooling
release:
	$(call venv,$(LEARNER_PINS),$(TEST_PINS))
	$(BIN)/python -m modbus_edu.course release $(RELEASE)

## grade: grade a class's notebooks (SUBMISSIONS=one folder or zip, spaces kept, default submissions/)
##     into a gradebook, a page per learner and a class summary in $(OUT)/ (OUT=dir to change it);
##     NOTEBOOKS=00,01,03 says which notebooks count, EXPORT=moodle|canvas writes the platform's grade
##     import; each notebook runs in a fresh, limited kernel (modbus-edu grade --help for the rest)
grade:
	$(call venv,$(LEARNER_PINS),$(TEST_PINS))
	$(BIN)/python -m modbus_edu grade $(call quote,$(SUBMISSIONS)) --out $(call quote,$(OUT))$(if \
	  $(NOTEBOOKS), --notebooks $(call quote,$(NOTEBOOKS)))$(if $(EXPORT), --export $(call quote,$(EXPORT)))

## lite: build the course as a JupyterLite site in _site/ (notebooks on Pyodide, in the browser; any static
##     host serves it). Published (default): Pyodide and matplotlib from Pyodide's CDN, at the version the
##     kernel expects. `make lite OFFLINE=1`: Pyodide from the npm package (lite/package.json), every
##     package bundled, no request leaves the site (a USB stick, a classroom without internet)
lite:
	@[ -x $(LITE_VENV)/bin/python ] || $(PYTHON) -m venv $(LITE_VENV)
	$(LITE_VENV)/bin/python -m pip install --quiet -r lite/requirements.txt
	$(LITE_VENV)/bin/python lite/wheels.py $(LITE_WHEELS)
	$(if $(OFFLINE),cd lite && npm ci --no-audit --no-fund --loglevel=error)
	$(LITE_VENV)/bin/python lite/build_site.py --wheels $(LITE_WHEELS) --out _site $(if $(OFFLINE),--offline)

## clean: remove the virtual environment, the caches and what the targets above wrote
clean:
	rm -rf $(VENV) .venv-* .pytest_cache .hypothesis .ruff_cache .coverage .coverage.* .coverage-notebooks \
	    build dist $(RELEASE) _site lite/node_modules
