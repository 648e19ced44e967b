# A new software version, the maintainer's way (docs/adding-a-firmware.md): start its golden
# vectors from the newest of its series, then run every golden vector through every target.

.PHONY: new-vector test-vectors

## new-vector: start VERSION's robot-state vectors from the newest of its series, values marked
## `TODO: check` for a person to lay out (make new-vector VERSION=5.27 [VECTOR=tests/golden/...])
new-vector:
	@test -n "$(VERSION)" || { echo "usage: make new-vector VERSION=5.27 [VECTOR=tests/golden/<file>]" >&2; exit 2; }
	$(PYTHON) scripts/new_vector.py $(VERSION) $(if $(VECTOR),--from $(VECTOR))

# The golden vectors of the primary interface, RTDE and the dashboard, by target.
VECTOR_TESTS_PYTHON := tests/python/test_vectors.py tests/python/test_rtde_vectors.py tests/python/test_dashboard.py
VECTOR_TESTS_C := tests/c/test_c_vectors.py tests/c/test_rtde_c.py::test_c_prints_what_python_prints \
	tests/c/test_c_dashboard.py::test_golden_vectors
VECTOR_TESTS_TSHARK := tests/lua/test_vectors.py tests/lua/test_rtde_dissector.py::test_dissector_shows_every_vector \
	tests/lua/test_dashboard.py::test_golden_vectors tests/lua/test_dashboard.py::test_golden_vectors_in_one_byte_segments \
	tests/native/test_ur_native.py::test_golden_vectors_whole_and_in_1_to_7_byte_segments \
	tests/native/test_rtde_native.py::test_golden_exchanges_show_as_in_lua \
	tests/native/test_lines_native.py::test_every_golden_vector_whole_and_in_1_to_7_byte_segments
VECTOR_TESTS := $(VECTOR_TESTS_PYTHON) $(VECTOR_TESTS_C) $(VECTOR_TESTS_TSHARK)

## test-vectors: generated/ current, then every golden vector of the primary interface, RTDE and
## the dashboard through Python, C (gcc, clang, ASan/UBSan) and tshark (the Lua and the native
## dissectors): about a minute, where `make test` takes seven
test-vectors: check-generated
	$(PYTEST) -q -p no:cacheprovider $(VECTOR_TESTS)
