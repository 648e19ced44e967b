# urwire: one spec (spec/) -> generator (codegen/) -> Python, C and Lua targets (generated/).
# Target-specific rules live in mk/*.mk; each adds itself to ALL_TARGETS, TEST_TARGETS,
# DEMO_TARGETS and BENCH_TARGETS.

PYTHON ?= python3
PYTEST ?= $(PYTHON) -m pytest

ALL_TARGETS :=
TEST_TARGETS :=
DEMO_TARGETS :=
BENCH_TARGETS :=

.PHONY: all generate check-generated setup test test-codegen test-python demo demo-python bench bench-python

all: build-all

-include mk/*.mk

build-all: $(ALL_TARGETS)

## generate: rewrite generated/ from the spec
generate:
	$(PYTHON) -m codegen

## check-generated: fail if generated/ is not exactly what the spec gives
check-generated:
	$(PYTHON) -m codegen --check

## setup: install the system and Python packages that the tests and the demo need
setup:
	bash scripts/setup.sh

## test: every test of every target (the README's test command, and CI's)
test: check-generated test-codegen test-python $(TEST_TARGETS)

test-codegen:
	$(PYTEST) -q tests/codegen

test-python:
	$(PYTEST) -q tests/python

## demo: set up, then decode the bundled capture with every target
demo: setup demo-python $(DEMO_TARGETS)

demo-python:
	@echo "== Python: urwire decode --format text dissector/samples/primary_session.pcapng"
	@PYTHONPATH=generated/python $(PYTHON) -m urwire decode --format text dissector/samples/primary_session.pcapng | head -n 12

## bench: speed figures, each a ratio against a baseline measured in the same run
bench: bench-python $(BENCH_TARGETS)

bench-python:
	PYTHONPATH=generated/python $(PYTHON) tests/bench/bench_python.py
