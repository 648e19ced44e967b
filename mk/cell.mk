# The whole cell: the demo of the bundled capture of every interface (dissector/samples/cell_session.pcapng),
# shown after the primary interface's demo, and RTDE's benchmark (the real-time interface's is in realtime.mk).

DEMO_CELL_TARGETS += demo-cell
CELL_SAMPLE := dissector/samples/cell_session.pcapng
CELL_PROTOCOLS := ur || ur_realtime || rtde || ur_dashboard || ur_reverse || ur_script_sender || ur_trajectory \
	|| ur_script_command || ur_interpreter || robotiq_gripper

.PHONY: demo-cell

## demo-cell: the cell capture decoded by Python (every conversation), C (the real-time stream; the
## C command reads raw streams) and tshark with every dissector of generated/lua/ loaded
demo-cell: build/urwire-decode
	@echo "== Python: urwire decode --format text $(CELL_SAMPLE) (every interface of a cell; cut at 160 characters)"
	@PYTHONPATH=python:generated/python $(PYTHON) -m urwire decode --format text $(CELL_SAMPLE) | cut -c1-160
	@$(PYTHON) tests/tools/port_stream.py $(CELL_SAMPLE) 30003 build/cell_realtime.bin
	@echo "== C: build/urwire-decode --protocol ur_realtime build/cell_realtime.bin (30003's stream, lines cut)"
	@build/urwire-decode --protocol ur_realtime build/cell_realtime.bin | cut -c1-160
	@echo "== Wireshark (tshark + every generated/lua/*.lua): $(CELL_SAMPLE), protocol and Info columns"
	@$(TSHARK) -r $(CELL_SAMPLE) $(LUA_PLUGINS:%=-X lua_script:%) -Y '$(CELL_PROTOCOLS)' \
		-T fields -e frame.number -e _ws.col.Protocol -e _ws.col.Info 2>/dev/null
	@echo "== filter: rtde.actual_q && rtde.robot_mode (tree: the recipe's variables by name, the frame that set it up)"
	@$(TSHARK) -r $(CELL_SAMPLE) $(LUA_PLUGINS:%=-X lua_script:%) -O rtde -Y 'rtde.actual_q && rtde.robot_mode' \
		2>/dev/null | sed -n '/^Universal Robots Real-Time/,$$p'
	@echo "== the RTDE setup's expert warnings"
	@$(TSHARK) -r $(CELL_SAMPLE) $(LUA_PLUGINS:%=-X lua_script:%) -q -z expert,warn 2>/dev/null | sed '/^$$/d'

BENCH_TARGETS += bench-rtde
BENCH_RTDE_PACKAGES ?= 30000
BENCH_RTDE_LARGE ?= 1000000

.PHONY: bench-rtde

build/bench_rtde: tests/bench/bench_rtde.c generated/c/rtde.c generated/c/rtde.h
	@mkdir -p build
	$(CC) -std=c99 -O2 -Wall -Wextra -Werror -pedantic -Wconversion -Igenerated/c -o $@ tests/bench/bench_rtde.c \
		generated/c/rtde.c

# One package, L1-hot, at each level: urwire's readers against the hand-written one and, when a checkout of UR's
# own library is found (URCL_SOURCE, else ../Universal_Robots_Client_Library: tests/tools/urcl.py), against
# URCL built from it at the same level. bench-rtde asks urcl.py, which says why when there is none.
BENCH_RTDE_LEVELS := O2 O3 Os
BENCH_RTDE_HOT_PACKAGES ?= 200000
CXX ?= c++
URCL_RTDE_BENCH_SOURCES = $(filter-out %/rtde_client.cpp %/rtde_writer.cpp,$(wildcard $(URCL_SOURCE)/src/rtde/*.cpp)) \
	$(addprefix $(URCL_SOURCE)/src/,log.cpp default_log_handler.cpp helpers.cpp ur/version_information.cpp)
BENCH_RTDE_HOT := $(if $(URCL_SOURCE),build/bench_rtde_hot_urcl,build/bench_rtde_hot)

build/urcl/include/ur_client_library/compile_options.h: tests/tools/urcl.py
	@mkdir -p $(@D)
	$(PYTHON) -c 'import sys; from tests.tools.urcl import COMPILE_OPTIONS; sys.stdout.write(COMPILE_OPTIONS)' > $@

build/bench_rtde_hot-%: tests/bench/bench_rtde_hot.c generated/c/rtde.c generated/c/rtde.h
	@mkdir -p build
	$(CC) -std=c99 -$* -Wall -Wextra -Werror -pedantic -Wconversion -Igenerated/c -o $@ tests/bench/bench_rtde_hot.c \
		generated/c/rtde.c

build/bench_rtde_hot_urcl-%: tests/bench/bench_rtde_hot.c tests/bench/bench_rtde_urcl.cpp generated/c/rtde.c \
		generated/c/rtde.h build/urcl/include/ur_client_library/compile_options.h
	$(CC) -std=c99 -$* -Wall -Wextra -Werror -pedantic -Wconversion -Igenerated/c -DBENCH_URCL -c \
		-o $@-hot.o tests/bench/bench_rtde_hot.c
	$(CC) -std=c99 -$* -Igenerated/c -c -o $@-rtde.o generated/c/rtde.c
	$(CXX) -std=c++17 -$* -I$(URCL_SOURCE)/include -Ibuild/urcl/include -I$(URCL_SOURCE)/3rdparty -o $@ \
		tests/bench/bench_rtde_urcl.cpp $(URCL_RTDE_BENCH_SOURCES) $@-hot.o $@-rtde.o

## bench-rtde: RTDE data packages per second by recipe (a driver's 9-variable recipe at 500 Hz) in
## Python (against struct alone) and C (against memcpy, and Python), at BENCH_RTDE_PACKAGES and
## BENCH_RTDE_LARGE packages (the cost per package, large against small), Python reading one 12-variable
## package hot (against a hand-written struct reader), and tshark with rtde.lua against
## --disable-protocol rtde on BENCH_RTDE_PACKAGES packages, Python and rtde.lua also against the tree
## before their recipes were planned once (bench_rtde.py's BASE); then one 12-variable package
## L1-hot at -O2, -O3 and -Os, read by index and by name (each type's inline reader), by rtde_data_value, as a
## list and by rtde_data_find, against a hand-written reader and URCL (built from URCL_SOURCE, else from
## ../Universal_Robots_Client_Library when it is there; the output says when URCL is not compared, and why)
bench-rtde: build/bench_rtde
	$(PYTHON) tests/bench/bench_rtde.py --packages $(BENCH_RTDE_PACKAGES) --large $(BENCH_RTDE_LARGE)
	@$(MAKE) --no-print-directory bench-rtde-hot URCL_SOURCE="$$($(PYTHON) tests/tools/urcl.py)"

.PHONY: bench-rtde-hot
bench-rtde-hot: $(BENCH_RTDE_LEVELS:%=$(BENCH_RTDE_HOT)-%)
	@for level in $(BENCH_RTDE_LEVELS); do \
		echo "== RTDE in C, one 284-byte package L1-hot, -$$level ($(BENCH_RTDE_HOT_PACKAGES) packages, best of 5 turns)"; \
		$(BENCH_RTDE_HOT)-$$level $(BENCH_RTDE_HOT_PACKAGES) 5 || exit 1; \
	done
