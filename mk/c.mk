# C target: generated/c/*.{h,c} (written by `make generate`: urwire.{h,c} for the primary interface,
# one <interface>.{h,c} pair for each other interface of the cell), the urwire-decode CLI and the
# C runtime it compiles, its
# tests (gcc, clang, ASan/UBSan, differential against Python), the benchmark, a demo and
# installation. Its fuzzers are in mk/fuzz.mk.

CC ?= cc
CLANG ?= clang
C_STRICT := -std=c99 -Wall -Wextra -Werror -pedantic -Wconversion -Wshadow
C_OPT ?= -O2
C_SOURCES := $(wildcard generated/c/*.c)
C_LIB := $(C_SOURCES) $(wildcard generated/c/*.h)
# The C runtime compiled beside generated/c, not joined into it: runtime/c/json (canonical JSON,
# float digits, the record loop; urwire._ccore compiles it too) and the stream framing of RTDE
# (runtime/c/typed_messages/rtde_stream.c) and of the real-time interface
# (runtime/c/sized_packets/ur_realtime_stream.c). The command itself is tools/urwire-decode.
C_STREAMS := runtime/c/typed_messages/rtde_stream runtime/c/sized_packets/ur_realtime_stream
C_RUNTIME := $(wildcard runtime/c/json/*.c runtime/c/json/*.h) $(C_STREAMS:%=%.c) $(C_STREAMS:%=%.h)
C_INCLUDES := -Igenerated/c -Iruntime/c/json -Iruntime/c/typed_messages -Iruntime/c/sized_packets \
	-Itools/urwire-decode -Iruntime/c/capture
C_CLI := $(wildcard tools/urwire-decode/*.c tools/urwire-decode/*.h) $(C_RUNTIME)
# The command compiles, from what every kind's C runtime shares, the UTF-8 decoder runtime/c/json
# writes text with (the text-line interfaces join it into their generated C instead).
C_CLI += runtime/c/common/utf8.c runtime/c/common/utf8.h runtime/c/common/macros.h
C_CLI += runtime/c/common/held.c runtime/c/common/held.h
# The capture reader (.pcap, .pcapng, TCP reassembly), which urwire._ccore compiles too.
C_CLI += $(wildcard runtime/c/capture/*.c runtime/c/capture/*.h)
PREFIX ?= /usr/local
BENCH_C_LEVELS ?= -O3 -O2 -Os
BENCH_C_BASE ?= b8aabfa

ALL_TARGETS += build/urwire-decode
TEST_BUILDS += build/urwire-decode
BENCH_TARGETS += bench-c bench-c-cli
DEMO_TARGETS += demo-c

PIN ?= 5.11
PINNED_C := build/pinned
SUBSET_C := build/subset

.PHONY: test-c bench-c bench-c-cli demo-c install install-c uninstall-c pinned-c subset-c

build/urwire-decode: $(C_LIB) $(C_CLI)
	@mkdir -p build
	$(CC) $(C_STRICT) $(C_OPT) $(C_INCLUDES) -o $@ $(filter %.c,$(C_CLI)) $(C_SOURCES) -lm

build/liburwire.a: $(C_LIB)
	@mkdir -p build/obj
	rm -f $@
	for src in $(C_SOURCES); do \
		$(CC) $(C_STRICT) $(C_OPT) -c $$src -o build/obj/$$(basename $$src .c).o || exit 1; done
	ar rcs $@ $(patsubst generated/c/%.c,build/obj/%.o,$(C_SOURCES))

## pinned-c: the C parser of one software version only, with no version branches (PIN=5.11):
## build/pinned/c/urwire.{h,c}, and build/pinned/urwire.o at -Os with its size
pinned-c:
	$(PYTHON) -m codegen --pin $(PIN) --target c --out $(PINNED_C)
	$(CC) $(C_STRICT) -Os -c $(PINNED_C)/c/urwire.c -o $(PINNED_C)/urwire.o
	@if command -v size >/dev/null; then size $(PINNED_C)/urwire.o; fi

## subset-c: the C parser of some parts only, the rest framed and kept raw (docs/generator.md#subsets):
## SELECT=ur:robot_state.joint_data,robot_state.tool_data or a selection file, and PIN=5.11 to pin it
## too; build/subset/c/*.{h,c}, and build/subset/*.o at -Os with their sizes
subset-c:
	@test -n "$(SELECT)" || { echo "subset-c: give SELECT=interface:name,name or a selection file" >&2; exit 2; }
	rm -rf $(SUBSET_C)
	$(PYTHON) -m codegen --select $(SELECT) $(if $(filter command line environment,$(origin PIN)),--pin $(PIN)) \
		--target c --out $(SUBSET_C)
	for src in $(SUBSET_C)/c/*.c; do \
		$(CC) $(C_STRICT) -Os -c $$src -o $(SUBSET_C)/$$(basename $$src .c).o || exit 1; done
	@if command -v size >/dev/null; then size $(SUBSET_C)/*.o; fi

## test-c: the C library and CLI under gcc, clang and the sanitizers: vectors, differential
## against Python, the fuzzers' kept corpora through their harnesses, round trips, build checks
test-c: build/urwire-decode
	$(PYTEST) -q tests/c

## bench-c: robot-state decode throughput against memcpy of the same bytes, same run, with the
## library built at each of BENCH_C_LEVELS (ns per state, and each level against -O3)
## and the library that BENCH_C_BASE generated, level by level, in the same run: by default b8aabfa,
## the last before the spec held every controller generation, so that `make bench` shows what they
## cost the e-Series (BENCH_C_BASE= leaves it out)
bench-c: $(C_LIB) tests/bench/bench_c.c tests/bench/bench_c.py
	@mkdir -p build
	for opt in $(BENCH_C_LEVELS); do \
		$(CC) -std=c99 $$opt -Igenerated/c -o build/bench_c$$opt tests/bench/bench_c.c generated/c/urwire.c || exit 1; \
	done
ifneq ($(BENCH_C_BASE),)
	@mkdir -p build/bench-base
	git show $(BENCH_C_BASE):generated/c/urwire.h > build/bench-base/urwire.h
	git show $(BENCH_C_BASE):generated/c/urwire.c > build/bench-base/urwire.c
	# a library older than urwire_framer_learn is benchmarked without it
	learn=$$(grep -q urwire_framer_learn build/bench-base/urwire.h || echo -DBENCH_C_WITHOUT_LEARN); \
	for opt in $(BENCH_C_LEVELS); do \
		$(CC) -std=c99 $$opt $$learn -Ibuild/bench-base -o build/bench_c-base$$opt tests/bench/bench_c.c \
			build/bench-base/urwire.c || exit 1; \
	done
endif
	$(PYTHON) tests/bench/bench_c.py $(BENCH_C_LEVELS:%=build/bench_c%) \
		$(if $(BENCH_C_BASE),$(BENCH_C_LEVELS:%=build/bench_c-base%))

## bench-c-cli: build/urwire-decode against `python3 -m urwire decode` on the same raw stream of
## real robot states to /dev/null, in one run: MB/s of CPU time each and the ratio
## (BENCH_CLI_MB: the stream sizes in MB)
BENCH_CLI_MB ?= 10 100
bench-c-cli: build/urwire-decode tests/bench/bench_cli.py
	$(PYTHON) tests/bench/bench_cli.py $(BENCH_CLI_MB)

## demo-c: the C decoder on the bundled capture's robot->client stream (urwire-decode reads raw streams)
demo-c: build/urwire-decode
	@$(PYTHON) tests/c/seeds.py --capture dissector/samples/primary_session.pcapng build/primary_session.bin
	@echo "== C: build/urwire-decode build/primary_session.bin (the TCP payload of dissector/samples/primary_session.pcapng; first records, cut at 160 characters)"
	@build/urwire-decode build/primary_session.bin | cut -c1-160 | head -n 12; true

## install: copy the headers, liburwire.a and urwire-decode under PREFIX (DESTDIR honoured)
install: install-c
install-c: build/liburwire.a build/urwire-decode
	install -d $(DESTDIR)$(PREFIX)/include $(DESTDIR)$(PREFIX)/lib $(DESTDIR)$(PREFIX)/bin
	install -m 644 $(wildcard generated/c/*.h) $(DESTDIR)$(PREFIX)/include/
	install -m 644 build/liburwire.a $(DESTDIR)$(PREFIX)/lib/liburwire.a
	install -m 755 build/urwire-decode $(DESTDIR)$(PREFIX)/bin/urwire-decode

uninstall-c:
	rm -f $(patsubst generated/c/%,$(DESTDIR)$(PREFIX)/include/%,$(wildcard generated/c/*.h)) \
		$(DESTDIR)$(PREFIX)/lib/liburwire.a \
		$(DESTDIR)$(PREFIX)/bin/urwire-decode
