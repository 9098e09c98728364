# tankfx: the two commands of the quick start are `make demo` and `make test`.
# Both create .venv (Python >= 3.12) if it is missing and install the project into it.

VENV    ?= .venv
PY      := $(VENV)/bin/python
MPIEXEC := $(VENV)/bin/mpiexec
NP      ?= 2
STAMP   := $(VENV)/.tankfx-installed
INSTALL_CHROMIUM ?= yes

.PHONY: demo test verify lint docs test-serial test-mpi verify-serial verify-mpi benchmark venv clean gallery verification figures browser

venv: $(STAMP)

# The first Python >= 3.12 found: python3.12, python3.13, then python3 (with pyenv, the
# .python-version file of this repository makes python3 resolve to 3.12).
$(STAMP): pyproject.toml
	@if [ ! -x $(PY) ]; then \
	  py=""; for c in python3.12 python3.13 python3.14 python3; do \
	    if $$c -c 'import sys; sys.exit(sys.version_info < (3, 12))' >/dev/null 2>&1; then py=$$c; break; fi; \
	  done; \
	  if [ -z "$$py" ]; then echo "make: tankfx needs Python >= 3.12 (none found on PATH)"; exit 1; fi; \
	  echo "make: creating $(VENV) with $$($$py --version)"; \
	  $$py -m venv $(VENV) || exit 1; \
	fi
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e ".[test,docs]"
	@touch $(STAMP)

demo: $(STAMP)
	$(PY) demos/embedded_tank.py

# Every figure of `tankfx run` for three scenes, in docs/gallery/ (docs/gallery.md)
gallery: $(STAMP)
	$(PY) docs/gallery.py

# The suite. The site is built by its test (tests/test_docs.py, warnings as errors), not by
# `make docs` again. Headless Chromium, which two tests render pages in, is installed first
# where it is missing and this user may (root, or sudo without a password; INSTALL_CHROMIUM=no
# never installs): else those two are skipped, each with its reason, and the end says so.
test: lint browser test-serial test-mpi
	@command -v chromium >/dev/null 2>&1 || echo "make test: passed without the 2 browser \
	tests (no chromium on the PATH; sudo apt-get install chromium, then make test again)"

browser:
	@INSTALL_CHROMIUM=$(INSTALL_CHROMIUM) sh tests/install_chromium.sh

# The documentation site, warnings as errors: open docs/_build/html/index.html. The
# tutorials (from the demos) and the command line's help are generated as it builds.
docs: $(STAMP)
	$(VENV)/bin/sphinx-build -q -W --keep-going -b html docs docs/_build/html
	@echo "docs: open docs/_build/html/index.html"

# The figures of the tutorials (docs/figures/), drawn by the demos on their default meshes
figures: $(STAMP)
	$(PY) docs/figures.py

# The verification table of the site (docs/verification.md) from fresh verification runs
verification: $(STAMP)
	$(PY) docs/verification.py

# The package's layers and no import cycle (import-linter's contracts in pyproject.toml;
# docs/architecture.md says what each layer holds).
lint: $(STAMP)
	$(VENV)/bin/lint-imports

# The serial tests in WORKERS processes side by side (pytest-xdist), a test file to a
# process (a module's shared fixtures are made once): on this project's 2-core machine 403 s
# against 661 s one after another. WORKERS=0 runs them in this one process.
WORKERS ?= 2

PYTEST   = $(PY) -m pytest -q -rfEs -p no:cacheprovider
XDIST    = $(if $(filter 0,$(WORKERS)),,-n $(WORKERS) --dist loadfile)

test-serial: $(STAMP)
	$(PYTEST) --durations=12 $(XDIST) -m "not verify"

# The tests marked `mpi` again on $(NP) ranks: each compares its parallel results with a
# serial solve of the same scene.
test-mpi: $(STAMP)
	$(MPIEXEC) -n $(NP) $(PYTEST) -m "mpi and not verify"

# The rest of the verification (docs/development/testing.md): the tests marked `verify`
# (convergence studies, fine meshes, the bounds at their published gaps, the slow demos
# at their default meshes), serially and, those marked `mpi` too, on $(NP) ranks.
verify: verify-serial verify-mpi

verify-serial: $(STAMP)
	$(PYTEST) --durations=12 $(XDIST) -m verify

verify-mpi: $(STAMP)
	$(MPIEXEC) -n $(NP) $(PYTEST) -m "mpi and verify"

benchmark: $(STAMP)
	$(PY) benchmarks/flexible_load.py

clean:
	rm -rf $(VENV) results .pytest_cache docs/_build docs/_generated
