-- A dissector of fixed int32 records (the ROS driver's reverse, trajectory and script command
-- sockets): each direction cut into records of the size the driver release gives (a preference;
-- a capture does not tell it), reassembled across TCP segments, every int32 shown as its field,
-- scaled fields with their value and their raw int32, enums by name. The control PC listens on
-- the port and the robot's script connects, so bytes to the port come from the robot.
local spec, rt = ...

local proto = Proto(spec.name, spec.title)
local F, fields = {}, {}
for _, f in ipairs(spec.fields) do
    local filter = spec.name .. "." .. f.name
    local shown = f.label .. (f.unit and (" (" .. f.unit .. ")") or "")   -- a unit follows the label
    if f.scaled then
        F[f.name] = ProtoField.double(filter, shown, f.desc)
        F[f.name .. "_raw"] = ProtoField.int32(filter .. "_raw", f.label .. " (raw int32)", base.DEC, nil, nil,
            f.raw_desc)
        fields[#fields + 1] = F[f.name .. "_raw"]
    else
        F[f.name] = ProtoField.int32(filter, shown, base.DEC, f.enum and spec.enums[f.enum] or nil, nil, f.desc)
    end
    fields[#fields + 1] = F[f.name]
end
local E = {
    unspecified = ProtoExpert.new(spec.name .. ".unspecified", "Bytes in a direction where no record is specified",
        expert.group.UNDECODED, expert.severity.WARN),
    internal = ProtoExpert.new(spec.name .. ".internal_error", "Dissector error",
        expert.group.MALFORMED, expert.severity.ERROR),
}
proto.fields = fields
proto.experts = {E.unspecified, E.internal}
proto.prefs.release = Pref.string("Driver release", "",
    "The release of the driver's client library (as 1.3.2 or 2.10.0): it chooses the record layouts. \z
    Empty: " .. spec.default_text .. ".")

-- "2.10" or "2.10.0" -> (major * 1000 + minor) * 1000 + patch; nil for anything else.
local function parse_release(text)
    local major, minor, patch = rt.dotted_version(text)
    if not major then return nil end
    return (major * 1000 + minor) * 1000 + patch
end

local function layout_of(record, release)
    local index = 1
    for i, start in ipairs(record.starts) do
        if release >= start then index = i + 1 end
    end
    return record.layouts[index]
end

local function show_slot(tree, tvb, at, slot)
    local f = spec.fields_by_name[slot.field]
    for k = 0, slot.count - 1 do
        local range = tvb(at + 4 * (slot.index + k), 4)
        local raw = range:int()
        if slot.scale then
            local item = tree:add(F[f.name], range, raw / slot.scale)
            item:append_text(" (raw " .. raw .. ", scaled by " .. slot.scale_name .. " = " .. slot.scale .. ")")
            item:add(F[f.name .. "_raw"], range, raw)
        else
            tree:add(F[f.name], range)
        end
    end
end

local function dissect(tvb, pinfo, tree)
    local n = tvb:len()
    local from_robot = pinfo.dst_port == pinfo.match_uint
    -- Not `from_robot and spec.from_robot or spec.to_robot`: with no record from the robot, that
    -- would read the robot's bytes as the PC's records.
    local record
    if from_robot then record = spec.from_robot else record = spec.to_robot end
    pinfo.cols.protocol = spec.short
    if not record then
        tree:add(proto, tvb()):add_proto_expert_info(E.unspecified)
        return n
    end
    local release = parse_release(proto.prefs.release) or spec.default_release
    local layout = layout_of(record, release)
    local at, count = 0, 0
    while n - at >= layout.size do
        local item = tree:add(proto, tvb(at, layout.size), record.label)
        for _, slot in ipairs(layout.slots) do show_slot(item, tvb, at, slot) end
        at, count = at + layout.size, count + 1
    end
    if at < n then
        if pinfo.can_desegment > 0 then
            pinfo.desegment_offset = at
            pinfo.desegment_len = layout.size - (n - at)
        else
            tree:add(proto, tvb(at, n - at)):set_text("Part of a record (reassembly is off)")
        end
    end
    if count > 0 then pinfo.cols.info = record.label .. (count > 1 and (" x" .. count) or "") end
    return n
end

proto.dissector = rt.guard(proto, dissect, E.internal, spec.name)
rt.register_port_preference(proto, spec.name, table.concat(spec.ports, ","))
rt.parse_release, rt.layout_of = parse_release, layout_of
