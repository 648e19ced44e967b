# Lua Wireshark dissectors: generated/lua/*.lua (written by `make generate`: urwire.lua for the
# primary interface, one file per other interface of the cell, each loading on its own), their tests,
# benchmark, sample captures and installation into the user's personal plugins folder.

TSHARK ?= tshark
LUA_PLUGIN := generated/lua/urwire.lua
LUA_PLUGINS := $(wildcard generated/lua/*.lua)

BENCH_TARGETS += bench-lua
DEMO_TARGETS += demo-lua

.PHONY: test-lua bench-lua demo-lua samples screenshots

## test-lua: the dissector in real tshark against every vector, segmentation and mutated stream
test-lua:
	$(PYTEST) -q tests/lua

## bench-lua: tshark with the dissector against tshark with `--disable-protocol ur`, same file
## (BENCH_LUA_PLUGIN=path measures another build of the dissector the same way)
bench-lua:
	$(PYTHON) tests/bench/bench_lua.py

## demo-lua: the dissector on the bundled primary-port capture
demo-lua:
	@echo "== Wireshark (tshark + $(LUA_PLUGIN)): dissector/samples/primary_session.pcapng, Info column"
	@$(TSHARK) -r dissector/samples/primary_session.pcapng -X lua_script:$(LUA_PLUGIN) -Y ur \
		-T fields -e frame.number -e _ws.col.Info 2>/dev/null | head -n 20
	@echo "== a robot state and a global-variables update in one segment (tree excerpt)"
	@$(TSHARK) -r dissector/samples/primary_session.pcapng -X lua_script:$(LUA_PLUGIN) -O ur \
		-Y 'frame.number == 30' 2>/dev/null | sed -n '/^Universal Robots/,$$p' | head -n 40
	@echo "== filter: ur.robot_mode_data.robot_mode == \"RUNNING\" && ur.joint_data.q_actual > 1.5"
	@$(TSHARK) -r dissector/samples/primary_session.pcapng -X lua_script:$(LUA_PLUGIN) \
		-Y 'ur.robot_mode_data.robot_mode == "RUNNING" && ur.joint_data.q_actual > 1.5' 2>/dev/null | head -n 5

## screenshots: the pictures of dissector/README.md, taken from the real Wireshark GUI on the bundled
## captures under Xvfb (dissector/images/*.png; needs wireshark-qt, xvfb, xdotool, imagemagick);
## SHOTS="gripper.png rtde_output.png" takes only those
screenshots:
	xvfb-run -a -s "-screen 0 1600x1000x24" $(PYTHON) scripts/screenshots.py $(SHOTS)

## samples: rewrite dissector/samples/ from the conformance bytes (deterministic)
samples:
	$(PYTHON) dissector/make_samples.py
