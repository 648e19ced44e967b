-- Typed values of global variables: a type byte, then its data, nested for LIST and MATRIX.
-- The meaning of a type byte depends on the software version (spec.value_tables: one table
-- per version range). Adds the descriptor kind "values" to the walker.
local spec, rt = ...
local fmt, byte = string.format, string.byte
local be_int, short, negative = rt.be_int, rt.short, rt.negative
local value_table, add_text = rt.value_table, rt.add_text
local add, add_value, add_labelled, range_of = rt.add, rt.add_value, rt.add_labelled, rt.range_of

local MAX_VALUE_DEPTH = spec.max_value_depth
local VALUE_TABLES = spec.value_tables

-- Items that cannot fit in the bytes from o to e (each takes at least vt.min_size) are refused
-- before any is read; at is the offset of their count. Returns the error text, or nil.
local function too_many(st, vt, path, at, items, o, e)
    if items * vt.min_size > e - o then
        return fmt("%s at offset %d: %d items need more than the %d bytes left", path, at - st.base, items, e - o)
    end
end

-- One typed value at o, under tree; vf holds the fields values are shown with, vt the
-- version's value types; label is what its item reads ("Variable 2", "Item 0"), path names it in
-- errors ("variables[2][0]"). Returns the offset after it, or nil and the canonical error text.
local function walk_value(tvb, tree, o, e, st, vf, vt, label, path, depth)
    local raw = st.raw
    if o >= e then return nil, short(st, path .. ".type", o, 1, e) end
    local code = byte(raw, o + 1)
    if depth > MAX_VALUE_DEPTH then
        return nil, fmt("%s at offset %d: nesting deeper than %d", path, o - st.base, MAX_VALUE_DEPTH)
    end
    local kind = vt.kinds[code]
    if not kind then return nil, fmt("%s.type at offset %d: unknown value type %d", path, o - st.base, code) end
    local start = o
    local code_range = range_of(tvb, o, 1)
    local item = add_labelled(tree, vf.item, code_range, label .. ": " .. kind.name)
    add_value(item, vf.type, code_range, kind.name)
    add(item, vf.code, code_range)
    o = o + 1
    local layout = kind.layout
    if layout == "scalar" or layout == "array" then
        local need = kind.n * kind.count
        if o + need > e then return nil, short(st, path, o, need, e) end
        for _ = 1, kind.count do
            add(item, vf[kind.item], range_of(tvb, o, kind.n))
            o = o + kind.n
        end
    elseif layout == "string" then
        if o + kind.len > e then return nil, short(st, path, o, kind.len, e) end
        local n = be_int(raw, o, kind.len)
        if n < 0 then return nil, negative(st, path, o, n) end
        add(item, vf.count, range_of(tvb, o, kind.len))
        o = o + kind.len
        if o + n > e then return nil, short(st, path, o, n, e) end
        add_text(item, vf.string, tvb, o, n)
        o = o + n
    elseif layout == "list" then
        if o + kind.len > e then return nil, short(st, path, o, kind.len, e) end
        local n = be_int(raw, o, kind.len)
        if n < 0 then return nil, negative(st, path, o, n) end
        local err = too_many(st, vt, path, o, n, o + kind.len, e)
        if err then return nil, err end
        add(item, vf.count, range_of(tvb, o, kind.len))
        o = o + kind.len
        for i = 0, n - 1 do
            o, err = walk_value(tvb, item, o, e, st, vf, vt, "Item " .. i, path .. "[" .. i .. "]", depth + 1)
            if not o then return nil, err end
        end
    elseif layout == "matrix" then
        if o + 2 * kind.len > e then return nil, short(st, path, o, 2 * kind.len, e) end
        local rows, cols = be_int(raw, o, kind.len), be_int(raw, o + kind.len, kind.len)
        if rows < 0 then return nil, negative(st, path, o, rows) end
        if cols < 0 then return nil, negative(st, path, o + kind.len, cols) end
        -- Rows of no items would take no bytes at all: any number of them fits in none.
        if rows > 0 and cols == 0 then
            return nil, fmt("%s at offset %d: %d rows of 0 columns", path, o - st.base, rows)
        end
        local err = too_many(st, vt, path, o, rows * cols, o + 2 * kind.len, e)
        if err then return nil, err end
        add(item, vf.rows, range_of(tvb, o, kind.len))
        add(item, vf.cols, range_of(tvb, o + kind.len, kind.len))
        o = o + 2 * kind.len
        for r = 0, rows - 1 do
            local row = add_labelled(item, vf.row, range_of(tvb, o, 0), fmt("Row %d", r))
            local row_start = o
            for c = 0, cols - 1 do
                o, err = walk_value(tvb, row, o, e, st, vf, vt, "Column " .. c, path .. "[" .. r .. "][" .. c .. "]",
                                    depth + 1)
                if not o then return nil, err end
            end
            row:set_len(o - row_start)
        end
    end
    item:set_len(o - start)
    return o
end

-- Typed values, each followed by a terminator, to the end of the layout.
function rt.KIND.values(tvb, tree, o, e, st, d, pre)
    local vt = value_table(VALUE_TABLES, st.version)
    local i = 0
    while o < e do
        local path = fmt("%s%s[%d]", pre or "", d.path, i)
        local err
        o, err = walk_value(tvb, tree, o, e, st, d.vf, vt, fmt("%s %d", d.label, i), path, 1)
        if not o then return nil, err end
        if o >= e then return nil, short(st, path, o, 1, e) end
        local b = byte(st.raw, o + 1)
        if b ~= d.term then
            return nil, fmt("%s at offset %d: expected terminator 0x%02x, found 0x%02x", path, o - st.base, d.term, b)
        end
        o = o + 1
        i = i + 1
    end
    return o
end

rt.walk_value = walk_value
