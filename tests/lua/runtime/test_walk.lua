-- runtime/lua/packages/walk.lua: a small descriptor list walked into a stub tree, and the error paths.
local S = dofile("stubs.lua")
local rt = S.walker_rt()
local walk = rt.walk

local L_joint = {
    { k = "scalar", f = "ur.p.q", n = 2, path = "q", signed = false },
}
local L = {
    { k = "scalar", f = "ur.p.flag", n = 1, path = "flag", signed = false, keep = "flag" },
    { k = "cond", present_if = "flag", fields = {
        { k = "scalar", f = "ur.p.extra", n = 1, path = "extra", signed = false },
    } },
    { k = "cond", low = 5010000, fields = {
        { k = "scalar", f = "ur.p.new", n = 1, path = "new", signed = false },
    } },
    { k = "bits", f = "ur.p.bits", n = 1, path = "bits", signed = false, bits = { "ur.p.bits.a", "ur.p.bits.b" } },
    { k = "array", f = "ur.p.arr", n = 1, count = 2, path = "arr" },
    { k = "group", f = "ur.p.joints", label = "Joint", count = 2, size = 2, item = L_joint, path = "joints" },
    { k = "switch", sel = "flag", path = "sw", default = { f = "ur.p.sw", n = 4 }, cases = { [1] = { f = "ur.p.sw_uint8", n = 1 } } },
    { k = "pstring", f = "ur.p.name", n = 1, signed = true, path = "name" },
    { k = "strings", f = "ur.p.names", term = 10, path = "names" },
}

