-- runtime/messages.lua: one function pair per message kind, driven by each message's data.
local S = dofile("stubs.lua")

local function message_rt(messages)
    local spec = { header_size = 5, package_header_size = 5, package_length_size = 4, messages = messages }
    local rt = S.walker_rt(spec)
    rt.X, rt.E = S.X, S.E
    S.load("info.lua", spec, rt)
    S.load("messages.lua", spec, rt)
    return rt
end

-- A message with a header (a one-byte source), then a subtype byte.
local KEY = {
    { k = "scalar", f = "ur.key.code", n = 1, path = "code", signed = false, show = "#" },
    { k = "string", f = "ur.key.text", path = "text", show = ": " },
}
local UPDATE = { { k = "scalar", f = "ur.update.index", n = 1, path = "index", signed = false } }
local ROBOT = {
    kind = "subtypes", label = "Robot message", body_offset = 7,
    header = {
        { k = "scalar", f = "ur.robot.source", n = 1, path = "source", signed = true },
        { k = "scalar", f = "ur.robot.type", n = 1, path = "type", signed = false },
    },
    subtype_field = "ur.robot.type", subtype_names = { [7] = "KEY", [8] = "UPDATE", [9] = "NOT_LAID_OUT" },
    subtypes = {
        [7] = { name = "key", label = "Key", item = "ur.key", layout = KEY, needs_version = false,
                header = { { k = "scalar", f = "ur.key.source", n = 1, path = "source", signed = true } } },
        [8] = { name = "update", label = "Update", item = "ur.update", layout = UPDATE, needs_version = true,
                header = { { k = "scalar", f = "ur.update.source", n = 1, path = "source", signed = true } } },
    },
}
local STATE = {
    kind = "packages", label = "Robot state", types = { [0] = "MODE", [1] = "JOINTS", [14] = "PAYLOAD" },
    length = "ur.package.length", type = "ur.package.type",
    packages = {
        [0] = { name = "mode", label = "Mode", item = "ur.mode", refs = { "ur.mode.mode" },
                info = { { at = 0, n = 1, vs = { [7] = "RUNNING" } } },
                layout = { { k = "scalar", f = "ur.mode.mode", n = 1, path = "mode", signed = true } } },
    },
}
local rt = message_rt({ [20] = ROBOT, [16] = STATE })
local robot, state = rt.handlers[20], rt.handlers[16]
S.eq(robot.suffix, ", Robot message", "the item's suffix, made at load time")
S.eq(robot.m, ROBOT, "the message's data")

