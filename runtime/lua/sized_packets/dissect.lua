-- The real-time dissector's runtime: frames the robot's TCP stream by each packet's int32 size
-- (reassembling a packet split over segments), chooses the packet's layout by the spec's
-- same_size rule over spec.forms_by_size, and walks the layout's slots into the tree. What a
-- client sends to the port is URScript text. The interface has no version message, so the only
-- state is the software-version preference: nothing is kept per conversation, and two robots or
-- two clients in one capture cannot share anything.
local spec, rt = ...
local proto = spec.proto
local F, ITEMS, FLAGS = spec.fields, spec.items, spec.flags
local LABELS, UNITS, ENUM_OF = spec.labels, spec.units, spec.enum_of
local LAYOUTS, FORMS = spec.layouts, spec.forms_by_size
local fmt, floor = string.format, math.floor
local SIZE_BYTES, MIN_SIZE, MAX_SIZE = spec.size_field_bytes, spec.min_message_size, spec.max_message_size
local PREFIX = spec.name .. "."     -- every field's filter name starts so: ur_realtime.q_actual
local wanted_names, wanted_entries = rt.wanted_names, rt.wanted_entries

-- The dissector's own fields and experts, beside the spec's.
local X = {
    layout = ProtoField.string(spec.name .. ".layout", "Layout",
        "The packet layout its size names, and the versions that send it."),
    urscript = ProtoField.string(spec.name .. ".urscript", "URScript", "URScript text the client sends to the robot."),
    raw = ProtoField.bytes(spec.name .. ".raw", "Bytes of a packet of unknown size", base.NONE,
        "A packet whose size names no layout of the spec, shown whole."),
}
local E = {
    -- Framed, and kept: a layout the spec does not know yet, not a broken stream.
    unknown_size = ProtoExpert.new(spec.name .. ".unknown_size", "Packet size matches no layout",
        expert.group.PROTOCOL, expert.severity.WARN),
    bad_size = ProtoExpert.new(spec.name .. ".bad_size", "Packet size cannot frame a packet",
        expert.group.MALFORMED, expert.severity.ERROR),
    internal = ProtoExpert.new(spec.name .. ".internal_error", "Dissector error",
        expert.group.MALFORMED, expert.severity.ERROR),
}

