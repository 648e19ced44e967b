# Fuzzing: four coverage-guided harnesses, each seeded with the vectors, messages at the 1 MiB
# length limit (tests/c/seeds.py) and its kept corpus (tests/fuzz/corpus/<harness>/):
#   urwire  tests/c/fuzz_urwire.c          the C framer and every decoder, encoder and visitor
#   json    tests/c/fuzz_json.c            urwire-decode: version hint, record loop, JSON writer
#   python  tests/python/fuzz_decoder.py   the Python decoder (atheris), and urwire-decode
#                                          against it through one driver process
#   ur_realtime  tests/c/fuzz_ur_realtime.c  the real-time decoder, its stream framing and its JSON
#                                          writer (its kept corpus only)
# `make test` does not fuzz: it builds each harness and runs it once over its kept corpus and
# seeds (tests/c/test_c_fuzz_corpus.py, tests/python/test_fuzz_corpus.py), and replays the kept
# corpora through C against Python and through tshark (tests/lua/test_fuzz_corpus.py).
# The cell's other interfaces: their C harnesses and the differential fuzzer of Python against C
# are in mk/cell_fuzz.mk (fuzz-diff), tshark's fuzzing of every interface in mk/native.mk
# (fuzz-wireshark); tests/fuzz/README.md lists them all.

FUZZ_SECONDS ?= 60
FUZZ_LONG_SECONDS ?= 3600
FUZZ_CORPUS := tests/fuzz/corpus
# Inputs up to two messages at the runtime's length limit, plus its framer's slack and the
# control byte: lengths at, just above and just below the limit get fuzzed too. Long inputs run
# less often, as they take longer (-entropic_scale_per_exec_time).
URWIRE_MAX_MESSAGE := $(shell sed -n 's/^\#define URWIRE_MAX_MESSAGE_LENGTH \([0-9]*\)u.*/\1/p' generated/c/urwire.h)
FUZZ_MAX_LEN := $(shell echo $$((2 * $(URWIRE_MAX_MESSAGE) + 4096 + 1)))
FUZZ_FLAGS = -max_len=$(FUZZ_MAX_LEN) -entropic_scale_per_exec_time=1 -max_total_time=$(FUZZ_SECONDS) \
	-print_final_stats=1
FUZZ_CC := $(CLANG) -std=c99 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
	$(C_INCLUDES)
CLI_LIB := $(filter-out %/main.c,$(filter %.c,$(C_CLI)))

.PHONY: fuzz fuzz-c fuzz-json fuzz-python fuzz-ur-realtime fuzz-rtde fuzz-capture fuzz-long fuzz-corpus

## fuzz: every fuzzer for FUZZ_SECONDS (60) each; crashes land in build/fuzz/crashes/<harness>/
fuzz: fuzz-c fuzz-json fuzz-python fuzz-ur-realtime fuzz-rtde fuzz-capture

## fuzz-long: every fuzzer for FUZZ_LONG_SECONDS (an hour) each
fuzz-long:
	$(MAKE) --no-print-directory fuzz FUZZ_SECONDS=$(FUZZ_LONG_SECONDS)

build/fuzz/fuzz_urwire: tests/c/fuzz_urwire.c $(C_LIB) $(C_CLI)
	@mkdir -p build/fuzz
	$(FUZZ_CC) -o $@ tests/c/fuzz_urwire.c $(CLI_LIB) $(C_SOURCES) -lm

build/fuzz/fuzz_json: tests/c/fuzz_json.c $(C_LIB) $(C_CLI)
	@mkdir -p build/fuzz
	$(FUZZ_CC) -o $@ tests/c/fuzz_json.c $(CLI_LIB) $(C_SOURCES) -lm

# The Python fuzzer's peer: the test driver answering for urwire-decode, input after input.
build/fuzz/driver: tests/c/driver.c tests/c/state_members.py $(C_LIB) $(C_CLI)
	@mkdir -p build/fuzz
	$(PYTHON) tests/c/state_members.py generated/c/urwire.h build/fuzz
	$(CC) $(C_STRICT) $(C_OPT) $(C_INCLUDES) -Ibuild/fuzz -o $@ tests/c/driver.c $(CLI_LIB) \
		$(C_SOURCES) -lm

# $(call fuzz_run,HARNESS,COMMAND,MORE SEED FOLDERS)
define fuzz_run
	@rm -rf build/fuzz/seeds/$(1) && mkdir -p build/fuzz/corpus/$(1) build/fuzz/crashes/$(1)
	$(PYTHON) tests/c/seeds.py --harness $(1) build/fuzz/seeds/$(1)
	$(2) $(FUZZ_FLAGS) -artifact_prefix=build/fuzz/crashes/$(1)/ build/fuzz/corpus/$(1) \
		build/fuzz/seeds/$(1) $(FUZZ_CORPUS)/$(1) $(3)
endef

