# C target: generated/c/urwire.{h,c} (written by `make generate`), the urwire-decode CLI, its
# tests (gcc, clang, ASan/UBSan, differential against Python), the libFuzzer harness, the
# benchmark, a demo and installation.

CC ?= cc
CLANG ?= clang
C_STRICT := -std=c99 -Wall -Wextra -Werror -pedantic -Wconversion -Wshadow
C_OPT ?= -O2
C_LIB := generated/c/urwire.c generated/c/urwire.h
C_CLI := tools/urwire-decode/main.c tools/urwire-decode/json.c tools/urwire-decode/json.h
PREFIX ?= /usr/local
FUZZ_SECONDS ?= 60
FUZZ_CI_SECONDS ?= 60
BENCH_C_LEVELS ?= -O3 -O2 -Os

ALL_TARGETS += build/urwire-decode
TEST_TARGETS += test-c
BENCH_TARGETS += bench-c
DEMO_TARGETS += demo-c

PIN ?= 5.11
PINNED_C := build/pinned

.PHONY: test-c fuzz fuzz-c bench-c demo-c install install-c uninstall-c pinned-c

build/urwire-decode: $(C_LIB) $(C_CLI)
	@mkdir -p build
	$(CC) $(C_STRICT) $(C_OPT) -Igenerated/c -Itools/urwire-decode -o $@ \
		tools/urwire-decode/main.c tools/urwire-decode/json.c generated/c/urwire.c -lm

build/liburwire.a: $(C_LIB)
	@mkdir -p build/obj
	$(CC) $(C_STRICT) $(C_OPT) -c generated/c/urwire.c -o build/obj/urwire.o
	ar rcs $@ build/obj/urwire.o

## pinned-c: the C parser of one software version only, with no version branches (PIN=5.11):
## build/pinned/c/urwire.{h,c}, and build/pinned/urwire.o at -Os with its size
pinned-c:
	$(PYTHON) -m codegen --pin $(PIN) --target c --out $(PINNED_C)
	$(CC) $(C_STRICT) -Os -c $(PINNED_C)/c/urwire.c -o $(PINNED_C)/urwire.o
	@if command -v size >/dev/null; then size $(PINNED_C)/urwire.o; fi

## test-c: fuzz (bounded), then the C library and CLI under gcc, clang and the sanitizers: vectors,
## differential against Python (the fuzzer's corpus included), round trips, build checks
test-c: build/urwire-decode
	$(MAKE) --no-print-directory fuzz FUZZ_SECONDS=$(FUZZ_CI_SECONDS)
	$(PYTEST) -q tests/c

## fuzz: libFuzzer over the framer and every decoder, seeded with the vectors (FUZZ_SECONDS=60)
fuzz: fuzz-c
fuzz-c: $(C_LIB) tests/c/fuzz_urwire.c tools/urwire-decode/json.c
	@mkdir -p build/fuzz/corpus build/fuzz/crashes
	$(CLANG) -std=c99 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
		-Igenerated/c -Itools/urwire-decode -o build/fuzz/fuzz_urwire tests/c/fuzz_urwire.c \
		tools/urwire-decode/json.c generated/c/urwire.c -lm
	$(PYTHON) tests/c/seeds.py build/fuzz/seeds
	build/fuzz/fuzz_urwire -max_total_time=$(FUZZ_SECONDS) -print_final_stats=1 \
		-artifact_prefix=build/fuzz/crashes/ build/fuzz/corpus build/fuzz/seeds tests/c/regressions

## bench-c: robot-state decode throughput against memcpy of the same bytes, same run, with the
## library built at each of BENCH_C_LEVELS (ns per state, and each level against -O3)
## (BENCH_C_BASE=<git revision>: also the library that revision generated, level by level, in the
## same run, e.g. make bench-c BENCH_C_BASE=b8aabfa)
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

## demo-c: the C decoder on the bundled capture's robot->client stream (urwire-decode reads raw streams)
demo-c: build/urwire-decode
	@$(PYTHON) tests/c/seeds.py --capture dissector/samples/primary_session.pcapng build/primary_session.bin
	@echo "== C: build/urwire-decode build/primary_session.bin (the TCP payload of dissector/samples/primary_session.pcapng; first records, cut at 160 characters)"
	@build/urwire-decode build/primary_session.bin | cut -c1-160 | head -n 12; true

## install: copy urwire.h, liburwire.a and urwire-decode under PREFIX (DESTDIR honoured)
install: install-c
install-c: build/liburwire.a build/urwire-decode
	install -d $(DESTDIR)$(PREFIX)/include $(DESTDIR)$(PREFIX)/lib $(DESTDIR)$(PREFIX)/bin
	install -m 644 generated/c/urwire.h $(DESTDIR)$(PREFIX)/include/urwire.h
	install -m 644 build/liburwire.a $(DESTDIR)$(PREFIX)/lib/liburwire.a
	install -m 755 build/urwire-decode $(DESTDIR)$(PREFIX)/bin/urwire-decode

uninstall-c:
	rm -f $(DESTDIR)$(PREFIX)/include/urwire.h $(DESTDIR)$(PREFIX)/lib/liburwire.a \
		$(DESTDIR)$(PREFIX)/bin/urwire-decode
