# The optional C extension urwire._ccore (ext/ccore/module.c over generated/c/urwire.c and the C
# runtime's JSON writer, runtime/c/json): built in place beside python/urwire so that the
# tree's Python (PYTHONPATH=python:generated/python) decodes through it; setup.py builds the same
# module for `pip install .` and `pip wheel .`.

PYTHON_EXT_SOURCES := setup.py ext/ccore/sources.txt $(shell cat ext/ccore/sources.txt) \
	$(wildcard ext/ccore/*.h) generated/c/urwire.h $(wildcard runtime/c/json/*.h) \
	runtime/c/common/utf8.h runtime/c/common/macros.h $(wildcard runtime/c/capture/*.h)
PYTHON_EXT_STAMP := build/python-ext.stamp

ALL_TARGETS += python-ext
TEST_BUILDS += python-ext

.PHONY: python-ext

## python-ext: build urwire._ccore in place (python/urwire/_ccore*.so); URWIRE_BACKEND=python ignores it
python-ext: $(PYTHON_EXT_STAMP)

$(PYTHON_EXT_STAMP): $(PYTHON_EXT_SOURCES)
	@mkdir -p build
	$(PYTHON) setup.py --quiet build_ext --inplace --build-temp build/python-ext --build-lib build/python-ext/lib
	@# setup.py leaves the extension out rather than fail (pip install must work without a compiler);
	@# here its absence is an error.
	PYTHONPATH=python:generated/python URWIRE_BACKEND=c $(PYTHON) -c "import urwire"
	@touch $@

## test-python-backend: the tests of what the C backend changes (urwire decode of a raw primary
## stream; the dataset's primary columns; the records of decode_message, the Framer and
## decode_stream: vectors, round trips, any split, every generation; real-time packets and RTDE
## data packages) under pure Python (URWIRE_BACKEND=python); `make test-deep` runs them so (and
## test-python-range runs every test without the extension), `make test` under the default
## backend, the C one, which it builds first
PYTHON_BACKEND_TESTS := tests/python/test_cli.py tests/python/test_hostile_bytes.py tests/python/test_c_backend.py \
	tests/python/test_vectors.py tests/python/test_roundtrip.py tests/python/test_streaming.py \
	tests/python/test_generations.py tests/python/test_message_kinds.py tests/python/test_undocumented.py \
	tests/python/test_realtime.py tests/python/test_rtde.py tests/python/test_rtde_vectors.py \
	tests/python/test_c_backend_flat.py \
	tests/python/test_dataset.py
DEEP_TESTS += test-python-backend
.PHONY: test-python-backend
test-python-backend: python-ext
	URWIRE_BACKEND=python $(PYTEST) -q $(PYTHON_BACKEND_TESTS)
