# Two commands for a fresh machine with python3 (with venv) and make:
#   make demo   create .venv, install, screen the bundled records -> results/
#   make test   create .venv if needed, install with test extras, run the suite except the tests marked
#               slow (make test-slow runs those; CI runs both)
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
PYTEST_ARGS ?=

.PHONY: demo event-demo constrain-demo test test-slow soak lint browser peers bench clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)

$(VENV)/.installed: pyproject.toml | $(BIN)/python
	@echo "installing rockscreen and its dependencies (pyproject.toml) into $(VENV) with pip: about a minute, once"
	@$(PYTHON) tools/ticking.py "installing" -- $(BIN)/python -m pip install --quiet --disable-pip-version-check -e .
	touch $@

$(VENV)/.installed-test: pyproject.toml | $(BIN)/python
	@echo "installing rockscreen, its dependencies and the test extras into $(VENV) with pip: a minute or two, once"
	@$(PYTHON) tools/ticking.py "installing" -- $(BIN)/python -m pip install --quiet --disable-pip-version-check \
	    -e '.[test]'
	touch $@ $(VENV)/.installed

$(VENV)/.installed-lint: pyproject.toml | $(BIN)/python
	@$(PYTHON) tools/ticking.py "installing" -- $(BIN)/python -m pip install --quiet --disable-pip-version-check \
	    -e '.[lint]'
	touch $@ $(VENV)/.installed

demo: $(VENV)/.installed
	$(BIN)/screen --records records --blocks configs/blocks.csv --out results --tolerate-failures
	$(BIN)/screen chart --block COL-1 --blocks configs/blocks.csv --results results/screening.nc \
	    --out results/chart-COL-1.nc
	$(BIN)/screen --records records --blocks examples/assemblies/blocks.csv --out results/assemblies \
	    --tolerate-failures

# After an earthquake: fragilities of the example inventory from the bundled records (on PGV, the component
# ShakeMap reports), then the scenario ShakeMap -> results/event/event.html, inspection.csv, event.nc
event-demo: $(VENV)/.installed
	$(BIN)/screen fragility --records records --blocks examples/event/blocks.csv --im pgv --im-component larger \
	    --levels auto --out results/event-fragility --tolerate-failures
	$(BIN)/screen event --shakemap examples/event/903_m6p09_se-scenario-grid.xml.gz \
	    --blocks examples/event/blocks.csv --fragility results/event-fragility --out results/event

# Rocks that stood: the fragility of the two granite rocks of examples/constrain/ from the bundled records (on PGA as
# RotD50, OpenQuake's definition), then the constraint they put on the example's OpenQuake logic tree
# -> results/constrain/constrain.html, constrain.nc and the reweighted curves
constrain-demo: $(VENV)/.installed
	$(BIN)/screen fragility --records records --blocks examples/constrain/rocks.csv --im pga --im-component rotd50 \
	    --levels auto --out results/pbr-fragility --tolerate-failures
	$(BIN)/screen constrain --fragility results/pbr-fragility --ages examples/constrain/ages.csv \
	    --hazard-branches examples/constrain/openquake --out results/constrain

# the simulator is compiled (or loaded from numba's cache) once before the two test workers start, not by each,
# in two processes at once, each taking the next kernel not yet taken (pipeline/bodies/compile_share.py);
# a test file's tests stay on one worker (--dist loadfile), so a module's shared screenings run once, not on each
# worker (169 s against 211-222 s for the suite, measured)
test: $(VENV)/.installed-test browser
	@echo "compiling the simulator for the tests, or loading it from numba's cache (about 80 s the first time)"
	@$(PYTHON) tools/ticking.py "compiling the simulator" -- \
	$(BIN)/python -c "from pipeline.bodies.warmup import compile_kernels as c; c(helpers=1)"
	$(BIN)/python -m pytest -n 2 --dist loadfile -m "not slow and not soak" $(PYTEST_ARGS)

