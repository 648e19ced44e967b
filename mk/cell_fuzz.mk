# The C fuzz harnesses of the cell's other interfaces, part of `make fuzz`. The dashboard server's
# (tests/c/fuzz_ur_dashboard.c: line splitting, command lookup, reply classification, JSON writer);
# its kept corpus is tests/fuzz/corpus/ur_dashboard, replayed by tests/c/test_c_dashboard.py.

.PHONY: fuzz-ur-dashboard

build/fuzz/fuzz_ur_dashboard: tests/c/fuzz_ur_dashboard.c generated/c/ur_dashboard.c generated/c/ur_dashboard.h
	@mkdir -p build/fuzz
	$(CLANG) -std=c99 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all -Igenerated/c \
		-o $@ tests/c/fuzz_ur_dashboard.c generated/c/ur_dashboard.c

## fuzz-ur-dashboard: the dashboard harness for FUZZ_SECONDS; crashes land in build/fuzz/crashes/ur_dashboard/
fuzz-ur-dashboard: build/fuzz/fuzz_ur_dashboard
	@mkdir -p build/fuzz/corpus/ur_dashboard build/fuzz/crashes/ur_dashboard
	$< -max_len=12000 -max_total_time=$(FUZZ_SECONDS) -print_final_stats=1 \
		-artifact_prefix=build/fuzz/crashes/ur_dashboard/ build/fuzz/corpus/ur_dashboard tests/fuzz/corpus/ur_dashboard

fuzz: fuzz-ur-dashboard

# The ROS driver's sockets: tests/c/fuzz_int32_records.c built once per interface (its sizes by
# release, decoders and JSON writers); kept corpora tests/fuzz/corpus/<interface>, replayed by
# tests/c/test_c_driver_sockets.py.
INT32_RECORD_INTERFACES := ur_reverse ur_trajectory ur_script_command

.PHONY: fuzz-driver-sockets

build/fuzz/fuzz_%: tests/c/fuzz_int32_records.c generated/c/%.c generated/c/%.h
	@mkdir -p build/fuzz
	$(CLANG) -std=c99 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all -Igenerated/c \
		-DPREFIX=$*_ '-DHEADER="$*.h"' -o $@ tests/c/fuzz_int32_records.c generated/c/$*.c

## fuzz-driver-sockets: each driver socket's harness for FUZZ_SECONDS; crashes in build/fuzz/crashes/<interface>/
fuzz-driver-sockets: $(INT32_RECORD_INTERFACES:%=build/fuzz/fuzz_%)
	for name in $(INT32_RECORD_INTERFACES); do \
		mkdir -p build/fuzz/corpus/$$name build/fuzz/crashes/$$name; \
		build/fuzz/fuzz_$$name -max_len=4096 -max_total_time=$(FUZZ_SECONDS) -print_final_stats=1 \
			-artifact_prefix=build/fuzz/crashes/$$name/ build/fuzz/corpus/$$name tests/fuzz/corpus/$$name || exit 1; \
	done

fuzz: fuzz-driver-sockets

# The differential fuzzer of the cell's other interfaces (tests/fuzz/fuzz_diff.py): `urwire decode`
# in-process against urwire-decode's main run again and again in one process
# (tests/c/decode_driver.c, ASan and UBSan on), on mutated sessions of both directions. The
# interfaces run in three groups, one process each, so that `make -j2 fuzz` spreads them; the
# driver sockets share their group's FUZZ_SECONDS. Failing sessions land in
# build/fuzz/crashes/diff_<interface>/; kept corpora are tests/fuzz/corpus/diff_<interface>/,
# replayed by tests/c/test_diff_fuzz_corpus.py.
DIFF_CC := $(CC) $(C_STRICT) -g -O1 -fsanitize=address,undefined -fno-sanitize-recover=all $(C_INCLUDES)
DIFF_GROUPS := rtde dashboard-realtime driver-sockets
DIFF_rtde := rtde
DIFF_dashboard-realtime := ur_dashboard ur_realtime
DIFF_driver-sockets := ur_reverse ur_script_sender ur_trajectory ur_script_command

.PHONY: fuzz-diff $(DIFF_GROUPS:%=fuzz-diff-%)

build/fuzz/decode_driver: tests/c/decode_driver.c $(C_LIB) $(C_CLI)
	@mkdir -p build/fuzz
	$(DIFF_CC) -Dmain=urwire_decode_main -c -o build/fuzz/urwire_decode_main.o tools/urwire-decode/main.c
	$(DIFF_CC) -o $@ tests/c/decode_driver.c build/fuzz/urwire_decode_main.o $(CLI_LIB) $(C_SOURCES) -lm

## fuzz-diff: every interface but the primary, Python against C on mutated sessions, FUZZ_SECONDS a
## group: fuzz-diff-rtde, fuzz-diff-dashboard-realtime, fuzz-diff-driver-sockets (one interface:
## python3 tests/fuzz/fuzz_diff.py --seconds 60 ur_trajectory)
fuzz-diff: $(DIFF_GROUPS:%=fuzz-diff-%)

$(DIFF_GROUPS:%=fuzz-diff-%): fuzz-diff-%: build/fuzz/decode_driver
	$(PYTHON) tests/fuzz/fuzz_diff.py --peer build/fuzz/decode_driver --seconds $(FUZZ_SECONDS) $(DIFF_$*)

fuzz: fuzz-diff
