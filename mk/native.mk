# The native Wireshark plugin: every generated/epan/packet-*.c built into one epan plugin,
# urwire.so, with CMake and find_package(Wireshark) against the installed Wireshark
# (dissector/native/CMakeLists.txt; wireshark-dev, cmake and a C compiler, from scripts/setup.sh).

NATIVE_BUILD ?= build/native
# the folder of the packet-*.c to build (the tests point it at a fixture)
URWIRE_EPAN_DIR ?= $(CURDIR)/generated/epan
NATIVE_CMAKE_FLAGS ?=
CMAKE ?= cmake
# install-dissector: auto (the native plugin where it builds, else Lua), yes (native or fail), no (Lua)
NATIVE ?= auto

BENCH_TARGETS += bench-wireshark

.PHONY: native-dissector install-dissector uninstall-dissector bench-wireshark

## native-dissector: build the native plugin under build/native and print where it is
native-dissector:
	@command -v $(CMAKE) >/dev/null || { echo "native-dissector: cmake is not installed (scripts/setup.sh)" >&2; exit 2; }
	@mkdir -p $(NATIVE_BUILD)
	$(CMAKE) -S dissector/native -B $(NATIVE_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo \
		-DURWIRE_EPAN_DIR=$(abspath $(URWIRE_EPAN_DIR)) $(NATIVE_CMAKE_FLAGS) >$(NATIVE_BUILD)/configure.log 2>&1 \
		|| { cat $(NATIVE_BUILD)/configure.log >&2; exit 1; }
	$(CMAKE) --build $(NATIVE_BUILD)
	@echo "native-dissector: $$(find $(NATIVE_BUILD)/plugins -name urwire.so)"

## install-dissector: the native plugin into tshark's personal plugins folder (`tshark -G folders`)
## where it builds, else the Lua dissectors into the personal Lua folder; never both, as they
## register the same protocols (NATIVE=no installs Lua, NATIVE=yes fails rather than fall back)
install-dissector:
	@NATIVE=$(NATIVE) TSHARK=$(TSHARK) MAKE="$(MAKE)" LUA_PLUGINS="$(LUA_PLUGINS)" \
		bash scripts/install-dissector.sh install

## uninstall-dissector: remove both the native plugin and the Lua dissectors
uninstall-dissector:
	@TSHARK=$(TSHARK) LUA_PLUGINS="$(LUA_PLUGINS)" bash scripts/install-dissector.sh uninstall

## bench-wireshark: tshark with the native plugin and with the Lua dissector of each interface, each
## against --disable-protocol on the same file, at 30k and 100k messages, beside their goals
## (BENCH_SMALL=1: 2k and 6k, a quick look; BENCH_WIRESHARK_ARGS="--interfaces ur rtde")
BENCH_WIRESHARK_ARGS ?=
bench-wireshark:
	$(PYTHON) tests/bench/bench_wireshark.py $(BENCH_WIRESHARK_ARGS)

## fuzz-wireshark: Wireshark's fuzz-test.sh approach, per interface: editcap -E mutations of its golden
## vectors (whole and in 1-7 byte segments) and of its conversations in the sample captures, each read
## by tshark -nVx with the native plugin under ASan+UBSan and, separately, with the Lua dissectors;
## a table counts malformed packets and failures per interface; a failing capture is kept under
## build/fuzz-wireshark/failures/ (tests/fuzz/fuzz_wireshark.py). Four groups of interfaces, FUZZ_SECONDS
## of mutations each after its unmutated pass: fuzz-wireshark-primary-realtime, -rtde,
## -dashboard-sender, -driver-sockets (one interface: python3 tests/fuzz/fuzz_wireshark.py --seconds 60 rtde)
WIRESHARK_GROUPS := primary-realtime rtde dashboard-sender driver-sockets
WIRESHARK_primary-realtime := ur ur_realtime
WIRESHARK_rtde := rtde
WIRESHARK_dashboard-sender := ur_dashboard ur_script_sender
WIRESHARK_driver-sockets := ur_reverse ur_trajectory ur_script_command
.PHONY: fuzz-wireshark $(WIRESHARK_GROUPS:%=fuzz-wireshark-%)
fuzz: fuzz-wireshark
fuzz-wireshark: $(WIRESHARK_GROUPS:%=fuzz-wireshark-%)
$(WIRESHARK_GROUPS:%=fuzz-wireshark-%): fuzz-wireshark-%:
	$(PYTHON) tests/fuzz/fuzz_wireshark.py --seconds $(FUZZ_SECONDS) $(WIRESHARK_$*)

## upstream-patch: lay out under build/upstream/ exactly the files a Wireshark patch would carry
## (epan/dissectors/packet-*.c, rendered as Wireshark's copy that reads no command line, and the
## generator under tools/; docs/wireshark-upstream.md), then build an out-of-tree plugin from
## exactly those dissector files (URWIRE_EPAN_DIR given: its packet-*.c instead of the rendered ones)
UPSTREAM ?= build/upstream
.PHONY: upstream-patch check-upstream
upstream-patch:
	$(PYTHON) scripts/upstream-patch.py $(UPSTREAM) $(if $(filter-out file,$(origin URWIRE_EPAN_DIR)),$(URWIRE_EPAN_DIR))
	$(MAKE) --no-print-directory native-dissector URWIRE_EPAN_DIR=$(abspath $(UPSTREAM))/epan/dissectors \
		NATIVE_BUILD=$(UPSTREAM)-plugin

## check-upstream: Wireshark's own source checks (checkAPIs.pl, checkhf.pl,
## check_typed_item_calls.py ...) from a Wireshark checkout, which Debian does not package, on
## the copy of the dissectors a Wireshark patch carries (rendered under build/upstream-epan), or on
## URWIRE_EPAN_DIR's when it is given: make check-upstream WIRESHARK_SOURCE=~/src/wireshark
UPSTREAM_EPAN := build/upstream-epan
CHECKED_EPAN = $(if $(filter-out file,$(origin URWIRE_EPAN_DIR)),$(URWIRE_EPAN_DIR),$(UPSTREAM_EPAN)/epan)
check-upstream:
	@[ -n "$(WIRESHARK_SOURCE)" ] || { echo "check-upstream: set WIRESHARK_SOURCE to a Wireshark checkout" >&2; exit 2; }
	@$(if $(filter-out file,$(origin URWIRE_EPAN_DIR)),:,$(PYTHON) -m codegen --target epan --upstream --out $(UPSTREAM_EPAN))
	@bash scripts/check-upstream.sh $(WIRESHARK_SOURCE) $(CHECKED_EPAN)/packet-*.[ch]