local function msg(mtype, body) return S.bytes(0, 0, 0, 5 + #body, mtype) .. body end
local function tree_of(h, raw, version, assumed)
    local tree = S.tree()
    local st = S.st(raw, version)
    st.assumed = assumed or false
    h.tree(h.m, S.tvb(raw), tree, 0, #raw, st)
    return S.dump(tree)
end

-- subtypes
local key = msg(20, S.bytes(0xfe, 7, 3) .. "go")
S.eq(robot.info(robot.m, S.tvb(key), key, 0, #key), "Key: #3: go", "Info of a known subtype")
S.eq(tree_of(robot, key), S.lines(
    "ur.key @5+5",
    "  ur.key.source @5+1",
    "  ur.robot.type @6+1",
    "  ur.key.code @7+1",
    "  ur.key.text @8+2 = go"), "tree of a known subtype")
local unknown = msg(20, S.bytes(1, 9, 0xaa))
S.eq(robot.info(robot.m, S.tvb(unknown), unknown, 0, #unknown), "Robot message subtype 9", "Info of a subtype not laid out")
S.eq(tree_of(robot, unknown), S.lines(
    "ur.robot.source @5+1",
    "ur.robot.type @6+1",
    "ur.raw @7+1"), "a named subtype without a layout: raw, no expert")
local undocumented = msg(20, S.bytes(1, 42))
S.eq(tree_of(robot, undocumented), S.lines(
    "!unknown: robot message subtype 42 is not in the spec, kept raw",
    "ur.robot.source @5+1",
    "ur.robot.type @6+1"), "a subtype not in the spec: an expert")
local short = msg(20, S.bytes(1))
S.eq(robot.info(robot.m, S.tvb(short), short, 0, #short), "Robot message (too short)", "Info of a short message")
S.eq(tree_of(robot, short), S.lines(
    "!malformed: type at offset 6: needs 1 bytes, 0 left",
    "ur.robot.source @5+1",
    "ur.raw @5+1"), "a short message: its header and an expert")
local update = msg(20, S.bytes(1, 8, 4, 0xee))
S.eq(tree_of(robot, update, 5009, true), S.lines(
    "ur.update @5+4",
    "  !assumed: no Version message seen on this stream: assuming software 5.9 (preference ur.version)",
    "  !extra: update: 1 bytes after the layout",
    "  ur.update.source @5+1",
    "  ur.robot.type @6+1",
    "  ur.software_version @nil+nil = 5.9",
    "  ur.version_assumed @nil+nil = true",
    "  ur.update.index @7+1",
    "  ur.extra @8+1"), "the version a message is read with; extra bytes")
local cut = msg(20, S.bytes(1, 8))
S.eq(tree_of(robot, cut, 5010, false), S.lines(
    "ur.update @5+2",
    "  !malformed: update: index at offset 7: needs 1 bytes, 0 left",
    "  ur.update.source @5+1",
    "  ur.robot.type @6+1",
    "  ur.software_version @nil+nil = 5.10",
    "  ur.raw @7+0"), "a body that cannot be read is kept raw")

-- packages
local function package(code, body) return S.bytes(0, 0, 0, 5 + #body, code) .. body end
local robot_state = msg(16, package(0, S.bytes(7)) .. package(14, "") .. package(99, "zz"))
S.eq(state.info(state.m, S.tvb(robot_state), robot_state, 0, #robot_state), "Robot state: RUNNING", "Info of a robot state")
S.eq(tree_of(state, robot_state), S.lines(
    "ur.mode @5+6",
    "  ur.package.length @5+4",
    "  ur.package.type @9+1",
    "  ur.mode.mode @10+1",
    "ur.unknown_package @11+5 (Unknown package 14 (PAYLOAD))",
    "  ur.package.length @11+4",
    "  ur.package.type @15+1",
    "  ur.raw @16+0",
    "ur.unknown_package @16+7 (Unknown package 99 (not in the spec))",
    "  !unknown: package type 99 is not in the spec, kept raw",
    "  ur.package.length @16+4",
    "  ur.package.type @20+1",
    "  ur.raw @21+2"), "packages: known, named but not laid out, not in the spec")
local bad = msg(16, S.bytes(0, 0, 0, 2, 0, 1))
S.eq(tree_of(state, bad), S.lines(
    "!malformed: package at offset 5: length 2 is below 5",
    "ur.raw @5+6"), "a package length below its header")
bad = msg(16, S.bytes(0, 0, 0, 9, 0, 1))
S.eq(tree_of(state, bad), S.lines(
    "!malformed: package at offset 5: length 9 exceeds the 6 bytes left",
    "ur.raw @5+6"), "a package longer than the message")
bad = msg(16, package(0, S.bytes(7)) .. S.bytes(0, 0))
S.eq(tree_of(state, bad):match("!malformed: package at offset 11: needs 5 bytes, 2 left") ~= nil, true, "a cut header")

-- No tree and no field of the package asked for: the package's fields are skipped.
local tree = S.tree(false)
local st = S.st(robot_state)
st.visible = false
state.tree(state.m, S.tvb(robot_state), tree, 0, #robot_state, st)
S.eq(S.dump(tree):match("ur.mode.mode") == nil, true, "skipped without a tree")
tree = S.tree(false)
tree.asked["ur.mode.mode"] = true
state.tree(state.m, S.tvb(robot_state), tree, 0, #robot_state, st)
S.eq(S.dump(tree):match("ur.mode.mode @10%+1") ~= nil, true, "walked when a filter asks for its field")

-- A message of a kind the runtime does not know stops the load.
local ok, err = pcall(message_rt, { [30] = { kind = "tlv", label = "New" } })
S.eq(ok, false, "unknown kind")
S.eq(err:match("message type 30 has an unknown kind tlv") ~= nil, true, "its error: " .. tostring(err))
print("ok")
