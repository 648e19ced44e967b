-- runtime/lua/packages/items.lua: a message's tree shows at most max_tree_items items; the rest are
-- counted.
local S = dofile("stubs.lua")
local rt = S.load("packages/items.lua", { max_tree_items = 3 })
local range = S.tvb("abcdef")(0, 2)

local top = S.tree()
top.asked["ur.a.x"] = true
rt.items_begin(top)
local a = rt.add(top, "ur.a", range)
rt.add_value(a, "ur.a.x", range, 7)
rt.add_field(a, "ur.a.s", range, ENC_UTF_8)
S.eq(rt.items_hidden(), 0, "three items fit")
local past = rt.add(a, "ur.a.y", range)
past:set_text("y"); past:set_len(1); past:append_text("!")
S.eq(past:set_generated(), past, "an item past the cap takes every call")
rt.add(past, "ur.a.y.z", range)
past:add("ur.a.y.w", range)
rt.add_value(top, "ur.b", range, 1)
S.eq(rt.items_hidden(), 4, "each item past the cap is counted, nested ones too")
S.eq(past:referenced("ur.a.x"), true, "what a filter asks for is still known")
past:add_proto_expert_info("malformed", "a.y at offset 9: needs 4 bytes, 1 left")
past:add_proto_expert_info("malformed", "another")
S.eq(S.lines(S.dump(top)), S.lines(
    "!malformed: a.y at offset 9: needs 4 bytes, 1 left",
    "ur.a @0+2",
    "  ur.a.x @0+2 = 7",
    "  ur.a.s @0+2 = ab"), "the first three items, and the first expert past the cap on the message")
S.eq(rt.items_hidden(), 5, "a second expert past the cap is counted with the items")

-- The next message starts with the whole cap.
local next_top = S.tree()
rt.items_begin(next_top)
S.eq(rt.items_hidden(), 0, "nothing hidden yet")
rt.add(next_top, "ur.c", range)
S.eq(#next_top.children, 1, "shown")

-- add_labelled: an item with its text, counted like the others.
rt.items_begin(S.tree())
local labelled = rt.add_labelled(S.tree(), "ur.g", range, "Joint 0")
S.eq(labelled.text, "Joint 0", "the text set")
rt.add(S.tree(), "ur.h", range); rt.add(S.tree(), "ur.i", range)
local over = rt.add_labelled(S.tree(), "ur.g", range, "Joint 1")
S.eq(over.text, nil, "past the cap: nothing to label")
S.eq(rt.items_hidden(), 1, "and counted")

-- room(k): k items counted at once when they all fit, none when they do not.
rt.items_begin(S.tree())
S.eq(rt.room(2), true, "two of three fit")
S.eq(rt.room(2), false, "two more do not")
S.eq(rt.items_hidden(), 0, "and are not counted as hidden: they go one by one")
S.eq(rt.add(S.tree(), "ur.d", range) ~= nil, true, "the last one still fits")
S.eq(rt.room(1), false, "then none")
-- A Wireshark without the class tables: the methods are called by name.
local classes = { TreeItem, Tvb }
TreeItem, Tvb = nil, nil
local by_name = S.load("packages/items.lua", { max_tree_items = 3 })
TreeItem, Tvb = classes[1], classes[2]
local root = S.tree()
by_name.items_begin(root)
local item = by_name.add(root, "ur.n", by_name.range_of(S.tvb("abcdef"), 1, 2))
by_name.append_text(item, " rad")
S.eq(S.dump(root), "ur.n @1+2 ( rad)", "added, ranged and appended by name")
print("ok")
