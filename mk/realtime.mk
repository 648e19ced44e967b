# The real-time interface (30003): its benchmark. Its tests run with each target's (tests/python,
# tests/c, tests/lua); its fuzzer is in mk/fuzz.mk.

BENCH_TARGETS += bench-realtime
BENCH_REALTIME_PACKETS ?= 30000
BENCH_REALTIME_LARGE ?= 1000000

.PHONY: bench-realtime

## bench-realtime: real-time packets per second in Python and C (urwire-decode, against the Python
## command), and tshark with ur_realtime.lua against --disable-protocol ur_realtime, on
## BENCH_REALTIME_PACKETS packets (30,000); the cost per packet in Python and C at
## BENCH_REALTIME_LARGE packets (1,000,000) against BENCH_REALTIME_PACKETS
bench-realtime: build/urwire-decode
	$(PYTHON) tests/bench/bench_realtime.py --packets $(BENCH_REALTIME_PACKETS) --large $(BENCH_REALTIME_LARGE)
