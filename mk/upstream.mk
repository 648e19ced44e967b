# The dissectors built inside Wireshark's own source tree, as the upstream patch puts them there
# (docs/wireshark-upstream.md, "Built in Wireshark's tree"): outside `make test` and CI, since a
# Wireshark build takes an hour or more on two cores.
#
#   make upstream-build WIRESHARK_SRC=~/src/wireshark-4.6.9
#
# upstream-apply: writes the patch of `make upstream-patch` against WIRESHARK_SRC (build/upstream.patch)
#   and applies it there (once: a tree that has it already is left as it is);
# upstream-configure: configures tshark's build with Wireshark's own warning flags, as errors
#   (ENABLE_WERROR), in WIRESHARK_BUILD;
# upstream-build: builds tshark, editcap and capinfos, runs the test the patch adds to
#   test/suite_dissection.py (class TestDissectUniversalRobots) and tools/fuzz-test.sh over the cell
#   captures (dissector/samples/*.pcapng, FUZZ_PASSES passes each).

WIRESHARK_SRC ?=
WIRESHARK_BUILD ?= $(WIRESHARK_SRC)/build-urwire
UPSTREAM_PATCH ?= build/upstream.patch
FUZZ_PASSES ?= 100
UPSTREAM_CMAKE_FLAGS ?= -DBUILD_wireshark=OFF -DBUILD_logray=OFF -DBUILD_stratoshark=OFF -DENABLE_WERROR=ON
UPSTREAM_GENERATOR ?= $(if $(shell command -v ninja),-G Ninja,)
UPSTREAM_SAMPLES := $(abspath $(wildcard dissector/samples/*.pcapng))

.PHONY: upstream-apply upstream-configure upstream-build

## upstream-apply, upstream-configure, upstream-build: the patch into WIRESHARK_SRC, its build
## configured, then built and tested there (above; docs/wireshark-upstream.md)
upstream-apply:
	@[ -f "$(WIRESHARK_SRC)/epan/dissectors/CMakeLists.txt" ] || \
		{ echo "upstream-apply: set WIRESHARK_SRC to a Wireshark source tree" >&2; exit 2; }
	@if [ -f "$(WIRESHARK_SRC)/epan/dissectors/packet-ur-common.c" ]; then \
		echo "upstream-apply: $(WIRESHARK_SRC) has the dissectors already"; \
	else \
		$(PYTHON) scripts/upstream-patch.py $(UPSTREAM) --against $(WIRESHARK_SRC) --patch $(UPSTREAM_PATCH) >/dev/null && \
		cd $(WIRESHARK_SRC) && git apply --check $(abspath $(UPSTREAM_PATCH)) && git apply $(abspath $(UPSTREAM_PATCH)) && \
		echo "upstream-apply: $(abspath $(UPSTREAM_PATCH)) applied to $(WIRESHARK_SRC)"; \
	fi

upstream-configure: upstream-apply
	$(CMAKE) -S $(WIRESHARK_SRC) -B $(WIRESHARK_BUILD) $(UPSTREAM_GENERATOR) $(UPSTREAM_CMAKE_FLAGS)

upstream-build: upstream-configure
	$(CMAKE) --build $(WIRESHARK_BUILD) --target tshark editcap capinfos
	cd $(WIRESHARK_SRC) && $(PYTHON) -m pytest --program-path $(abspath $(WIRESHARK_BUILD))/run \
		test/suite_dissection.py -k TestDissectUniversalRobots
	@mkdir -p build/upstream-fuzz
	cd $(WIRESHARK_SRC) && tools/fuzz-test.sh -b $(abspath $(WIRESHARK_BUILD))/run -d $(abspath build/upstream-fuzz) \
		-p $(FUZZ_PASSES) $(UPSTREAM_SAMPLES)
