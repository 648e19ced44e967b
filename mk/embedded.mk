# The C parser on microcontrollers: flash, static RAM and worst-case stack of every interface's
# parser and of the firmwares of examples/embedded, on Cortex-M0+, Cortex-M4F, Cortex-M7
# (arm-none-eabi-gcc, newlib-nano) and RV32IMC (riscv64-unknown-elf-gcc, picolibc), at -Os and
# -O2. The figures go to examples/embedded/measurements.json and docs/c.md's budget table
# (scripts/bench_embedded.py); tests/c/test_embedded.py checks that the table is the
# measurement's and that the measurement is of today's code.

EMBEDDED_SUBSET ?= ur:robot_state.joint_data,robot_state.tool_data

.PHONY: bench-embedded embedded-table

## bench-embedded: measure flash, RAM and stack on the microcontroller targets (a few minutes)
## and write docs/c.md's budget table; the pinned firmware is PIN's (make pinned-c)
bench-embedded: pinned-c
	$(PYTHON) scripts/bench_embedded.py measure --pinned $(PINNED_C)/c --subset-selection '$(EMBEDDED_SUBSET)'

## embedded-table: docs/c.md's budget table again from the last measurement
embedded-table:
	$(PYTHON) scripts/bench_embedded.py render