local registered_fields = {}
for _, f in pairs(F) do registered_fields[#registered_fields + 1] = f end
for _, f in pairs(X) do registered_fields[#registered_fields + 1] = f end
for _, items in pairs(ITEMS) do
    for _, item in ipairs(items) do registered_fields[#registered_fields + 1] = item[1] end
end
for _, flags in pairs(FLAGS) do
    for _, f in ipairs(flags) do registered_fields[#registered_fields + 1] = f end
end
proto.fields = registered_fields
proto.experts = { E.unknown_size, E.bad_size, E.internal }

proto.prefs.ports = Pref.range("Ports", spec.ports, "TCP ports of the real-time interface", 65535)
proto.prefs.version = Pref.string("Software version", "",
    "The controller's software version (5.9, 3.15.2): chooses among layouts that share a size; " ..
    "empty: the newest of them")

-- "5.9" or "3.15.2" -> the version number the forms are written in; nil for anything else.
local function version_number(text)
    local major, minor, bugfix = rt.dotted_version(text)
    if not major then return nil end
    if bugfix > 999 then bugfix = 999 end
    return (major * 1000 + minor) * 1000 + bugfix
end

local version = nil

-- The same_size rule: the first form of the size whose versions hold the version, else the last.
local function form_of(size)
    local forms = FORMS[size]
    if not forms then return nil end
    if version then
        for _, form in ipairs(forms) do
            if form[1] <= version and version <= form[2] then return form end
        end
    end
    return forms[#forms]
end

-- One double: its value with its unit (a named item's own: `i`, from 1), an enum code's name
-- where the form has one, and the flags a whole value carries where the field names its bits.
local function add_value(tree, name, range, names, i)
    local v = range:float()
    local named = i and ITEMS[name] and ITEMS[name][i]
    local item = tree:add(named and named[1] or F[name], range, v)
    local unit = nil
    if named then unit = named[2] elseif UNITS[name] then unit = " " .. UNITS[name] end
    if unit then item:append_text(unit) end
    if names and v == floor(v) and names[v] then item:append_text(" (" .. names[v] .. ")") end
    if FLAGS[name] and v == floor(v) and v >= 0 and v < 2 ^ 32 then
        for _, flag in ipairs(FLAGS[name]) do item:add(flag, range, v) end
    end
    return v
end

-- Where each layout sends the robot mode (nil: it does not): the Info column reads it even when
-- no tree is built.
local ROBOT_MODE_AT = {}
for i, layout in ipairs(LAYOUTS) do
    for _, slot in ipairs(layout.slots) do
        if slot[1] == "robot_mode" then ROBOT_MODE_AT[i] = slot[2] end
    end
end

-- The Info column's words for a packet of a known layout, without a tree.
local function info_of(tvb, o, form)
    local layout, at = LAYOUTS[form[3]], ROBOT_MODE_AT[form[3]]
    local names = at and form[4][ENUM_OF.robot_mode]
    if not names then return layout.name end
    local mode = names[tvb(o + at, 8):float()]
    return mode and (layout.name .. ", " .. mode) or layout.name
end

-- The filter name of a slot's items: its field's, under which its named items and flags filter too.
local function slot_part(slot)
    return PREFIX .. slot[1]
end

-- One whole packet at offset o: its subtree when someone looks (`detail`), with only the slots
-- a tshark -T fields run names (`wanted`, runtime/lua/common/wanted.lua; nil: every slot), else
-- only what the Info column and the experts need; returns the Info column's words for it.
local function dissect_packet(tvb, tree, o, size, detail, wanted)
    local form = form_of(size)
    if form and not detail then return info_of(tvb, o, form) end
    local sub = tree:add(proto, tvb(o, size))
    sub:add(F[spec.size_field], tvb(o, SIZE_BYTES))
    if not form then
        sub:append_text(fmt(", unknown size %d", size))
        sub:add(X.raw, tvb(o + SIZE_BYTES, size - SIZE_BYTES))
        sub:add_proto_expert_info(E.unknown_size, fmt("Packet size %d matches no layout", size))
        return fmt("Unknown size %d", size)
    end
    local layout, names = LAYOUTS[form[3]], form[4]
    sub:append_text(", " .. layout.name)
    sub:add(X.layout, layout.name):set_generated()
    for _, slot in ipairs(wanted_entries(layout.slots, wanted, slot_part)) do
        local name, at, count = slot[1], o + slot[2], slot[3]
        local enum = ENUM_OF[name] and names[ENUM_OF[name]]
        if count == 1 then
            add_value(sub, name, tvb(at, 8), enum)
        else
            local unit = UNITS[name] and (" (" .. UNITS[name] .. ")") or ""
            local group = sub:add(tvb(at, 8 * count), LABELS[name] .. unit)
            for i = 0, count - 1 do add_value(group, name, tvb(at + 8 * i, 8), enum, i + 1) end
        end
    end
    return info_of(tvb, o, form)
end

-- A call's words, after an earlier call's for the same frame (runtime/lua/common/info_column.lua).
local write_info = rt.info_writer(", ")

local function show_info(pinfo, words)
    write_info(pinfo, pinfo.cols.info, words, false)
end

-- Where the next plausible packet starts from offset o on: the next size some layout has (a size
-- no layout has is not trusted, since a packet's doubles hold small int32s often enough); nil when
-- the bytes up to len hold none whole.
local function next_packet(tvb, o, len)
    while len - o >= SIZE_BYTES do
        if FORMS[tvb(o, SIZE_BYTES):int()] then return o end
        o = o + 1
    end
    return nil
end

local handle = nil

local function dissect(tvb, pinfo, tree)
    local len = tvb:len()
    -- Field work only when someone looks: a visible tree, or a filter or column naming the protocol.
    handle = handle or Dissector.get(spec.name)
    local detail = tree.visible or tree:referenced(handle)
    local wanted = tree.visible and wanted_names(PREFIX) or nil
    pinfo.cols.protocol = "UR real-time"
    if pinfo.src_port ~= pinfo.match_uint then
        -- Client to robot: URScript text, not decoded.
        tree:add(proto, tvb()):add(X.urscript, tvb())
        show_info(pinfo, "URScript")
        return len
    end
    local o, infos = 0, {}
    while o < len do
        local left = len - o
        if left < SIZE_BYTES then
            pinfo.desegment_offset, pinfo.desegment_len = o, DESEGMENT_ONE_MORE_SEGMENT
            break
        end
        local size = tvb(o, SIZE_BYTES):int()
        if size < MIN_SIZE or size > MAX_SIZE then
            -- The middle of a packet (a segment after a lost one): skip to the next size some
            -- layout has; where the segment holds none, its last bytes may begin one, and wait
            -- for the next segment.
            local found = next_packet(tvb, o + 1, len)
            local stop = found or len - (SIZE_BYTES - 1)
            local item = tree:add(proto, tvb(o, stop - o))
            item:add_proto_expert_info(E.bad_size, fmt("Packet size %d cannot frame a packet (%d to %d)",
                size, MIN_SIZE, MAX_SIZE))
            infos[#infos + 1] = fmt("Bad size %d", size)
            if not found then
                pinfo.desegment_offset, pinfo.desegment_len = stop, DESEGMENT_ONE_MORE_SEGMENT
                break
            end
            o = found
        elseif left < size then
            pinfo.desegment_offset, pinfo.desegment_len = o, size - left
            break
        else
            infos[#infos + 1] = dissect_packet(tvb, tree, o, size, detail, wanted)
            o = o + size
        end
    end
    if #infos > 0 then
        show_info(pinfo, #infos == 1 and infos[1] or fmt("%s (+%d)", infos[1], #infos - 1))
    end
    return len
end

-- A Lua error while dissecting shows as the expert ur_realtime.internal_error (runtime/lua/common/guard.lua).
proto.dissector = rt.guard(proto, dissect, E.internal, spec.name)

function proto.prefs_changed()
    version = version_number(proto.prefs.version)
    rt.register_ports(proto, proto.prefs.ports)
end

rt.register_ports(proto, proto.prefs.ports)
rt.version_number, rt.form_of = version_number, form_of
