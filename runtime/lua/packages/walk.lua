-- The generic walk of a layout: a list of field descriptors in wire order ({ k = "scalar",
-- f = <ProtoField>, n = 8, path = "timestamp", ... }), each added to the tree by the function
-- KIND[d.k]. st is the message being dissected: its raw bytes (raw), its first byte (base, for
-- error offsets) and its software version. Offsets are tvb offsets; o is where a field starts
-- and e where the layout ends. Every KIND function returns the offset after the field, or nil
-- and the canonical error text. values.lua adds KIND.values.
-- A scalar descriptor may carry: `value` (its wire type is narrower than its field's, which
-- another version's entry of the same name gives: the number is added explicitly; `float` when
-- it is a float), `tables` and `label` (its enum's names depend on the version), `unit` (the
-- text after a float's value, " rad": Wireshark 4.0 shows no unit string of a float field).
local spec, rt = ...
local fmt, byte = string.format, string.byte
local be_uint, be_int, short, negative = rt.be_uint, rt.be_int, rt.short, rt.negative
local version_in, enum_names = rt.version_in, rt.enum_names
local add, add_value, add_field, room = rt.add, rt.add_value, rt.add_field, rt.room
local tree_add, append_text, range_of, add_labelled = rt.tree_add, rt.append_text, rt.range_of, rt.add_labelled

local kept = {}   -- values of earlier fields that later ones depend on (present_if, switch)
local walk

-- A text field; a zero-length one still shows, at its offset.
local function add_text(tree, f, tvb, o, n)
    return add_field(tree, f, range_of(tvb, o, n), ENC_UTF_8)
end

-- The number of a scalar descriptor at o (range is tvb(o, d.n)), in its own wire type.
local function number_at(range, raw, o, d)
    if d.float then return range:float() end
    if d.signed then return be_int(raw, o, d.n) end
    return be_uint(raw, o, d.n)
end

-- An enum item whose names depend on the software version v: its field shows the newest
-- table's name; under another version's table the item says that table's name instead.
local function rename(item, label, tables, v, value)
    local names = enum_names(tables, v)
    if names ~= tables.newest then
        item:set_text(fmt("%s: %s (%d)", label, names[value] or "Unknown", value))
    end
end

-- One scalar into the tree: explicitly when its wire type is narrower than its field's, named
-- by the version when its enum needs it, its unit after it. Its item, and its number when it
-- was read.
local function add_scalar(tree, range, o, st, d)
    if not (d.value or d.tables or d.keep) then
        local item = add(tree, d.f, range)
        if d.unit then item:append_text(d.unit) end
        return item, nil
    end
    local v = number_at(range, st.raw, o, d)
    local item
    if d.value then item = add_value(tree, d.f, range, v) else item = add(tree, d.f, range) end
    if d.tables then rename(item, d.label, d.tables, st.version, v) end
    if d.unit then item:append_text(d.unit) end
    return item, v
end

local KIND = {}

-- A scalar (integer, float or bool); kept when a later field depends on it.
function KIND.scalar(tvb, tree, o, e, st, d, pre)
    if o + d.n > e then return nil, short(st, (pre or "") .. d.path, o, d.n, e) end
    local _, v = add_scalar(tree, range_of(tvb, o, d.n), o, st, d)
    if d.keep then kept[d.keep] = v end
    return o + d.n
end

-- An integer whose bits are shown one by one.
function KIND.bits(tvb, tree, o, e, st, d, pre)
    if o + d.n > e then return nil, short(st, (pre or "") .. d.path, o, d.n, e) end
    local range = range_of(tvb, o, d.n)
    -- The bits read the range itself (a narrower range holds the low bits).
    local item = add_scalar(tree, range, o, st, d)
    local bits = d.bits
    if room(#bits) then
        for i = 1, #bits do tree_add(item, bits[i], range) end
    else
        for i = 1, #bits do add(item, bits[i], range) end
    end
    return o + d.n
end

-- count scalars in a row.
function KIND.array(tvb, tree, o, e, st, d, pre)
    local n, count = d.n, d.count
    if not (d.value or d.tables) and o + n * count <= e and room(count) then
        local f, unit = d.f, d.unit
        for _ = 1, count do
            local item = tree_add(tree, f, range_of(tvb, o, n))
            if unit then append_text(item, unit) end
            o = o + n
        end
        return o
    end
    for i = 0, count - 1 do
        if o + d.n > e then return nil, short(st, fmt("%s%s[%d]", pre or "", d.path, i), o, d.n, e) end
        add_scalar(tree, range_of(tvb, o, d.n), o, st, d)
        o = o + d.n
    end
    return o
end

-- Labels ("Joint 0") and error paths ("joints[0].") of group items, made once and kept.
local labels, prefixes = {}, {}
local function item_names(d, pre, i)
    local l = labels[d]
    if not l then l = {}; labels[d] = l end
    local label = l[i]
    if not label then label = fmt("%s %d", d.label, i); l[i] = label end
    if pre then return label, fmt("%s%s[%d].", pre, d.path, i) end
    local p = prefixes[d]
    if not p then p = {}; prefixes[d] = p end
    local prefix = p[i]
    if not prefix then prefix = fmt("%s[%d].", d.path, i); p[i] = prefix end
    return label, prefix
end

-- A repeated group ("Joint 0".."Joint 5"), count times or to the end of the layout.
function KIND.group(tvb, tree, o, e, st, d, pre)
    local i, count, size = 0, d.count, d.size
    while (count and i < count) or (not count and o < e) do
        local start = o
        local fits = size and o + size <= e
        local label, prefix = item_names(d, pre, i)
        local item = add_labelled(tree, d.f, range_of(tvb, o, fits and size or 0), label)
        local err
        o, err = walk(tvb, item, o, e, st, d.item, prefix)
        if not o then
            item:set_len(e - start)
            return nil, err
        end
        if not fits then item:set_len(o - start) end
        i = i + 1
    end
    return o
end

-- A text with a length prefix.
function KIND.pstring(tvb, tree, o, e, st, d, pre)
    local path = (pre or "") .. d.path
    if o + d.n > e then return nil, short(st, path, o, d.n, e) end
    local n = d.signed and be_int(st.raw, o, d.n) or be_uint(st.raw, o, d.n)
    if n < 0 then return nil, negative(st, path, o, n) end
    o = o + d.n
    if o + n > e then return nil, short(st, path, o, n, e) end
    add_text(tree, d.f, tvb, o, n)
    return o + n
end

-- A text running to the end of the layout, with no terminator.
function KIND.string(tvb, tree, o, e, st, d)
    add_text(tree, d.f, tvb, o, e - o)
    return e
end

-- Opaque bytes to the end of the layout.
function KIND.bytes(tvb, tree, o, e, st, d)
    add(tree, d.f, range_of(tvb, o, e - o))
    return e
end

-- Texts each ended by a terminator; bytes after the last terminator are extra.
function KIND.strings(tvb, tree, o, e, st, d)
    local raw, start = st.raw, o
    for i = o, e - 1 do
        if byte(raw, i + 1) == d.term then
            add_text(tree, d.f, tvb, start, i - start)
            start = i + 1
        end
    end
    return start
end

-- One scalar whose type follows an earlier field.
function KIND.switch(tvb, tree, o, e, st, d, pre)
    local c = d.cases[kept[d.sel]] or d.default
    if o + c.n > e then return nil, short(st, (pre or "") .. d.path, o, c.n, e) end
    local item = add(tree, c.f, range_of(tvb, o, c.n))
    if c.unit then item:append_text(c.unit) end
    return o + c.n
end

-- Fields present only when an earlier field is nonzero, or for some software versions.
function KIND.cond(tvb, tree, o, e, st, d, pre)
    if d.present_if and (kept[d.present_if] or 0) == 0 then return o end
    if not version_in(st.version, d.low, d.high) then return o end
    return walk(tvb, tree, o, e, st, d.fields, pre)
end

-- Scalars added as they are (no explicit value, no names by version, not kept) that follow
-- one another: one step, a run, with one bounds check and one count of tree items.
function KIND.run(tvb, tree, o, e, st, d, pre)
    local fields, sizes, units, count = d.fields, d.sizes, d.units, d.count
    if o + d.size <= e and room(count) then
        for j = 1, count do
            local n = sizes[j]
            local item = tree_add(tree, fields[j], range_of(tvb, o, n))
            if units[j] then append_text(item, units[j]) end
            o = o + n
        end
        return o
    end
    -- One by one: the first that does not fit is named; past the item cap they are counted.
    local scalars = d.scalars
    for j = 1, count do
        local err
        o, err = KIND.scalar(tvb, tree, o, e, st, scalars[j], pre)
        if not o then return nil, err end
    end
    return o
end

-- One element of a plain array as a scalar of its own (its path "name[i]"), to join a run.
local elements_of = {}
local function element(d, i)
    local list = elements_of[d]
    if not list then list = {}; elements_of[d] = list end
    local x = list[i]
    if not x then
        x = { k = "scalar", f = d.f, n = d.n, path = fmt("%s[%d]", d.path, i), signed = d.signed, unit = d.unit }
        list[i] = x
    end
    return x
end

-- A layout's steps for software version v: its descriptors with the fields of the conditions
-- on the version alone put in place (or left out), and runs of plain scalars and plain arrays'
-- elements joined, across those conditions too (a robot state walked some 40 runs of 4 fields,
-- 25 conditions and 9 arrays in 45 calls of walk without it).
local function steps(layout, v)
    local out, run = {}, nil
    local function join(d)
        if not run then
            run = { k = "run", fields = {}, sizes = {}, units = {}, scalars = {}, size = 0, count = 0 }
            out[#out + 1] = run
        end
        local j = run.count + 1
        run.count, run.fields[j], run.sizes[j], run.scalars[j] = j, d.f, d.n, d
        run.units[j] = d.unit or false
        run.size = run.size + d.n
    end
    local function put(list)
        for i = 1, #list do
            local d = list[i]
            if d.k == "scalar" and not (d.value or d.tables or d.keep) then
                join(d)
            elseif d.k == "array" and not (d.value or d.tables) then
                for j = 0, d.count - 1 do join(element(d, j)) end
            elseif d.k == "cond" and not d.present_if then
                if version_in(v, d.low, d.high) then put(d.fields) end
            else
                run = nil
                out[#out + 1] = d
            end
        end
    end
    put(layout)
    return out
end

-- Where a layout's steps change with the version: the bounds of its conditions on the version
-- alone (a low bound, and the version after a high one), sorted.
local function bounds_of(layout)
    local set, list = {}, {}
    local function collect(descriptors)
        for i = 1, #descriptors do
            local d = descriptors[i]
            if d.k == "cond" and not d.present_if then
                if d.low then set[d.low] = true end
                if d.high then set[d.high + 1] = true end
                collect(d.fields)
            end
        end
    end
    collect(layout)
    for b in pairs(set) do list[#list + 1] = b end
    table.sort(list)
    return list
end

-- The steps of each layout, made once per span of versions between its bounds (a stream's
-- Version message may announce any number: the spans are the spec's), and the last version
-- asked for with its steps.
local plans = {}
local function steps_for(layout, v)
    local plan = plans[layout]
    if not plan then
        plan = { bounds = bounds_of(layout), by_span = {} }
        plans[layout] = plan
    end
    if plan.v == v then return plan.last end
    local bounds, span = plan.bounds, 1
    while bounds[span] and bounds[span] <= v do span = span + 1 end
    local found = plan.by_span[span]
    if not found then
        found = steps(layout, v)
        plan.by_span[span] = found
    end
    plan.v, plan.last = v, found
    return found
end

-- Walk a layout from o to at most e: the offset after it, or nil and the canonical error text.
-- pre is the error path of the enclosing group item ("joints[2]."), nil at the top.
walk = function(tvb, tree, o, e, st, layout, pre)
    layout = steps_for(layout, st.version)
    for i = 1, #layout do
        local d = layout[i]
        local err
        o, err = KIND[d.k](tvb, tree, o, e, st, d, pre)
        if not o then return nil, err end
    end
    return o
end

-- How many step lists a layout keeps (for tests: one per span of versions, not per version).
local function step_lists(layout)
    local n = 0
    for _ in pairs(plans[layout] and plans[layout].by_span or {}) do n = n + 1 end
    return n
end

rt.KIND, rt.walk, rt.add_text, rt.rename, rt.step_lists = KIND, walk, add_text, rename, step_lists