# The tests marked slow (each over 15 s: kill and interrupt runs, Dask runs against serial, re-measured
# figures quoted to users; the process pools against serial, 7-8 s each; and whole screen runs of 4-9 s each
# whose check a faster test also makes on fewer files or models: every bundled file, the pulse parity through the
# command, a model added to the registry, four of the five outputs' failed writes; and eleven checks of 2.6-6 s
# each, moved here because make test from a fresh clone, its install and compilation included, took 299 s: a
# signal at exit, margins split into tasks, a stack's shared runs, the run layer against its stages, a fragility
# link, the constrain page, a units.toml line, make's ticker, the benchmarks' heartbeat and loading, bench's
# failing record; and twenty checks whose file keeps faster ones of the same code: the five on the fragility
# suite against solve_ivp (its fixture 25-29 s), the drum columns' reference verdicts (17-23 s), nine of the
# twelve two-sided bodies (12-15 s together), the 20 m column on El Centro, a forced re-run, a run that lost a
# worker, a planted link, a helper's wait (4-8 s each): without them
# the suite took 260 s on 2 cores, with them 281-295 s, the same slower day, numba's cache warm); CI runs them after
# make test
test-slow: $(VENV)/.installed-test peers
	$(BIN)/python -m pytest -n 2 -m "slow and not soak" $(PYTEST_ARGS)

# Fifty scheduled screen runs into one output, killed at random (SIGKILL, SIGTERM, a worker's SIGKILL); after
# each the output shows one whole set, equal to an uninterrupted run's (about 5 minutes)
soak: $(VENV)/.installed-test
	$(BIN)/python -m pytest -m soak -s $(PYTEST_ARGS)

# The report is tested in headless Chromium (Debian's package). Installed when missing and possible
# (root with apt-get); otherwise that test is skipped with a loud reason.
browser:
	@command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1 || { \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
	    echo "installing Debian's chromium for the report test (apt-get)"; \
	    { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium; } >/dev/null 2>&1 \
	      || echo "WARNING: could not install chromium; the browser test will be skipped"; \
	  else \
	    echo "WARNING: chromium is missing and cannot be installed here (needs root and apt-get);" \
	         "the browser test will be skipped"; \
	  fi; }

# openseespy (the building peer of the floor-motion tests) needs the system's BLAS and LAPACK: installed when
# missing and possible (root with apt-get); otherwise that test is skipped with a loud reason.
peers:
	@ldconfig -p 2>/dev/null | grep -q 'libblas\.so\.3' && ldconfig -p 2>/dev/null | grep -q 'liblapack\.so\.3' || { \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
	    echo "installing Debian's libblas3 and liblapack3 for openseespy (apt-get)"; \
	    { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libblas3 liblapack3; } \
	      >/dev/null 2>&1 || echo "WARNING: could not install libblas3 and liblapack3; the OpenSees test will be skipped"; \
	  else \
	    echo "WARNING: libblas.so.3 or liblapack.so.3 is missing and cannot be installed here (needs root and" \
	         "apt-get); the OpenSees building test will be skipped"; \
	  fi; }

# ruff (pyflakes, pycodestyle, isort, bugbear, numpy rules) and mypy, configured in pyproject.toml
lint: $(VENV)/.installed-lint
	$(BIN)/ruff check .
	$(BIN)/mypy

# Benchmarks print measured ratios (never timed tests); about 20 minutes in all on 2 cores
# (bench_scale.py with 1000 records or 1000 blocks, or with sampling, takes much longer: run it by hand)
bench: $(VENV)/.installed-test
	$(BIN)/python benchmarks/bench_pulses.py
	$(BIN)/python benchmarks/bench_rocking.py --limit 60
	$(BIN)/python benchmarks/bench_boundaries.py
	$(BIN)/python benchmarks/criterion_vs_reference.py
	$(BIN)/screen bench --records records --blocks configs/blocks.csv --out results/bench --tiers-only
	$(BIN)/python benchmarks/bench_whole.py
	$(BIN)/python benchmarks/bench_scale.py --records 10,100 --blocks 10,100 --samples 0
	$(BIN)/python benchmarks/bench_scale.py --records 300,1000 --blocks 10 --samples 0   # memory against records
	$(BIN)/python benchmarks/bench_fragility.py
	$(BIN)/python benchmarks/bench_event.py

clean:
	rm -rf $(VENV) results .pytest_cache .hypothesis
