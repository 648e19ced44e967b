-- Messages: spec.messages holds one data table per message type, and its kind names the pair
-- of functions that dissect it: info (the Info column text, from the raw bytes; nil when `text`
-- is false, when no column is built) and tree (the fields under the message's item). Three kinds:
--   packages  a list of sub-packages, each framed by its own length (robot state);
--   subtypes  a header, then a subtype byte that chooses the layout of the rest (robot
--             messages, program-state messages);
--   body      one layout right after the message header (message types 5, 22, 23, 24).
local spec, rt = ...
local fmt, byte = string.format, string.byte
local be_int, walk, version_text = rt.be_int, rt.walk, rt.version_text
local choose, pick, enum_names, named_in_any, rename = rt.choose, rt.pick, rt.enum_names, rt.named_in_any, rt.rename
local layout_summary, package_summary, labelled = rt.layout_summary, rt.package_summary, rt.labelled
local X, E = rt.X, rt.E
local add, range_of = rt.add, rt.range_of
local HEADER = spec.header_size
local PACKAGE_HEADER = spec.package_header_size
local PACKAGE_LENGTH = spec.package_length_size

-- True when a filter, column or tap asks for a field of package pk (its data table). Asked once
-- per package kind per dissector call (st.call), not per field of every package.
local asked = {}
local function referenced(tree, pk, call)
    local a = asked[pk]
    if a and a.call == call then return a.yes end
    local yes, fields = false, pk.refs
    for i = 1, #fields do
        if tree:referenced(fields[i]) then yes = true; break end
    end
    if not a then a = {}; asked[pk] = a end
    a.call, a.yes = call, yes
    return yes
end

-- The body of a package or message from body to stop, walked with its layout for version v;
-- what cannot be read is kept raw, what is left over is shown as extra bytes, each with its
-- expert.
local function walk_body(tvb, item, body, stop, st, layout, name, v)
    local keep = st.version
    st.version = v
    local used, err = walk(tvb, item, body, stop, st, layout, nil)
    st.version = keep
    if not used then
        add(item, X.raw, range_of(tvb, body, stop - body))
        item:add_proto_expert_info(E.malformed, name .. ": " .. err)
    elseif used < stop then
        add(item, X.extra, range_of(tvb, used, stop - used))
        item:add_proto_expert_info(E.extra, fmt("%s: %d bytes after the layout", name, stop - used))
    end
end

-- A type or subtype code: its field, and under a version whose table names it otherwise, that
-- name. tables: the enum's tables by version, nil when its names do not depend on it.
local function add_code(tree, f, range, label, tables, v, code)
    local item = add(tree, f, range)
    if tables then rename(item, label, tables, v, code) end
    return item
end

-- The name of a code for version v, and whether the spec names it in any version.
local function code_name(names, tables, v, code)
    local name = (tables and enum_names(tables, v) or names)[code]
    return name, name ~= nil or (tables ~= nil and named_in_any(tables, code))
end

-- What the message was read with (st.message_version; see framing.lua): the version, and how it
-- was found when no Version message told it: from layout sizes (the versions of the form that
-- showed it), from the ur.version preference, or the default; each of these with a note.
local FROM_SIZES = setmetatable({}, { __index = function(t, versions)
    local text = versions .. " (from layout sizes)"
    t[versions] = text
    return text
end })
local function show_version(item, st)
    local v, implied = st.message_version, st.message_implied
    if implied then
        add(item, X.version, FROM_SIZES[implied]):set_generated()
    else
        add(item, X.version, version_text(v)):set_generated()
    end
    if st.announced then return end
    add(item, X.assumed, true):set_generated()
    if implied then
        item:add_proto_expert_info(E.assumed,
            fmt("no Version message seen on this stream: software %s, as the layout sizes show", implied))
    elseif st.from_pref then
        item:add_proto_expert_info(E.assumed, fmt("no Version message seen on this stream: assuming software %s \z
            (preference ur.version)", version_text(v)))
    else
        item:add_proto_expert_info(E.assumed, fmt("no Version message seen on this stream: assuming software %s \z
            (the default; preference ur.version)", version_text(v)))
    end
end

-- A form chosen by its length, not by the version: a note on its item.
local function note_length(item, form, length)
    item:add_proto_expert_info(E.by_length, fmt("laid out as software %s (chosen by length %d)", form.versions, length))
end

local KINDS = {}

-- One package of a robot state at p, of size bytes, its form chosen: its item, header and
-- fields. Without a tree shown, its fields are walked only when some are asked for.
local function package(m, tvb, tree, p, size, st, code, form, use, by_length)
    local pk = form and form.of
    local v = use or st.version
    local item = add(tree, pk and pk.item or X.unknown_package, range_of(tvb, p, size))
    local name, named = code_name(m.types, m.type_tables, v, code)
    if not pk then item:set_text(fmt("Unknown package %d (%s)", code, name or "not in the spec")) end
    add(item, m.length, range_of(tvb, p, PACKAGE_LENGTH))
    add_code(item, m.type, range_of(tvb, p + PACKAGE_LENGTH, PACKAGE_HEADER - PACKAGE_LENGTH), "Type", m.type_tables,
             v, code)
    if by_length then note_length(item, form, size) end
    local body, stop = p + PACKAGE_HEADER, p + size
    if pk and not st.visible and not referenced(item, pk, st.call) then
        -- No tree shown and no field of this package asked for: skip its fields.
    elseif pk then
        walk_body(tvb, item, body, stop, st, pk.layout, pk.name, use)
    else
        add(item, X.raw, range_of(tvb, body, stop - body))
        -- Types the spec names but does not lay out (e.g. 14) are normal: no expert.
        if not named then
            item:add_proto_expert_info(E.unknown, fmt("package type %d is not in the spec, kept raw", code))
        end
    end
end

-- m: { packages = { [type] = its forms, each of = { name, label, item, layout, summary, refs } },
-- types = value string of package types (type_tables: by version, when they depend on it),
-- length, type = the fields of a package header, needs_version }.
KINDS.packages = {
    info = function(m, tvb, raw, o, e, st, text)
        local summary = package_summary(tvb, raw, o + HEADER, e, m.packages, st, text)
        return text and labelled(m.label, summary) or nil
    end,
    tree = function(m, tvb, tree, o, e, st)
        if m.needs_version then show_version(tree, st) end
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
                add(tree, X.raw, range_of(tvb, p, left))
                tree:add_proto_expert_info(E.malformed, err)
                return
            end
            local code = byte(raw, p + PACKAGE_LENGTH + 1)
            local forms = m.packages[code]
            local form, use, by_length, pk
            if forms then
                form, use, by_length = pick(forms, size - PACKAGE_HEADER, st)
                pk = form.of
            end
            -- A tshark -T fields run that names no field of this package: not built at all
            -- (runtime/lua/packages/wanted.lua).
            if not (pk and st.only and not st.only[pk]) then
                package(m, tvb, tree, p, size, st, code, form, use, by_length)
            end
            p = p + size
        end
    end,
}

-- m: { header = layout of the header and subtype, body_offset = where the body starts (the
-- subtype is the byte before it), subtype_field, subtype_names = value string of subtypes
-- (subtype_tables: by version, when they depend on it), subtypes = { [subtype] = its forms,
-- each of = { name, label, item, header, layout, needs_version } } }.
KINDS.subtypes = {
    info = function(m, tvb, raw, o, e, st, text)
        if not text then return nil end
        if e - o < m.body_offset then return m.label .. " (too short)" end
        local code = byte(raw, o + m.body_offset)
        local forms = m.subtypes[code]
        if not forms then return fmt("%s subtype %d", m.label, code) end
        local form, use = choose(forms, e - o - m.body_offset, st.version)
        return labelled(form.of.label, layout_summary(tvb, raw, o + m.body_offset, e, form.of.layout, use))
    end,
    tree = function(m, tvb, tree, o, e, st)
        local body = o + m.body_offset
        if e < body then
            local _, err = walk(tvb, tree, o + HEADER, e, st, m.header, nil)
            if e - o > HEADER then add(tree, X.raw, range_of(tvb, o + HEADER, e - o - HEADER)) end
            tree:add_proto_expert_info(E.malformed, err or "too short")
            return
        end
        local code = byte(st.raw, body)
        local forms = m.subtypes[code]
        if not forms then
            walk(tvb, tree, o + HEADER, body, st, m.header, nil)
            if body < e then add(tree, X.raw, range_of(tvb, body, e - body)) end
            local _, named = code_name(m.subtype_names, m.subtype_tables, st.version, code)
            if not named then
                tree:add_proto_expert_info(E.unknown,
                    fmt("%s subtype %d is not in the spec, kept raw", string.lower(m.label), code))
            end
            return
        end
        local form, use, by_length = choose(forms, e - body, st.version)
        local s = form.of
        local item = add(tree, s.item, range_of(tvb, o + HEADER, e - o - HEADER))
        -- The header again, under the subtype's own names (ur.key.timestamp).
        walk(tvb, item, o + HEADER, body - 1, st, s.header, nil)
        add_code(item, m.subtype_field, range_of(tvb, body - 1, 1), m.subtype_label, m.subtype_tables, use, code)
        if by_length then note_length(item, form, e - o) end
        if s.needs_version then show_version(item, st) end
        walk_body(tvb, item, body, e, st, s.layout, s.name, use)
        return item   -- where the subtype's fields are
    end,
}

-- m: { code = the message type, also the one code of forms; body_offset = where the layout
-- starts; forms = { [code] = its forms, each of = { name, label, item, layout, needs_version } } }.
KINDS.body = {
    info = function(m, tvb, raw, o, e, st, text)
        if not text then return nil end
        local form, use = choose(m.forms[m.code], e - o - m.body_offset, st.version)
        return labelled(form.of.label, layout_summary(tvb, raw, o + m.body_offset, e, form.of.layout, use))
    end,
    tree = function(m, tvb, tree, o, e, st)
        local body = o + m.body_offset
        local form, use, by_length = choose(m.forms[m.code], e - body, st.version)
        local s = form.of
        local item = add(tree, s.item, range_of(tvb, body, e - body))
        if by_length then note_length(item, form, e - o) end
        if s.needs_version then show_version(item, st) end
        walk_body(tvb, item, body, e, st, s.layout, s.name, use)
        return item   -- where the layout's fields are
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
