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
