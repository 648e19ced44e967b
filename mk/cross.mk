# Other CPUs: every interface's generated C (generated/c/*.c) cross-compiled for the
# microcontrollers firmware runs on, -Werror with the project's warnings (C_STRICT, mk/c.mk), at
# each of CROSS_LEVELS; and the golden vectors run under QEMU on a big-endian CPU, on 32-bit ARM
# and on a Cortex-M (tests/c/test_cross.py, which takes every compiler and flag from here through
# `make cross-table`). scripts/setup.sh installs the toolchains and QEMU.

CROSS_CPUS := cortex-m0plus cortex-m4f cortex-m7 rv32imc
CROSS_LEVELS ?= -Os -O2
CROSS_OUT ?= build/cross
# Sections per function and per object, as firmware builds them for --gc-sections.
CROSS_COMMON := $(C_STRICT) -ffunction-sections -fdata-sections

CROSS_CC_cortex-m0plus := arm-none-eabi-gcc
CROSS_FLAGS_cortex-m0plus := -mcpu=cortex-m0plus -mthumb
CROSS_CC_cortex-m4f := arm-none-eabi-gcc
CROSS_FLAGS_cortex-m4f := -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16
CROSS_CC_cortex-m7 := arm-none-eabi-gcc
CROSS_FLAGS_cortex-m7 := -mcpu=cortex-m7 -mthumb -mfloat-abi=hard -mfpu=fpv5-d16
# picolibc's specs give the libc headers (stddef.h and string.h) of a bare RV32 target.
CROSS_CC_rv32imc := riscv64-unknown-elf-gcc
CROSS_FLAGS_rv32imc := -march=rv32imc -mabi=ilp32 --specs=picolibc.specs

# The programs that run the golden vectors (tests/c/test_cross.py): urwire-decode's main run once
# per vector in one process (tests/c/decode_driver.c), built statically for Linux on s390x
# (big-endian) and on 32-bit ARM (no unaligned access emitted), run under qemu-s390x and qemu-arm;
# and on a Cortex-M4F (QEMU's mps2-an386 board, every unaligned access trapped), where newlib's
# semihosting (rdimon) gives the harness its stdin, files and stdout, never the library. The
# board's 16 MiB PSRAM (at 0x21000000) holds the program and its buffers, with RTDE kept to 64
# recipes (RUN_DEFINES: the x86 build it is compared with takes them too).
# RUN_CC_<run>, RUN_FLAGS_<run>, RUN_DEFINES_<run>, RUN_START_<run> (the harness's start code)
# and RUN_QEMU_<run> (the command line the program follows).
CROSS_RUNS := s390x armhf mps2-an386
RUN_CC_s390x := s390x-linux-gnu-gcc
RUN_FLAGS_s390x := -static
RUN_QEMU_s390x := qemu-s390x
RUN_CC_armhf := arm-linux-gnueabihf-gcc
RUN_FLAGS_armhf := -static -mno-unaligned-access
RUN_QEMU_armhf := qemu-arm
RUN_CC_mps2-an386 := arm-none-eabi-gcc
RUN_FLAGS_mps2-an386 := $(CROSS_FLAGS_cortex-m4f) -mno-unaligned-access --specs=rdimon.specs \
	-Wl,--section-start=.vectors=0 -Wl,-Ttext-segment=0x21000000
RUN_DEFINES_mps2-an386 := -DRTDE_JSON_RECIPES=64 -DRTDE_JSON_VARIABLES=2048 -DRTDE_JSON_NAMES=16384
RUN_START_mps2-an386 := tests/c/cross/mps2_start.c
RUN_QEMU_mps2-an386 := qemu-system-arm -M mps2-an386 -nographic -monitor none -serial none \
	-semihosting-config enable=on,target=native -kernel

.PHONY: cross cross-table

## cross: every interface's C for Cortex-M0+, M4F, M7 and RV32IMC at each of CROSS_LEVELS
## (-Os -O2), -Werror: CROSS_OUT/<cpu>/<level without its dash>/<interface>.o
CROSS_NAMES := $(patsubst generated/c/%.c,%,$(C_SOURCES))
cross: $(foreach cpu,$(CROSS_CPUS),$(foreach level,$(CROSS_LEVELS:-%=%),\
	$(CROSS_NAMES:%=$(CROSS_OUT)/$(cpu)/$(level)/%.o)))

define CROSS_RULE
$(CROSS_OUT)/$(1)/$(2:-%=%)/%.o: generated/c/%.c $(wildcard generated/c/*.h)
	@mkdir -p $$(@D)
	$(CROSS_CC_$(1)) $(CROSS_COMMON) $(2) $(CROSS_FLAGS_$(1)) -c $$< -o $$@
endef
$(foreach cpu,$(CROSS_CPUS),$(foreach level,$(CROSS_LEVELS),$(eval $(call CROSS_RULE,$(cpu),$(level)))))

## cross-table: what tests/c/test_cross.py builds with, a line each: "cpu NAME CC FLAGS" for
## `make cross`, "run NAME CC FLAGS | DEFINES | START | QEMU" for the QEMU runs, "common FLAGS"
cross-table:
	@$(foreach cpu,$(CROSS_CPUS),echo 'cpu $(cpu) $(CROSS_CC_$(cpu)) $(CROSS_FLAGS_$(cpu))';)
	@$(foreach run,$(CROSS_RUNS),echo 'run $(run) $(RUN_CC_$(run)) $(RUN_FLAGS_$(run)) | $(RUN_DEFINES_$(run)) \
		| $(RUN_START_$(run)) | $(RUN_QEMU_$(run))';)
	@echo 'common $(CROSS_COMMON)'

DEEP_TESTS += cross
