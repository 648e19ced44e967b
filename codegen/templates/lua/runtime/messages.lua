-- Messages: spec.messages holds one data table per message type, and its kind names the pair
-- of functions that dissect it: info (the Info column text, from the raw bytes) and tree (the
-- fields under the message's item). Two kinds:
--   packages  a list of sub-packages, each framed by its own length (robot state);
--   subtypes  a header, then a subtype byte that chooses the layout of the rest (robot
--             messages, program-state messages).
local spec, rt = ...
local fmt, byte = string.format, string.byte
local be_int, walk, version_text = rt.be_int, rt.walk, rt.version_text
local layout_summary, package_summary, labelled = rt.layout_summary, rt.package_summary, rt.labelled
local X, E = rt.X, rt.E
local HEADER = spec.header_size
local PACKAGE_HEADER = spec.package_header_size
local PACKAGE_LENGTH = spec.package_length_size

-- True when a filter, column or tap asks for one of these fields.
local function referenced(tree, fields)
    for _, f in ipairs(fields) do
        if tree:referenced(f) then return true end
    end
    return false
end

-- The body of a package or message from body to stop, walked with its layout; what cannot be
-- read is kept raw, what is left over is shown as extra bytes, each with its expert.
local function walk_body(tvb, item, body, stop, st, layout, name)
    local used, err = walk(tvb, item, body, stop, st, layout, nil)
    if not used then
        item:add(X.raw, tvb(body, stop - body))
        item:add_proto_expert_info(E.malformed, name .. ": " .. err)
    elseif used < stop then
        item:add(X.extra, tvb(used, stop - used))
        item:add_proto_expert_info(E.extra, fmt("%s: %d bytes after the layout", name, stop - used))
    end
end

local KINDS = {}

-- m: { packages = { [type] = { name, item, layout, info, refs } }, types = value string of
-- package types, length, type = the fields of a package header }.
KINDS.packages = {
    info = function(m, tvb, raw, o, e)
        return labelled(m.label, package_summary(raw, o + HEADER, e, m.packages))
    end,
    tree = function(m, tvb, tree, o, e, st)
        local raw = st.raw
        local p = o + HEADER
        while p < e do
            local left = e - p
            local err
            local size = left >= PACKAGE_HEADER and be_int(raw, p, PACKAGE_LENGTH) or 0
            if left < PACKAGE_HEADER then
                err = fmt("package at offset %d: needs %d bytes, %d left", p - st.base, PACKAGE_HEADER, left)
            elseif size < PACKAGE_HEADER then
                err = fmt("package at offset %d: length %d is below %d", p - st.base, size, PACKAGE_HEADER)
            elseif size > left then
                err = fmt("package at offset %d: length %d exceeds the %d bytes left", p - st.base, size, left)
            end
            if err then
                tree:add(X.raw, tvb(p, left))
                tree:add_proto_expert_info(E.malformed, err)
                return
            end
            local code = byte(raw, p + PACKAGE_LENGTH + 1)
            local pk = m.packages[code]
            local item = tree:add(pk and pk.item or X.unknown_package, tvb(p, size))
            if not pk then item:set_text(fmt("Unknown package %d (%s)", code, m.types[code] or "not in the spec")) end
            item:add(m.length, tvb(p, PACKAGE_LENGTH))
            item:add(m.type, tvb(p + PACKAGE_LENGTH, PACKAGE_HEADER - PACKAGE_LENGTH))
            local body, stop = p + PACKAGE_HEADER, p + size
            if pk and not st.visible and not referenced(item, pk.refs) then
                -- No tree shown and no field of this package asked for: skip its fields.
            elseif pk then
                walk_body(tvb, item, body, stop, st, pk.layout, pk.name)
            else
                item:add(X.raw, tvb(body, stop - body))
                -- Types the spec names but does not lay out (e.g. 14) are normal: no expert.
                if not m.types[code] then
                    item:add_proto_expert_info(E.unknown, fmt("package type %d is not in the spec, kept raw", code))
                end
            end
            p = stop
        end
    end,
}

-- m: { header = layout of the header and subtype, body_offset = where the body starts (the
-- subtype is the byte before it), subtype_field, subtype_names = value string of subtypes,
-- subtypes = { [subtype] = { name, label, item, header, layout, needs_version } } }.
KINDS.subtypes = {
    info = function(m, tvb, raw, o, e)
        if e - o < m.body_offset then return m.label .. " (too short)" end
        local code = byte(raw, o + m.body_offset)
        local s = m.subtypes[code]
        if not s then return fmt("%s subtype %d", m.label, code) end
        return labelled(s.label, layout_summary(tvb, raw, o + m.body_offset, e, s.layout))
    end,
    tree = function(m, tvb, tree, o, e, st)
        local body = o + m.body_offset
        if e < body then
            local _, err = walk(tvb, tree, o + HEADER, e, st, m.header, nil)
            if e - o > HEADER then tree:add(X.raw, tvb(o + HEADER, e - o - HEADER)) end
            tree:add_proto_expert_info(E.malformed, err or "too short")
            return
        end
        local code = byte(st.raw, body)
        local s = m.subtypes[code]
        if not s then
            walk(tvb, tree, o + HEADER, body, st, m.header, nil)
            if body < e then tree:add(X.raw, tvb(body, e - body)) end
            if not m.subtype_names[code] then
                tree:add_proto_expert_info(E.unknown, fmt("%s subtype %d is not in the spec, kept raw", string.lower(m.label), code))
            end
            return
        end
        local item = tree:add(s.item, tvb(o + HEADER, e - o - HEADER))
        -- The header again, under the subtype's own names (ur.key.timestamp).
        walk(tvb, item, o + HEADER, body - 1, st, s.header, nil)
        item:add(m.subtype_field, tvb(body - 1, 1))
        if s.needs_version then
            item:add(X.version, version_text(st.version)):set_generated()
            if st.assumed then
                item:add(X.assumed, true):set_generated()
                item:add_proto_expert_info(E.assumed, fmt("no Version message seen on this stream: assuming software %s (preference ur.version)", version_text(st.version)))
            end
        end
        walk_body(tvb, item, body, e, st, s.layout, s.name)
    end,
}

-- One handler per message type, made at load time: its data, its kind's functions, and the
-- text appended to the message's item.
local handlers = {}
for code, m in pairs(spec.messages) do
    local kind = KINDS[m.kind]
    if not kind then error(fmt("urwire: message type %d has an unknown kind %s", code, tostring(m.kind))) end
    handlers[code] = { m = m, info = kind.info, tree = kind.tree, suffix = ", " .. m.label }
end

rt.KINDS, rt.handlers, rt.walk_body = KINDS, handlers, walk_body
