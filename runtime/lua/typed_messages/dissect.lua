-- The RTDE dissector: frames the messages of a TCP stream, shows each by its layout (the spec's
-- MESSAGES, chosen by type code, direction and the protocol version in force), a data package's
-- values by the names of its recipe with a link to the frame that set the recipe up, each reply
-- linked with its request both ways (runtime/lua/typed_messages/exchanges.lua), and expert
-- infos for refused setups, unknown recipes, a refused start and bad framing. State is kept per
-- conversation (both addresses and both ports) on the first pass, and each message's view of it
-- is kept for later passes and the GUI (runtime/lua/typed_messages/state.lua holds the state itself).
local spec, rt = ...
local proto, F = spec.proto, spec.F
local HEADER = spec.header_size
local be_uint = rt.be_uint
local PREFIX = spec.name .. "."             -- every field's filter name starts so: rtde.actual_q
local wanted_names, wanted_entries = rt.wanted_names, rt.wanted_entries

-- Expert names are the protocol's filter name and the expert's (rtde.refused), as the fields' are.
local E = {
    bad_header = ProtoExpert.new(spec.name .. ".bad_header", "Bad message header",
        expert.group.MALFORMED, expert.severity.ERROR),
    short = ProtoExpert.new(spec.name .. ".short", "Message shorter than its layout",
        expert.group.MALFORMED, expert.severity.ERROR),
    extra = ProtoExpert.new(spec.name .. ".extra", "Bytes after the layout",
        expert.group.PROTOCOL, expert.severity.WARN),
    refused = ProtoExpert.new(spec.name .. ".refused", "Setup refused a variable (NOT_FOUND or IN_USE)",
        expert.group.RESPONSE_CODE, expert.severity.WARN),
    unknown_recipe = ProtoExpert.new(spec.name .. ".unknown_recipe",
        "Data package of a recipe this conversation did not set up", expert.group.SEQUENCE, expert.severity.WARN),
    start_refused = ProtoExpert.new(spec.name .. ".start_refused", "The robot refused to start",
        expert.group.RESPONSE_CODE, expert.severity.WARN),
    warning = ProtoExpert.new(spec.name .. ".setup_warning", "Setup exchange out of order",
        expert.group.SEQUENCE, expert.severity.WARN),
    undocumented = ProtoExpert.new(spec.name .. ".undocumented", "Message type with no public layout",
        expert.group.UNDECODED, expert.severity.NOTE),
    unknown_type = ProtoExpert.new(spec.name .. ".unknown_type", "Message type with no layout in this direction",
        expert.group.UNDECODED, expert.severity.WARN),
    not_kept = ProtoExpert.new(spec.name .. ".not_kept", "More requests awaited replies than a conversation keeps",
        expert.group.SEQUENCE, expert.severity.ERROR),
    protocol_unknown = ProtoExpert.new(spec.name .. ".protocol_unknown", "Accepted protocol version with no layouts",
        expert.group.PROTOCOL, expert.severity.ERROR),
    retyped = ProtoExpert.new(spec.name .. ".retyped", "Setup reply types a variable otherwise than the table",
        expert.group.PROTOCOL, expert.severity.WARN),
    internal = ProtoExpert.new(spec.name .. ".internal_error", "Dissector error",
        expert.group.MALFORMED, expert.severity.ERROR),
}
proto.experts = { E.bad_header, E.short, E.extra, E.refused, E.unknown_recipe, E.start_refused, E.warning,
                  E.undocumented, E.unknown_type, E.not_kept, E.protocol_unknown, E.retyped, E.internal }

