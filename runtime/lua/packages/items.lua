-- The tree items of one message: at most spec.max_tree_items under the message's item. A
-- message of a megabyte can hold hundreds of thousands of values; Wireshark slows down long
-- before it stops at a million items per packet, which would end the dissection with an error.
-- Past the cap the fields are still walked, so that errors are still found, but they go to
-- HIDDEN, an item that shows nothing and counts what is added to it; the first expert info it
-- is given goes to the message's item, so that a malformed message still reads as one.
local spec, rt = ...
local MAX_TREE_ITEMS = spec.max_tree_items

-- The TreeItem and Tvb methods called for every field, taken once from their class tables: a
-- method call on a Wireshark object (tree:add(f, tvb(o, n))) first asks the object's __index, a
-- C function, for the method: up to a tenth of a field's time under tshark -V (one with a unit).
-- Where a Wireshark has no class table, the method is called by name.
local function method(class, name)
    local f = class and class[name]
    if f then return f end
    return function(object, ...) return object[name](object, ...) end
end
local tree_add, append_text, set_text =
    method(TreeItem, "add"), method(TreeItem, "append_text"), method(TreeItem, "set_text")
local range_of = method(Tvb, "range")   -- range_of(tvb, o, n) is tvb(o, n)

local left, hidden, top, expert_moved = MAX_TREE_ITEMS, 0, nil, false

local HIDDEN = {}
function HIDDEN:add() hidden = hidden + 1; return HIDDEN end
HIDDEN.add_packet_field = HIDDEN.add
function HIDDEN:set_text() end
HIDDEN.append_text, HIDDEN.set_len = HIDDEN.set_text, HIDDEN.set_text
function HIDDEN:set_generated() return HIDDEN end
function HIDDEN:referenced(f) return top:referenced(f) end
function HIDDEN:add_proto_expert_info(e, text)
    if expert_moved then hidden = hidden + 1; return end
    expert_moved = true
    top:add_proto_expert_info(e, text)
end

-- A message's tree starts under item: the whole cap is left.
local function items_begin(item)
    left, hidden, top, expert_moved = MAX_TREE_ITEMS, 0, item, false
end

-- How many items the message's tree did not show.
local function items_hidden()
    return hidden
end

-- tree:add(f, a), where a is a range, or the value of a generated item; counted.
local function add(tree, f, a)
    if left > 0 then
        left = left - 1
        return tree_add(tree, f, a)
    end
    hidden = hidden + 1
    return HIDDEN
end

-- tree:add(f, range, value); counted.
local function add_value(tree, f, range, value)
    if left > 0 then
        left = left - 1
        return tree_add(tree, f, range, value)
    end
    hidden = hidden + 1
    return HIDDEN
end

-- tree:add_packet_field(f, range, encoding); counted.
local function add_field(tree, f, range, encoding)
    if left > 0 then
        left = left - 1
        return tree:add_packet_field(f, range, encoding)
    end
    hidden = hidden + 1
    return HIDDEN
end

-- tree:add(f, range) with its text set (a group's "Joint 0"); counted.
local function add_labelled(tree, f, range, label)
    if left > 0 then
        left = left - 1
        local item = tree_add(tree, f, range)
        set_text(item, label)
        return item
    end
    hidden = hidden + 1
    return HIDDEN
end

-- Whether k more items fit under the cap: then they are counted, and added with tree_add
-- directly (a run of fields in one loop).
local function room(k)
    if left >= k then
        left = left - k
        return true
    end
    return false
end

rt.items_begin, rt.items_hidden, rt.MAX_TREE_ITEMS = items_begin, items_hidden, MAX_TREE_ITEMS
rt.add, rt.add_value, rt.add_field, rt.add_labelled, rt.room = add, add_value, add_field, add_labelled, room
rt.tree_add, rt.append_text, rt.range_of = tree_add, append_text, range_of
