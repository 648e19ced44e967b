# urwire: one spec (spec/) -> generator (codegen/) -> Python, C and Lua targets (generated/).
# Target-specific rules live in mk/*.mk; each adds itself to ALL_TARGETS, TEST_BUILDS (what
# `make test` builds before its tests), DEEP_TESTS (what `make test-deep` runs beside its sweeps),
# DEMO_TARGETS and BENCH_TARGETS.

PYTHON ?= python3
PYTEST ?= $(PYTHON) -m pytest

ALL_TARGETS :=
TEST_BUILDS :=
DEEP_TESTS :=
DEMO_TARGETS :=
DEMO_CELL_TARGETS :=
BENCH_TARGETS :=

.PHONY: all generate check-generated spec-diff setup test test-deep test-codegen test-python test-python-range soak demo demo-python bench-export \
	bench bench-python

all: build-all

-include mk/*.mk

build-all: $(ALL_TARGETS)

## generate: rewrite generated/ and docs/protocol.md from the spec
generate:
	$(PYTHON) -m codegen
	$(PYTHON) -m codegen reference

## check-generated: fail if generated/ or docs/protocol.md is not exactly what the spec gives
check-generated:
	$(PYTHON) -m codegen --check
	$(PYTHON) -m codegen reference --check

## spec-diff: what changes between two software versions (make spec-diff FROM=3.15 TO=5.11), of
## any interface (SPEC=spec/ur_realtime.yaml)
FROM ?= 3.15
TO ?= 5.11
SPEC ?= spec/ur_primary.yaml
spec-diff:
	@$(PYTHON) -m codegen diff $(FROM) $(TO) --spec $(SPEC)

## setup: install the system and Python packages that the tests and the demo need
setup:
	bash scripts/setup.sh

## test: every test of every target (the README's test command, and CI's); the fuzzers' kept
## corpora are replayed there, and `make fuzz` fuzzes for longer. The live tools' tests wait on
## sockets and timers far more than they compute, so they run in a pytest of their own beside the
## rest (their output follows), and the rest spread over TEST_JOBS processes (pytest-xdist, a test
## file per process at a time); `pytest tests` runs everything in one.
LIVE_TESTS := tests/python/test_live.py tests/python/test_listen_field.py tests/python/test_listen_hostile.py \
	tests/python/test_serve_cell.py tests/python/test_serve_cell_hostile.py tests/python/test_rtde_client.py \
	tests/python/test_listen_rtde.py tests/python/test_cell_capture.py tests/python/test_urcl_rtde_dashboard.py \
	tests/python/test_serve_hostile.py tests/python/test_serve_refuses.py tests/python/test_serve_dashboard.py \
	tests/python/test_serve_rtde_table.py tests/python/test_serve_primary_layout.py \
	tests/python/test_mcap_listen.py tests/python/test_foxglove_listen.py
TEST_JOBS ?= auto
test: check-generated $(TEST_BUILDS)
	@mkdir -p build
	@$(PYTEST) -q $(LIVE_TESTS) > build/live-tests.log 2>&1 & live=$$!; \
	$(PYTEST) -q -n $(TEST_JOBS) --dist loadfile -m "not deep" tests $(LIVE_TESTS:%=--ignore=%); rest=$$?; \
	wait $$live; live=$$?; echo "== the live tools' tests"; cat build/live-tests.log; \
	[ $$rest -eq 0 ] && [ $$live -eq 0 ]

## test-deep: the long sweeps that `make test` leaves out (tests marked `deep`: the native
## dissectors against Lua on every segmentation and the whole fuzz corpora, every run of the
## plugin built with ASan+UBSan: tests/native/conftest.py, the Python extension so built, the
## long runs that must take flat memory, and a few builds of variants), and DEEP_TESTS (the targets' own, such as test-python-backend); CI runs it after `make test`
test-deep: $(TEST_BUILDS) $(DEEP_TESTS)
	$(PYTEST) -q -n $(TEST_JOBS) --dist loadfile -m deep tests $(LIVE_TESTS:%=--ignore=%)

## test-codegen, test-python (and test-c, test-lua): the tests of one folder
test-codegen:
	$(PYTEST) -q tests/codegen

test-python:
	$(PYTEST) -q tests/python

## test-python-range: tests/python and tests/codegen on the lowest and the highest Python the
## package claims (3.10 and 3.13 from pyenv or the system), each in a venv under build/python-range
PYTHON_RANGE ?= 3.10 3.13
test-python-range:
	bash scripts/test-python-range.sh $(PYTHON_RANGE)

## soak: serve with SOAK_CLIENTS clients and listen through a proxy that cuts it off every few
## seconds, for SOAK_SECONDS; prints each process's memory over time and the rates (not in `make test`)
SOAK_SECONDS ?= 300
SOAK_CLIENTS ?= 500
soak:
	PYTHONPATH=python:generated/python $(PYTHON) tests/tools/soak.py --seconds $(SOAK_SECONDS) --clients $(SOAK_CLIENTS)

## demo: set up, then decode the bundled captures with every target: the primary interface, then the whole cell
demo: setup demo-python $(DEMO_TARGETS) $(DEMO_CELL_TARGETS)

demo-python:
	@echo "== Python: urwire decode --format text dissector/samples/primary_session.pcapng"
	@PYTHONPATH=python:generated/python $(PYTHON) -m urwire decode --format text dissector/samples/primary_session.pcapng | head -n 12

## bench: speed figures, each a ratio against a baseline measured in the same run
bench: bench-python $(BENCH_TARGETS)

## bench-python: decode per message (against python-urx and the package of BENCH_PY_GENERATIONS),
## a JSON line (against the package of BENCH_PY_BASE), and BENCH_PY_MB megabytes of raw and .pcap
## input read in their own processes: MB/s and peak memory
BENCH_PY_BASE ?= 56d4759
BENCH_PY_GENERATIONS ?= 27a9d98
BENCH_PY_MB ?= 10 100
bench-python:
	PYTHONPATH=python:generated/python $(PYTHON) tests/bench/bench_python.py --base $(BENCH_PY_BASE) \
		--generations-base $(BENCH_PY_GENERATIONS) $(BENCH_PY_MB)

## bench-export: `urwire export` of one robot-day (BENCH_EXPORT_STATES real robot states) to the
## dataset, against `urwire export --out` of BENCH_EXPORT_BASE: time, states/s, peak memory, ratio
BENCH_TARGETS += bench-export
BENCH_EXPORT_BASE ?= a8e2eb2
BENCH_EXPORT_STATES ?= 864000
bench-export:
	PYTHONPATH=python:generated/python $(PYTHON) tests/bench/bench_export.py --base $(BENCH_EXPORT_BASE) \
		--states $(BENCH_EXPORT_STATES)

## bench-capture: `urwire decode` and `export --dataset` of a BENCH_CAPTURE_MB-megabyte capture of a cell
## (the bundled capture's primary conversation repeated, built in build/bench-capture) against the same
## bytes as a raw stream and against the Python capture reader: CPU time ratios
BENCH_TARGETS += bench-capture
BENCH_CAPTURE_MB ?= 1024
.PHONY: bench-capture
bench-capture: python-ext
	PYTHONPATH=python:generated/python $(PYTHON) tests/bench/bench_capture.py --mb $(BENCH_CAPTURE_MB)
