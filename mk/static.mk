# Static analysis of the C: cppcheck and clang-tidy over every interface's generated C, the C
# runtime on its own (each file as its standalone build compiles it: tests/c/runtime_spec.h and
# runtime_support.h stand in for the generated part) and the command tools/urwire-decode.
# Configuration: .clang-tidy (the checks, and why each one left out is) and
# .cppcheck-suppressions (each with its reason); a finding fails the target.

CPPCHECK ?= cppcheck
CLANG_TIDY ?= clang-tidy
CPPCHECK_FLAGS := --enable=warning,style,performance,portability --inconclusive --std=c99 --quiet \
	--inline-suppr --suppressions-list=.cppcheck-suppressions --error-exitcode=1 \
	--template='{file}:{line}: {severity} [{id}] {message}'

# Each group: its sources (STATIC_C_<group>) and the include folders they compile with (STATIC_C_<group>_I).
# The runtime files that are fragments of a generated file, with no includes of their own
# (runtime/c/typed_messages/rtde_read.c, rtde_conversation.c), are analysed inside generated/c/rtde.c.
STATIC_C_GROUPS := generated common packages lines int32_records realtime json streams capture cli
STATIC_C_generated := $(wildcard generated/c/*.c)
STATIC_C_generated_I := generated/c
STATIC_C_common := $(wildcard runtime/c/common/*.c)
STATIC_C_common_I := runtime/c/common
STATIC_C_packages := $(wildcard runtime/c/packages/*.c)
STATIC_C_packages_I := runtime/c/packages runtime/c/common tests/c
STATIC_C_lines := $(wildcard runtime/c/lines/*.c)
STATIC_C_lines_I := runtime/c/lines
STATIC_C_int32_records := $(wildcard runtime/c/int32_records/*.c)
STATIC_C_int32_records_I := runtime/c/int32_records
STATIC_C_realtime := runtime/c/sized_packets/ur_realtime_decode.c
STATIC_C_realtime_I := tests/c
STATIC_C_json := $(wildcard runtime/c/json/*.c)
STATIC_C_json_I := generated/c runtime/c/json
STATIC_C_streams := runtime/c/typed_messages/rtde_stream.c runtime/c/sized_packets/ur_realtime_stream.c
STATIC_C_streams_I := generated/c
STATIC_C_capture := $(wildcard runtime/c/capture/*.c)
STATIC_C_capture_I := runtime/c/capture
STATIC_C_cli := $(wildcard tools/urwire-decode/*.c)
# as mk/c.mk builds the command (`=`: read when used, whichever mk file make reads first)
STATIC_C_cli_I = $(patsubst -I%,%,$(C_INCLUDES))

.PHONY: static-c static-c-cppcheck static-c-tidy static-c-files

## static-c: cppcheck and clang-tidy over the generated C, the C runtime and urwire-decode (no finding passes)
static-c: static-c-cppcheck static-c-tidy

## static-c-cppcheck: cppcheck alone (a few seconds)
static-c-cppcheck:
	@status=0; $(foreach g,$(STATIC_C_GROUPS),$(CPPCHECK) $(CPPCHECK_FLAGS) $(STATIC_C_$(g)_I:%=-I%) $(STATIC_C_$(g)) \
		|| status=1;) exit $$status

## static-c-tidy: clang-tidy alone (.clang-tidy; about 1.5 minutes of CPU)
static-c-tidy:
	@status=0; $(foreach g,$(STATIC_C_GROUPS),$(CLANG_TIDY) --quiet $(STATIC_C_$(g)) -- -std=c99 $(STATIC_C_$(g)_I:%=-I%) \
		|| status=1;) exit $$status

## static-c-files: the files both tools read, one a line
static-c-files:
	@printf '%s\n' $(foreach g,$(STATIC_C_GROUPS),$(STATIC_C_$(g)))