## fuzz-c: the C framer and decoders (tests/c/fuzz_urwire.c)
fuzz-c: build/fuzz/fuzz_urwire
	$(call fuzz_run,urwire,build/fuzz/fuzz_urwire -timeout=25,tests/c/regressions)

## fuzz-json: urwire-decode's version hint, record loop and JSON writer (tests/c/fuzz_json.c)
fuzz-json: build/fuzz/fuzz_json
	$(call fuzz_run,json,build/fuzz/fuzz_json -timeout=25)

## fuzz-ur-realtime: the real-time decoder, its stream framing and its JSON writer
## (tests/c/fuzz_ur_realtime.c); seeded with its kept corpus only (tests/fuzz/corpus/ur_realtime/,
## the golden vectors with a control byte)
build/fuzz/fuzz_ur_realtime: tests/c/fuzz_ur_realtime.c $(C_LIB) $(C_CLI)
	@mkdir -p build/fuzz
	$(FUZZ_CC) -o $@ tests/c/fuzz_ur_realtime.c $(CLI_LIB) $(C_SOURCES) -lm

fuzz-ur-realtime: build/fuzz/fuzz_ur_realtime
	@mkdir -p build/fuzz/corpus/ur_realtime build/fuzz/crashes/ur_realtime
	build/fuzz/fuzz_ur_realtime -max_len=30000 -max_total_time=$(FUZZ_SECONDS) -print_final_stats=1 \
		-artifact_prefix=build/fuzz/crashes/ur_realtime/ build/fuzz/corpus/ur_realtime $(FUZZ_CORPUS)/ur_realtime

## fuzz-rtde: RTDE conversations, both directions with their recipes, and the JSON writer
## (tests/c/fuzz_rtde.c); seeded with its kept corpus (tests/fuzz/corpus/rtde/)
build/fuzz/fuzz_rtde: tests/c/fuzz_rtde.c $(C_LIB) $(C_CLI)
	@mkdir -p build/fuzz
	$(FUZZ_CC) -o $@ tests/c/fuzz_rtde.c $(CLI_LIB) $(C_SOURCES) -lm

fuzz-rtde: build/fuzz/fuzz_rtde
	@mkdir -p build/fuzz/corpus/rtde build/fuzz/crashes/rtde
	build/fuzz/fuzz_rtde -max_len=30000 -max_total_time=$(FUZZ_SECONDS) -print_final_stats=1 \
		-artifact_prefix=build/fuzz/crashes/rtde/ build/fuzz/corpus/rtde $(FUZZ_CORPUS)/rtde

## fuzz-capture: the C capture reader (runtime/c/capture: pcap, pcapng, the link, IP and TCP
## layers, reassembly), read whole and in chunks (tests/c/fuzz_capture.c); seeded with every
## capture under tests/ and dissector/
CAPTURE_C := $(wildcard runtime/c/capture/*.c runtime/c/capture/*.h)
build/fuzz/fuzz_capture: tests/c/fuzz_capture.c $(CAPTURE_C)
	@mkdir -p build/fuzz
	$(FUZZ_CC) -Iruntime/c/capture -o $@ tests/c/fuzz_capture.c $(filter %.c,$(CAPTURE_C))

fuzz-capture: build/fuzz/fuzz_capture
	@rm -rf build/fuzz/seeds/capture && mkdir -p build/fuzz/seeds/capture build/fuzz/corpus/capture \
		build/fuzz/crashes/capture
	find tests dissector -name '*.pcap' -o -name '*.pcapng' | xargs -I{} cp {} build/fuzz/seeds/capture/
	build/fuzz/fuzz_capture -max_len=65536 -max_total_time=$(FUZZ_SECONDS) -print_final_stats=1 \
		-artifact_prefix=build/fuzz/crashes/capture/ build/fuzz/corpus/capture build/fuzz/seeds/capture

## fuzz-python: the Python decoder, and urwire-decode against it (tests/python/fuzz_decoder.py)
fuzz-python: build/fuzz/driver
	$(call fuzz_run,python,$(PYTHON) tests/python/fuzz_decoder.py --peer=build/fuzz/driver -timeout=60)

## fuzz-corpus: merge what the fuzzers found (build/fuzz/corpus/) into the kept corpora, minimized
## with -merge=1: the inputs that add coverage beyond the seeds, none above 64 KiB
fuzz-corpus: build/fuzz/fuzz_urwire build/fuzz/fuzz_json build/fuzz/driver
	$(PYTHON) tests/fuzz/keep.py urwire build/fuzz/fuzz_urwire -max_len=$(FUZZ_MAX_LEN)
	$(PYTHON) tests/fuzz/keep.py json build/fuzz/fuzz_json -max_len=$(FUZZ_MAX_LEN)
	$(PYTHON) tests/fuzz/keep.py python $(PYTHON) tests/python/fuzz_decoder.py --peer=build/fuzz/driver \
		-max_len=$(FUZZ_MAX_LEN)
