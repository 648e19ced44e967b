-- runtime/lua/packages/messages.lua: one function pair per message kind, driven by each message's data.
local S = dofile("stubs.lua")

local function message_rt(messages)
    -- Two series of forms: up to 1.8, and from 3.0 (1.9 to 3.0 is no one's).
    local spec = { header_size = 5, package_header_size = 5, package_length_size = 4, messages = messages,
                   segment_starts = { "1.9", "3.0" } }
    local rt = S.walker_rt(spec)
    rt.X, rt.E = S.X, S.E
    S.load("common/info_column.lua", spec, rt)
    S.load("packages/info.lua", spec, rt)
    S.load("packages/messages.lua", spec, rt)
    return rt
end

-- Forms of a type code: one for every version, or several (see versions.lua).
local function single(part)
    return { single = true, summary = part.summary, { of = part, min = 0, rep = "5.9", versions = "all versions" } }
end

-- A message with a header (a one-byte source), then a subtype byte.
local KEY = {
    { k = "scalar", f = "ur.key.code", n = 1, path = "code", signed = false, show = "#" },
    { k = "string", f = "ur.key.text", path = "text", show = ": " },
}
local UPDATE = { { k = "scalar", f = "ur.update.index", n = 1, path = "index", signed = false } }
local OLD_UPDATE = { { k = "scalar", f = "ur.update.index", n = 2, path = "index", signed = false, value = true } }
local UPDATE_PART = { name = "update", label = "Update", item = "ur.update", layout = UPDATE, needs_version = true,
                      header = { { k = "scalar", f = "ur.update.source", n = 1, path = "source", signed = true } } }
local OLD_UPDATE_PART = { name = "old_update", label = "Old update", item = "ur.old_update", layout = OLD_UPDATE, needs_version = true,
                          header = { { k = "scalar", f = "ur.old_update.source", n = 1, path = "source", signed = true } } }
local SUBTYPE_NAMES = { [7] = "KEY", [8] = "UPDATE", [9] = "NOT_LAID_OUT" }
local ROBOT = {
    kind = "subtypes", label = "Robot message", body_offset = 7,
    header = {
        { k = "scalar", f = "ur.robot.source", n = 1, path = "source", signed = true },
        { k = "scalar", f = "ur.robot.type", n = 1, path = "type", signed = false },
    },
    subtype_field = "ur.robot.type", subtype_label = "type", subtype_names = SUBTYPE_NAMES,
    subtype_tables = { newest = SUBTYPE_NAMES, { high = 1008999, names = { [8] = "OLD_UPDATE", [42] = "GONE" } },
                       { low = 3000000, names = SUBTYPE_NAMES } },
    subtypes = {
        [7] = single({ name = "key", label = "Key", item = "ur.key", layout = KEY, needs_version = false,
                       header = { { k = "scalar", f = "ur.key.source", n = 1, path = "source", signed = true } } }),
        [8] = { segments = { 1, -1, 2 }, by_length = { [2] = 1, [1] = 2 },
                { of = OLD_UPDATE_PART, sizes = { [2] = true }, min = 2, rep = "1.8", versions = "up to 1.8" },
                { of = UPDATE_PART, sizes = { [1] = true }, min = 1, rep = "5.9", versions = "3.0 and later" } },
    },
}
local MODE_PART = { name = "mode", label = "Mode", item = "ur.mode", refs = { "ur.mode.mode" }, summary = true,
                    layout = { { k = "scalar", f = "ur.mode.mode", n = 1, path = "mode", signed = true, vs = { [7] = "RUNNING" }, show = "" } } }
local TYPES = { [0] = "MODE", [1] = "JOINTS", [14] = "PAYLOAD" }
local STATE = {
    kind = "packages", label = "Robot state", types = TYPES, needs_version = false,
    type_tables = { newest = TYPES, { high = 1008999, names = { [0] = "OLD_MODE", [5] = "EARLY", [20] = "GONE" } }, { low = 3000000, names = TYPES } },
    length = "ur.package.length", type = "ur.package.type",
    packages = { [0] = single(MODE_PART) },
}
local rt = message_rt({ [20] = ROBOT, [16] = STATE })
local robot, state = rt.handlers[20], rt.handlers[16]
S.eq(robot.suffix, ", Robot message", "the item's suffix, made at load time")
S.eq(robot.m, ROBOT, "the message's data")

local function msg(mtype, body) return S.bytes(0, 0, 0, 5 + #body, mtype) .. body end
-- st as framing.lua sets it: how = "announced", "pref", "default" or the implied versions.
local function state_of(raw, version, how)
    local st = S.st(raw, version)
    how = how or "announced"
    st.announced, st.from_pref = how == "announced", how == "pref"
    st.known = st.announced or st.from_pref
    if not (st.known or how == "default") then st.implied, st.message_implied = how, how end
    return st
end
local function tree_of(h, raw, version, how)
    local tree = S.tree()
    h.tree(h.m, S.tvb(raw), tree, 0, #raw, state_of(raw, version, how))
    return S.dump(tree)
end
local function info_of(h, raw, version, how)
    return h.info(h.m, S.tvb(raw), raw, 0, #raw, state_of(raw, version, how), true)
end

-- subtypes
local key = msg(20, S.bytes(0xfe, 7, 3) .. "go")
S.eq(info_of(robot, key), "Key: #3: go", "Info of a known subtype")
S.eq(tree_of(robot, key), S.lines(
    "ur.key @5+5",
    "  ur.key.source @5+1",
    "  ur.robot.type @6+1",
    "  ur.key.code @7+1",
    "  ur.key.text @8+2 = go"), "tree of a known subtype")
local unknown = msg(20, S.bytes(1, 9, 0xaa))
S.eq(info_of(robot, unknown), "Robot message subtype 9", "Info of a subtype not laid out")
S.eq(tree_of(robot, unknown), S.lines(
    "ur.robot.source @5+1",
    "ur.robot.type @6+1",
    "ur.raw @7+1"), "a named subtype without a layout: raw, no expert")
local undocumented = msg(20, S.bytes(1, 43))
S.eq(tree_of(robot, undocumented), S.lines(
    "!unknown: robot message subtype 43 is not in the spec, kept raw",
    "ur.robot.source @5+1",
    "ur.robot.type @6+1"), "a subtype not in the spec: an expert")
local gone = msg(20, S.bytes(1, 42))
S.eq(tree_of(robot, gone), S.lines(
    "ur.robot.source @5+1",
    "ur.robot.type @6+1"), "a subtype another version's table names: no expert")
local short = msg(20, S.bytes(1))
S.eq(info_of(robot, short), "Robot message (too short)", "Info of a short message")
S.eq(tree_of(robot, short), S.lines(
    "!malformed: type at offset 6: needs 1 bytes, 0 left",
    "ur.robot.source @5+1",
    "ur.raw @5+1"), "a short message: its header and an expert")
local update = msg(20, S.bytes(1, 8, 4, 0xee, 0xdd))
S.eq(tree_of(robot, update, 5009000, "pref"), S.lines(
    "ur.update @5+5",
    "  !assumed: no Version message seen on this stream: assuming software 5.9 (preference ur.version)",
    "  !extra: update: 2 bytes after the layout",
    "  ur.update.source @5+1",
    "  ur.robot.type @6+1",
    "  ur.software_version @nil+nil = 5.9",
    "  ur.version_assumed @nil+nil = true",
    "  ur.update.index @7+1",
    "  ur.extra @8+2"), "the version a message is read with; fits no form: the version's, extra bytes")
S.eq(tree_of(robot, update, 5009000, "default"):match(
    "!assumed: no Version message seen on this stream: assuming software 5.9 %(the default; preference ur.version%)") ~= nil,
    true, "no preference: the default")
local cut = msg(20, S.bytes(1, 8))
S.eq(tree_of(robot, cut, 5010000), S.lines(
    "ur.update @5+2",
    "  !malformed: update: index at offset 7: needs 1 bytes, 0 left",
    "  ur.update.source @5+1",
    "  ur.robot.type @6+1",
    "  ur.software_version @nil+nil = 5.10",
    "  ur.raw @7+0"), "a body that cannot be read is kept raw")

-- A subtype with two forms: the version's, else the one its length fits, with a note.
local old_update = msg(20, S.bytes(1, 8, 4, 0xee))
S.eq(tree_of(robot, old_update, 1008000), S.lines(
    "ur.old_update @5+4",
    "  ur.old_update.source @5+1",
    "  ur.robot.type @6+1 (type: OLD_UPDATE (8))",
    "  ur.software_version @nil+nil = 1.8",
    "  ur.update.index @7+2 = 1262"), "1.8: the old form, the old subtype name")
local new_update = msg(20, S.bytes(1, 8, 4))
S.eq(tree_of(robot, new_update, 1008000), S.lines(
    "ur.update @5+3",
    "  !by_length: laid out as software 3.0 and later (chosen by length 8)",
    "  ur.update.source @5+1",
    "  ur.robot.type @6+1",
    "  ur.software_version @nil+nil = 1.8",
    "  ur.update.index @7+1"), "1.8, but only the new form fits: chosen by length, read (and named) as 5.9")
S.eq(info_of(robot, new_update, 1008000), "Update", "Info: the form chosen by length")
S.eq(tree_of(robot, new_update, 1008000, "3.0 and later"):match(
    "ur.software_version @nil%+nil = 3.0 and later %(from layout sizes%)") ~= nil, true,
    "a version the layout sizes showed earlier in the stream")

-- packages
local function package(code, body) return S.bytes(0, 0, 0, 5 + #body, code) .. body end
local robot_state = msg(16, package(0, S.bytes(7)) .. package(14, "") .. package(99, "zz"))
S.eq(info_of(state, robot_state), "Robot state: RUNNING", "Info of a robot state")
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
-- Asked once per package kind per dissector call (st.call).
local tree = S.tree(false)
local st = state_of(robot_state)
st.visible, st.call = false, 1
local asked = 0
local function counting(t)   -- counts what is asked of the tree (its items share `asked`)
    t.asked = setmetatable({}, { __index = function() asked = asked + 1 end })
    return t
end
local twice = msg(16, package(0, S.bytes(7)) .. package(0, S.bytes(7)))
state.tree(state.m, S.tvb(twice), counting(tree), 0, #twice, st)
S.eq(S.dump(tree):match("ur.mode.mode") == nil, true, "skipped without a tree")
S.eq(asked, 1, "two packages of one kind: asked once")
tree = S.tree(false)
tree.asked["ur.mode.mode"] = true
st.call = 2
state.tree(state.m, S.tvb(robot_state), tree, 0, #robot_state, st)
S.eq(S.dump(tree):match("ur.mode.mode @10%+1") ~= nil, true, "walked when a filter asks for its field")

-- A tshark -T fields run that names no field of a package (st.only, runtime/lua/packages/wanted.lua): the
-- package is not built; the packages it names are, whole.
tree = S.tree()
st = state_of(robot_state)
st.only = {}
state.tree(state.m, S.tvb(robot_state), tree, 0, #robot_state, st)
S.eq(S.dump(tree):match("ur.mode") == nil, true, "a package no field of is named: not built")
S.eq(S.dump(tree):match("Unknown package 99") ~= nil, true, "one the spec does not lay out still shows")
tree = S.tree()
st.only = { [MODE_PART] = true }
state.tree(state.m, S.tvb(robot_state), tree, 0, #robot_state, st)
S.eq(S.dump(tree):match("ur.mode @5%+6\n  ur.package.length @5%+4\n  ur.package.type @9%+1\n  ur.mode.mode @10%+1") ~= nil,
     true, "a named package: whole")

-- A package type with two layouts (up to 1.8: 1 byte; from 3.0: 2 bytes), in a message whose
-- reading depends on the version: the version's layout, else the one its length fits.
local EARLY_PART = { name = "early", label = "Early", item = "ur.early", refs = {}, summary = false,
                     layout = { { k = "scalar", f = "ur.early.x", n = 1, path = "x", signed = false } } }
local LATE_PART = { name = "late", label = "Late", item = "ur.late", refs = {}, summary = false,
                    layout = { { k = "scalar", f = "ur.late.x", n = 2, path = "x", signed = false } } }
STATE.packages[5] = { segments = { 1, -1, 2 }, by_length = { [1] = 1, [2] = 2 },
                      { of = EARLY_PART, sizes = { [1] = true }, min = 1, rep = "1.8", versions = "up to 1.8" },
                      { of = LATE_PART, sizes = { [2] = true }, min = 2, rep = "5.9", versions = "3.0 and later" } }
STATE.needs_version = true
local early = msg(16, package(5, S.bytes(1)) .. package(0, S.bytes(7)))
S.eq(tree_of(state, early, 5009000, "default"), S.lines(
    "!assumed: no Version message seen on this stream: assuming software 5.9 (the default; preference ur.version)",
    "ur.software_version @nil+nil = 5.9",
    "ur.version_assumed @nil+nil = true",
    "ur.early @5+6",
    "  !by_length: laid out as software up to 1.8 (chosen by length 6)",
    "  ur.package.length @5+4",
    "  ur.package.type @9+1 (Type: EARLY (5))",
    "  ur.early.x @10+1",
    "ur.mode @11+6",
    "  ur.package.length @11+4",
    "  ur.package.type @15+1 (Type: OLD_MODE (0))",
    "  ur.mode.mode @16+1"), "chosen by length; the rest of the message follows its version (the old type names)")
local known = state_of(early, 5009000)
state.tree(state.m, S.tvb(early), S.tree(), 0, #early, known)
S.eq(known.version, 5009000, "an announced version stays")
local unknown_st = state_of(early, 5009000, "default")
S.eq(info_of(state, early, 5009000, "default"), "Robot state: RUNNING", "Info")
S.eq(state.info(state.m, S.tvb(early), early, 0, #early, unknown_st, false), nil, "no column: no text")
S.eq(unknown_st.version, 1008000, "the Info pass learns the version from the sizes, column or not")
S.eq(unknown_st.implied, "up to 1.8", "and which form told it")
-- Shown on the message as what the layout sizes tell, when framing.lua says so.
S.eq(tree_of(state, early, 5009000, "up to 1.8"):match(
    "^!assumed: no Version message seen on this stream: software up to 1.8, as the layout sizes show\n" ..
    "ur.software_version @nil%+nil = up to 1.8 %(from layout sizes%)\nur.version_assumed @nil%+nil = true") ~= nil,
    true, "the version the layout sizes show")
-- Without a tree the form is still chosen (the version learnt), its fields skipped.
tree = S.tree(false)
st = state_of(early, 5009000, "default")
st.visible = false
state.tree(state.m, S.tvb(early), tree, 0, #early, st)
S.eq(st.version, 1008000, "learnt without a tree")
S.eq(S.dump(tree):match("ur.early.x") == nil, true, "fields skipped")

-- A message of a kind the runtime does not know stops the load.
local ok, err = pcall(message_rt, { [30] = { kind = "tlv", label = "New" } })
S.eq(ok, false, "unknown kind")
S.eq(err:match("message type 30 has an unknown kind tlv") ~= nil, true, "its error: " .. tostring(err))
print("ok")