do
    -- A vector's named items share its filter name, of which tshark -G fields lists the first
    -- registered: they are registered first, in order, as the native dissector registers them.
    local list, listed = {}, {}
    for _, named in pairs(spec.items) do
        for _, entry in ipairs(named.items) do
            list[#list + 1], listed[entry[1]] = entry[1], true
        end
    end
    for _, f in pairs(F) do
        if not listed[f] then list[#list + 1] = f end
    end
    for _, f in ipairs(rt.exchange_field_list) do list[#list + 1] = f end
    proto.fields = list
end

local states, views = {}, {}
-- Whether this call's items are looked at (dissect sets it): a visible tree, or a filter or
-- column that names the protocol or one of its fields. Without, data packages add no value
-- items, which are most of the work (make bench-rtde, no tree). With a visible tree, `names` are
-- the rtde names of a tshark -T fields run (runtime/lua/common/wanted.lua; nil: every field): a
-- data package shows only the values they name.
local showing, names, handle = true, nil, nil

function proto.init()
    states, views = {}, {}
end

-- A conversation: both ends, and Wireshark's TCP conversation where the tree has it (the
-- innermost tcp.stream), so that a new connection on the same addresses and ports starts afresh,
-- as in the native plugin. Only the first pass reads a conversation's state.
local tcp_stream_index = rt.tcp_stream_index

local function conversation_key(pinfo)
    local a = tostring(pinfo.src) .. ":" .. tostring(pinfo.src_port)
    local b = tostring(pinfo.dst) .. ":" .. tostring(pinfo.dst_port)
    local index = tcp_stream_index()
    local tcp = index and "#" .. tostring(index) or ""
    if a < b then return a .. "|" .. b .. tcp end
    return b .. "|" .. a .. tcp
end

local function plausible(raw, at)
    local size = be_uint(raw, at, 2)
    local code = string.byte(raw, at + 3)
    return size >= HEADER and spec.type_names[code] ~= nil
end

-- Reads of one scalar from a TvbRange, by the spec's reader names.
local READ = {
    uint = function(r) return r:uint() end,
    int = function(r) return r:int() end,
    uint64 = function(r) return r:uint64() end,
    int64 = function(r) return r:int64() end,
    float = function(r) return r:float() end,
}

-- What each item of a value appends to its label, in one text: the unit (or, retyped, the
-- variable's name) and a vector's item index (" [0]", " [1]", ...); nil where an item appends nothing.
local function item_texts(unit, count)
    if count == 1 then return unit and { [0] = unit } or nil end
    local texts = {}
    for i = 0, count - 1 do texts[i] = (unit or "") .. " [" .. i .. "]" end
    return texts
end

-- How each value of a recipe shows, worked out once per recipe (the first time one of its data
-- packages is shown) and kept with it: its offset (state.lua's, from the setup), its item size
-- and count, the filter name of its item (`part`: its name's, under which its named items and
-- flags filter too), and the field, unit, named items, flags or retype the spec's tables give its
-- name and type. A name the variable table lacks (a newer controller's) shows its value's bytes
-- whole, with the name. A variable the setup reply types otherwise than the table is read by the
-- reply's type, under the field of that type (rtde.value_float64...), with its name and an expert.
local function value_items(recipe)
    local list, retyped = {}, {}
    for i, name in ipairs(recipe.names) do
        local type_name = recipe.types[i]
        local vt = spec.value_types[type_name]
        local v = { at = recipe.offsets[i], size = vt.size, count = vt.count, len = vt.size * vt.count }
        if not spec.variable_types[name] then
            v.unknown, v.part = " (" .. name .. ")", PREFIX .. "unknown_variable"
        else
            v.retyped = rt.retyped(name, type_name)
            local unit = nil
            if v.retyped then
                v.field, unit = F[vt.field], " (" .. name .. ")"
                retyped[#retyped + 1] = v.retyped
            else
                v.field, unit, v.named, v.flags = F[name], spec.variable_units[name], spec.items[name], spec.flags[name]
                v.part = PREFIX .. name
            end
            v.texts = item_texts(unit, vt.count)
        end
        list[i] = v
    end
    list.retyped = retyped
    recipe.items = list
    return list
end

-- One value of a recipe, at `base` (where the package's values start): an item per scalar (a
-- vector's items in order, each filterable by the variable's name: under a subtree by their
-- names where the spec names them, else with their index).
local function add_value(tree, tvb, base, v)
    local pos = base + v.at
    if v.unknown then
        tree:add(F.unknown_variable, tvb(pos, v.len)):append_text(v.unknown)
        return
    end
    if v.named then
        local group = tree:add(tvb(pos, v.len), v.named.group)
        for i, entry in ipairs(v.named.items) do
            local item = group:add(entry[1], tvb(pos + (i - 1) * v.size, v.size))
            if entry[2] then item:append_text(entry[2]) end
        end
        return
    end
    local texts = v.texts
    for i = 0, v.count - 1 do
        local range = tvb(pos + i * v.size, v.size)
        local item = tree:add(v.field, range)
        if texts then item:append_text(texts[i]) end
        if v.retyped and i == 0 then item:add_proto_expert_info(E.retyped, v.retyped) end
        if v.flags then
            for _, flag in ipairs(v.flags) do item:add(flag, range) end
        end
    end
end

-- Each step of a layout: adds its items and returns the next position, or nil when it does not fit.
local STEP = {}

function STEP.scalar(s, tree, tvb, pos, stop, values)
    if pos + s.size > stop then return nil end
    local range = tvb(pos, s.size)
    local item = tree:add(F[s.name], range)
    if s.unit then item:append_text(s.unit) end
    if s.read == "uint" or s.read == "int" then values[s.name] = READ[s.read](range) end
    return pos + s.size
end

function STEP.prefixed_text(s, tree, tvb, pos, stop, values)
    if pos + s.prefix > stop then return nil end
    local n = tvb(pos, s.prefix):uint()
    if pos + s.prefix + n > stop then return nil end
    tree:add(F[s.name], tvb(pos, s.prefix + n), tvb(pos + s.prefix, n):string())
    return pos + s.prefix + n
end

local function rest(s, tree, tvb, pos, stop, values)
    local text = stop > pos and tvb(pos, stop - pos):string() or ""
    values[s.name] = text
    if stop > pos then return stop, tree:add(F[s.name], tvb(pos, stop - pos)) end
    return stop, tree:add(F[s.name], tvb(pos, 0), "")
end
STEP.rest_text = rest
STEP.names = rest

-- The filter name of a value's item; nil for a retyped value, always shown (for its expert).
local function part_of(v)
    return v.part
end

-- A data package's values, read at the offsets its recipe worked out once. Only where someone
-- looks (`showing`: a visible tree, or a filter or column naming the protocol) do they become
-- items, and only those the command line names (`names`); otherwise only a retyped variable's
-- expert is added, for the expert infos.
function STEP.values(s, tree, tvb, pos, stop, values, view)
    local recipe = view.recipe
    if pos + recipe.size > stop then return nil end
    local items = recipe.items or value_items(recipe)
    if not showing then
        for _, text in ipairs(items.retyped) do tree:add_proto_expert_info(E.retyped, text) end
        return pos + recipe.size
    end
    tree:add(F.recipe_frame, tvb(pos, 0), recipe.frame):set_generated()
    local shown = wanted_entries(items, names, part_of)
    for i = 1, #shown do add_value(tree, tvb, pos, shown[i]) end
    return pos + recipe.size
end

-- What the state says about one message, worked out on the first pass and kept for the others,
-- under the message's place among the frame's bytes: a message reassembled from earlier segments
-- starts at 0 in its own data, the messages after it in the frame's own bytes later, so that two
-- calls for one frame (the reassembled message, then the rest of the segment) keep two views.
local function view_of(pinfo, tvb, state, offset)
    local key = pinfo.number .. ":" .. (tvb:offset() + offset)
    local view = views[key]
    if view and pinfo.visited then return view, false end
    view = { protocol = rt.protocol_of(state), assumed = state.protocol == nil }
    views[key] = view
    return view, true
end

-- A setup reply's types, each paired with the variable the request named in its place: under the
-- types' item, on each type's bytes (split at the commas of the bytes, as the state splits them).
local function add_pairs(item, tvb, raw, pos, stop, names)
    local starts, at = {}, pos
    while true do
        starts[#starts + 1] = at
        local comma = stop > pos and string.find(raw, ",", at + 1, true)
        if not comma or comma > stop then break end
        at = comma
    end
    if stop == pos or #starts ~= #names then return end
    starts[#starts + 1] = stop + 1
    for i, name in ipairs(names) do
        local range = tvb(starts[i], starts[i + 1] - 1 - starts[i])
        local shown = item:add(F.variable, range, name)
        shown:set_text(name .. ": " .. range:string())
        shown:set_generated()
    end
end

local function dissect_message(tvb, raw, offset, size, code, pinfo, tree, state, from_robot)
    local stop = offset + size
    local item = tree:add(proto, tvb(offset, size))
    item:add(F.length, tvb(offset, 2))
    item:add(F.type, tvb(offset + 2, 1))
    item:add(F.direction, tvb(offset + 2, 1), from_robot and "robot to client" or "client to robot"):set_generated()
    local view, first = view_of(pinfo, tvb, state, offset)
    local layout = spec.messages[code .. ":" .. (from_robot and 1 or 0) .. ":" .. view.protocol]
    local shown = item:add(F.protocol, tvb(offset + 2, 1), view.protocol)
    shown:set_generated()
    if view.assumed then shown:append_text(" (assumed: no version exchange seen)") end
    if not layout then
        local named = spec.undocumented[code]
        item:add(F.kind, tvb(offset + 2, 1), named and named.name or "unknown"):set_generated()
        item:add_proto_expert_info(named and E.undocumented or E.unknown_type)
        return named and named.label or ("Unknown type " .. code)
    end
    item:add(F.kind, tvb(offset + 2, 1), layout.name):set_generated()
    item:append_text(": " .. layout.label)
    if first then rt.follow_exchange(state, view, layout.name, pinfo) end
    if view.request or view.link then rt.show_exchange(item, tvb(offset + 2, 1), view) end
    local first_step = layout.steps[1]
    local is_data = false
    for _, s in ipairs(layout.steps) do
        if s.kind == "values" then is_data = true end
    end
    if is_data and first then
        local id = nil
        if first_step.name == "recipe_id" and size > HEADER then
            id = string.byte(raw, offset + HEADER + 1)
        end
        view.recipe = rt.recipe_for(state, from_robot, id)
    end
    if is_data and not view.recipe then
        if first_step.name == "recipe_id" and size > HEADER then item:add(F.recipe_id, tvb(offset + HEADER, 1)) end
        item:add_proto_expert_info(E.unknown_recipe)
        return layout.label
    end
    local values, pos = {}, offset + HEADER
    local names_item, names_pos = nil, nil
    for _, s in ipairs(layout.steps) do
        local next_pos, added = STEP[s.kind](s, item, tvb, pos, stop, values, view)
        if not next_pos then
            item:add_proto_expert_info(E.short, s.name .. " at offset " .. (pos - offset) .. ": does not fit")
            return layout.label
        end
        if s.kind == "names" then names_item, names_pos = added, pos end
        pos = next_pos
    end
    if pos < stop then item:add_proto_expert_info(E.extra, (stop - pos) .. " bytes after the layout") end
    if first then view.notes = rt.follow(state, layout.name, values, pinfo.number) end
    local notes = view.notes
    if notes and notes.names and names_item then add_pairs(names_item, tvb, raw, names_pos, pos, notes.names) end
    if notes and notes.refused then
        for _, pair in ipairs(notes.refused) do
            item:add_proto_expert_info(E.refused, pair[1] .. ": " .. pair[2])
        end
    end
    if notes and notes.retyped then
        for _, text in ipairs(notes.retyped) do item:add_proto_expert_info(E.retyped, text) end
    end
    if notes and notes.warning then
        item:add_proto_expert_info(layout.name == "start_reply" and E.start_refused or E.warning, notes.warning)
    end
    if notes and notes.not_kept then item:add_proto_expert_info(E.not_kept, notes.not_kept) end
    if notes and notes.protocol_error then item:add_proto_expert_info(E.protocol_unknown, notes.protocol_error) end
    return layout.label
end

local function dissect(tvb, pinfo, tree)
    handle = handle or Dissector.get(spec.name)
    showing = tree.visible or tree:referenced(handle)
    names = tree.visible and wanted_names(PREFIX) or nil
    local len = tvb:len()
    local raw = tvb:raw()
    local from_robot = pinfo.src_port == pinfo.match_uint
    local key = conversation_key(pinfo)
    local state = states[key]
    if not state then
        state = rt.new_state()
        states[key] = state
    end
    pinfo.cols.protocol = "RTDE"
    local labels, offset = {}, 0
    while offset < len do
        if len - offset < HEADER then
            pinfo.desegment_offset = offset
            pinfo.desegment_len = DESEGMENT_ONE_MORE_SEGMENT
            break
        end
        local size = be_uint(raw, offset, 2)
        local code = string.byte(raw, offset + 3)
        if size < HEADER or size > spec.max_message_length or not spec.type_names[code] then
            local at = offset + 1
            while len - at >= HEADER and not plausible(raw, at) do at = at + 1 end
            -- Fewer bytes than a header left: the scan ends with this segment (it is not carried over,
            -- or its next part would show the same fault again).
            if len - at < HEADER then at = len end
            local item = tree:add(proto, tvb(offset, at - offset))
            item:add_proto_expert_info(E.bad_header, "size " .. size .. ", type " .. code)
            labels[#labels + 1] = "Bad header"
            offset = at
        elseif len - offset < size then
            pinfo.desegment_offset = offset
            pinfo.desegment_len = size - (len - offset)
            break
        else
            labels[#labels + 1] = dissect_message(tvb, raw, offset, size, code, pinfo, tree, state, from_robot)
            offset = offset + size
        end
    end
    if #labels > 0 then pinfo.cols.info = table.concat(labels, ", ") end
    return len
end

-- A Lua error while dissecting shows as the expert rtde.internal_error (runtime/lua/common/guard.lua).
proto.dissector = rt.guard(proto, dissect, E.internal, spec.name)

proto.prefs.ports = Pref.range("TCP ports", spec.default_ports, "Robot-side TCP ports of " .. spec.title, 65535)

function proto.prefs_changed()
    rt.register_ports(proto, proto.prefs.ports)
end

rt.register_ports(proto, proto.prefs.ports)
