# The dashboard server's C fuzz harness (tests/c/fuzz_ur_dashboard.c: line splitting, command
# lookup, reply classification, JSON writer), part of `make fuzz`; its kept corpus is
# tests/fuzz/corpus/ur_dashboard, replayed by tests/c/test_c_dashboard.py on every `make test`.

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