local raw = S.bytes(1, 7, 3, 10, 11, 0, 1, 0, 2, 5, 2) .. "hi" .. "a\nb\nc"
local tree = S.tree()
S.eq(walk(S.tvb(raw), tree, 0, #raw, S.st(raw, 5009000), L, nil), #raw - 1, "offset after the layout: before the unterminated c")
S.eq(S.dump(tree), S.lines(
    "ur.p.flag @0+1",
    "ur.p.extra @1+1",
    "ur.p.bits @2+1",
    "  ur.p.bits.a @2+1",
    "  ur.p.bits.b @2+1",
    "ur.p.arr @3+1",
    "ur.p.arr @4+1",
    "ur.p.joints @5+2 (Joint 0)",
    "  ur.p.q @5+2",
    "ur.p.joints @7+2 (Joint 1)",
    "  ur.p.q @7+2",
    "ur.p.sw_uint8 @9+1",
    "ur.p.name @11+2 = hi",
    "ur.p.names @13+1 = a",
    "ur.p.names @15+1 = b"), "tree")

-- flag 0: no extra byte, the switch takes its default (4 bytes); version 5.10: the new byte.
raw = S.bytes(0, 9, 3, 10, 11, 0, 1, 0, 2, 0, 0, 0, 5, 0)
tree = S.tree()
S.eq(walk(S.tvb(raw), tree, 0, #raw, S.st(raw, 5010000), L, nil), #raw, "end")
S.eq(S.dump(tree):match("ur.p.new @1%+1") ~= nil, true, "version-gated field read from 5.10")
S.eq(S.dump(tree):match("ur.p.extra") == nil, true, "present_if field absent when flag is 0")
S.eq(S.dump(tree):match("ur.p.sw @9%+4") ~= nil, true, "switch default")

-- Errors name the field's path and the offset from the message's first byte.
raw = S.bytes(0, 3, 10, 11, 0, 1, 0)
tree = S.tree()
local o, err = walk(S.tvb(raw), tree, 0, #raw, S.st(raw, 5009000), L, nil)
S.eq(o, nil, "no offset on error")
S.eq(err, "joints[1].q at offset 6: needs 2 bytes, 1 left", "short group item")
S.eq(S.dump(tree):match("ur.p.joints @6%+1 %(Joint 1%)") ~= nil, true, "the broken item spans what is left")

o, err = walk(S.tvb(raw), S.tree(), 0, 3, S.st(raw), { L[5], L[5] }, nil)
S.eq(err, "arr[1] at offset 3: needs 1 bytes, 0 left", "second array, second item")
o, err = walk(S.tvb(raw), S.tree(), 0, 3, S.st(raw), L_joint, "joints[4].")
S.eq(err, nil, "fits")
o, err = walk(S.tvb(raw), S.tree(), 2, 3, S.st(raw), L_joint, "joints[4].")
S.eq(err, "joints[4].q at offset 2: needs 2 bytes, 1 left", "prefix of an enclosing group")

local neg = S.bytes(0xfe) .. "xx"
o, err = walk(S.tvb(neg), S.tree(), 0, #neg, S.st(neg), { L[8] }, nil)
S.eq(err, "name at offset 0: negative length -2", "negative length")

-- A group to the end of the layout, items of variable size, and text and bytes to the end.
local L_to_end = {
    { k = "group", f = "ur.p.threads", label = "Thread", path = "threads", item = {
        { k = "pstring", f = "ur.p.label", n = 1, signed = false, path = "label" },
    } },
}
raw = S.bytes(1) .. "a" .. S.bytes(2) .. "bc"
tree = S.tree()
S.eq(walk(S.tvb(raw), tree, 0, #raw, S.st(raw), L_to_end, nil), #raw, "group to the end")
S.eq(S.dump(tree), S.lines(
    "ur.p.threads @0+2 (Thread 0)",
    "  ur.p.label @1+1 = a",
    "ur.p.threads @2+3 (Thread 1)",
    "  ur.p.label @3+2 = bc"), "items sized after walking them")
tree = S.tree()
S.eq(walk(S.tvb("abc"), tree, 1, 3, S.st("abc"), { { k = "string", f = "ur.p.text", path = "text" } }, nil), 3, "string")
S.eq(S.dump(tree), "ur.p.text @1+2 = bc", "string to the end")
tree = S.tree()
S.eq(walk(S.tvb("abc"), tree, 3, 3, S.st("abc"), { { k = "bytes", f = "ur.p.raw", path = "raw" } }, nil), 3, "bytes")
S.eq(S.dump(tree), "ur.p.raw @3+0", "empty bytes still show")
-- A name whose entry in this version is narrower than its field (int16 bits of an int32
-- field, a float32 of a float64 field): the number is added explicitly, its bits read the range.
local L_narrow = {
    { k = "bits", f = "ur.p.inputs", n = 2, path = "inputs", signed = true, value = true, bits = { "ur.p.inputs.a" } },
    { k = "scalar", f = "ur.p.x", n = 4, path = "x", signed = false, value = true, float = true },
    { k = "array", f = "ur.p.ids", n = 1, count = 2, path = "ids", signed = true, value = true },
}
raw = S.bytes(0xff, 0xfe, 0x3f, 0xc0, 0, 0, 0xff, 2)
tree = S.tree()
S.eq(walk(S.tvb(raw), tree, 0, #raw, S.st(raw), L_narrow, nil), #raw, "narrow entries")
S.eq(S.dump(tree), S.lines(
    "ur.p.inputs @0+2 = -2",
    "  ur.p.inputs.a @0+2",
    "ur.p.x @2+4 = 1.5",
    "ur.p.ids @6+1 = -1",
    "ur.p.ids @7+1 = 2"), "explicit values in their own wire type")

-- An enum whose names depend on the version: the field's value string is the newest table;
-- another version's table names the item in its text.
local NEWEST, EARLY = { [240] = "READY_FOR_POWER_OFF" }, { [240] = "EMERGENCY_STOPPED" }
local NAMES = { newest = NEWEST, { high = 5000999, names = EARLY }, { low = 5001000, names = NEWEST } }
local L_mode = {
    { k = "scalar", f = "ur.p.joint_mode", n = 1, path = "joint_mode", signed = false, vs = NEWEST, tables = NAMES, label = "joint_mode" },
    { k = "array", f = "ur.p.modes", n = 1, count = 1, path = "modes", signed = false, tables = NAMES, label = "modes" },
}
raw = S.bytes(240, 7)
tree = S.tree()
walk(S.tvb(raw), tree, 0, #raw, S.st(raw, 3002000), L_mode, nil)
S.eq(S.dump(tree), S.lines(
    "ur.p.joint_mode @0+1 (joint_mode: EMERGENCY_STOPPED (240))",
    "ur.p.modes @1+1 (modes: Unknown (7))"), "names of an early version")
tree = S.tree()
walk(S.tvb(raw), tree, 0, #raw, S.st(raw, 5001000), L_mode, nil)
S.eq(S.dump(tree), S.lines(
    "ur.p.joint_mode @0+1",
    "ur.p.modes @1+1"), "the newest names: the field's own")

-- Plain scalars in a row are one run: added in one loop when they fit, else one by one, so
-- that the first that does not fit is named and those past the item cap are counted.
local L_run = {
    { k = "scalar", f = "ur.r.a", n = 2, path = "a", signed = false },
    { k = "scalar", f = "ur.r.b", n = 1, path = "b", signed = false },
    { k = "scalar", f = "ur.r.c", n = 4, path = "c", signed = false },
    { k = "array", f = "ur.r.d", n = 1, count = 3, path = "d", signed = false },
}
raw = S.bytes(0, 1, 2, 0, 0, 0, 3, 4, 5, 6)
tree = S.tree()
S.eq(walk(S.tvb(raw), tree, 0, #raw, S.st(raw), L_run, nil), 10, "a run and an array that fit")
S.eq(S.dump(tree), S.lines("ur.r.a @0+2", "ur.r.b @2+1", "ur.r.c @3+4", "ur.r.d @7+1", "ur.r.d @8+1", "ur.r.d @9+1"),
     "each at its offset")
tree = S.tree()
local o, err = walk(S.tvb(raw), tree, 0, 5, S.st(raw), L_run, "joints[1].")
S.eq(o, nil, "a run cut short")
S.eq(err, "joints[1].c at offset 3: needs 4 bytes, 2 left", "names its first field that does not fit")
S.eq(S.dump(tree), S.lines("ur.r.a @0+2", "ur.r.b @2+1"), "after the ones that fit")
o, err = walk(S.tvb(raw), S.tree(), 0, 8, S.st(raw), L_run, nil)
S.eq(err, "d[1] at offset 8: needs 1 bytes, 0 left", "an array cut short names its element")
local capped = S.walker_rt({ max_tree_items = 4 })
tree = S.tree()
capped.items_begin(tree)
S.eq(capped.walk(S.tvb(raw), tree, 0, #raw, S.st(raw), L_run, nil), 10, "past the item cap the fields are still walked")
S.eq(S.dump(tree), S.lines("ur.r.a @0+2", "ur.r.b @2+1", "ur.r.c @3+4", "ur.r.d @7+1"), "four shown")
S.eq(capped.items_hidden(), 2, "two counted")

-- Fields of a condition on the version alone join the run around them, for each version its
-- own steps; what is cut short is still named by its own path.
local L_gated = {
    { k = "scalar", f = "ur.g.a", n = 1, path = "a", signed = false },
    { k = "cond", low = 5010000, fields = {
        { k = "scalar", f = "ur.g.new", n = 2, path = "new", signed = false },
        { k = "array", f = "ur.g.pair", n = 1, count = 2, path = "pair", signed = false },
    } },
    { k = "scalar", f = "ur.g.b", n = 1, path = "b", signed = false },
}
raw = S.bytes(1, 0, 2, 3, 4, 5)
tree = S.tree()
S.eq(walk(S.tvb(raw), tree, 0, #raw, S.st(raw, 5010000), L_gated, nil), 6, "5.10: the gated fields in place")
S.eq(S.dump(tree), S.lines("ur.g.a @0+1", "ur.g.new @1+2", "ur.g.pair @3+1", "ur.g.pair @4+1", "ur.g.b @5+1"), "in wire order")
tree = S.tree()
S.eq(walk(S.tvb(raw), tree, 0, #raw, S.st(raw, 5009000), L_gated, nil), 2, "5.9: without them")
S.eq(S.dump(tree), S.lines("ur.g.a @0+1", "ur.g.b @1+1"), "the field after the condition follows the one before")
o, err = walk(S.tvb(raw), S.tree(), 0, 4, S.st(raw, 5010000), L_gated, "x.")
S.eq(err, "x.pair[1] at offset 4: needs 1 bytes, 0 left", "a gated array's element cut short")
o, err = walk(S.tvb(raw), S.tree(), 0, 1, S.st(raw, 5009000), L_gated, nil)
S.eq(err, "b at offset 1: needs 1 bytes, 0 left", "5.9 after the first field")
for v = 4000000, 6000000, 997 do walk(S.tvb(raw), S.tree(), 0, #raw, S.st(raw, v), L_gated, nil) end
S.eq(rt.step_lists(L_gated), 2, "steps made per span of versions (before 5.10, from it), not per version")

-- A float's unit follows its value ("Actual joint position: -0.42 rad"): Wireshark 4.0 shows no
-- unit string of a float field, so the walker appends it; plain, narrow, array and switch reads.
local L_units = {
    { k = "scalar", f = "ur.p.q", n = 4, path = "q", signed = false, unit = " rad" },
    { k = "scalar", f = "ur.p.t", n = 4, path = "t", signed = false, value = true, float = true, unit = " °C" },
    { k = "array", f = "ur.p.d", n = 1, count = 2, path = "d", signed = false, unit = " m" },
    { k = "scalar", f = "ur.p.sel", n = 1, path = "sel", signed = false, keep = "sel" },
    { k = "switch", sel = "sel", path = "sw", default = { f = "ur.p.sw", n = 1 }, cases = { [3] = { f = "ur.p.sw_f", n = 4, unit = " V" } } },
}
raw = S.bytes(0x3f, 0xc0, 0, 0, 0x3f, 0xc0, 0, 0, 1, 2, 3, 0x3f, 0xc0, 0, 0)
tree = S.tree()
S.eq(walk(S.tvb(raw), tree, 0, #raw, S.st(raw), L_units, nil), #raw, "units")
S.eq(S.dump(tree), S.lines(
    "ur.p.q @0+4 ( rad)",
    "ur.p.t @4+4 = 1.5 ( °C)",
    "ur.p.d @8+1 ( m)",
    "ur.p.d @9+1 ( m)",
    "ur.p.sel @10+1",
    "ur.p.sw_f @11+4 ( V)"), "each value followed by its unit")
print("ok")
