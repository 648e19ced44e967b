-- runtime/lua/common/wanted.lua: which fields a tshark -T fields command line needs, for every dissector.
local S = dofile("stubs.lua")

local rt = S.load("common/wanted.lua")

local function names(prefix, ...) return rt.named_fields({ ... }, prefix) end
local function set(t)
    local out = {}
    for k in pairs(t or {}) do out[#out + 1] = k end
    table.sort(out)
    return table.concat(out, " ")
end

-- The names under a prefix of a tshark -T fields run, from every argument.
S.eq(set(names("ur.", "tshark", "-r", "x.pcap", "-T", "fields", "-e", "ur.joint_data.q_actual")),
     "ur.joint_data.q_actual", "one field")
S.eq(set(names("ur.", "/usr/bin/tshark", "-Tfields", "-eur.joint_data.q_actual", "-Y",
               "ur.robot_mode_data.robot_mode == 7")),
     "ur.joint_data.q_actual ur.robot_mode_data.robot_mode", "joined options, and a display filter's fields")
S.eq(set(names("ur.", "tshark", "-T", "fields", "-e", "frame.number", "-X", "lua_script:/x/urwire.lua")), "",
     "no ur field: the plugin's path is not one")
S.eq(set(names("rtde.", "tshark", "-T", "fields", "-e", "rtde.actual_q", "-e", "ur.joint_data.q_actual",
               "-Y", "rtde.robot_status_bits.is_power_on")),
     "rtde.actual_q rtde.robot_status_bits.is_power_on", "only the prefix's names")
S.eq(set(names("ur_realtime.", "tshark", "-T", "fields", "-e", "ur_realtime.q_actual", "-e", "ur.type")),
     "ur_realtime.q_actual", "a prefix with an underscore")
S.eq(set(names("ur.", "tshark", "-T", "fields", "-e", "ur_realtime.q_actual", "-e", "urx.a")), "",
     "the prefix's dot is no wildcard")
S.eq(names("ur.", "tshark", "-V"), nil, "another output: every field")
S.eq(names("ur.", "tshark", "-T", "json", "-e", "ur.joint_data.q_actual"), nil, "-e with -T json: every field")
S.eq(names("ur.", "wireshark", "-T", "fields"), nil, "not tshark")
S.eq(names("rtde.", "tshark", "-T", "fields", "-e", "frame.number", "-z", "expert"), nil, "expert infos: every field")
S.eq(names("rtde.", "tshark", "-T", "fields", "-e", "frame.number", "-Y", "${robot}"), nil,
     "a filter macro: every field")
S.eq(names("ur."), nil, "no command line")

-- A part is wanted by its item's name, or a field's under it; not by a longer name that shares its start.
local chosen = { ["rtde.actual_q"] = true, ["rtde.robot_status_bits.is_power_on"] = true }
S.eq(rt.part_named(chosen, "rtde.actual_q"), true, "its item")
S.eq(rt.part_named(chosen, "rtde.robot_status_bits"), true, "a field under it")
S.eq(rt.part_named(chosen, "rtde.actual_qd"), false, "another part")
S.eq(rt.part_named({ ["rtde.actual_qd"] = true }, "rtde.actual_q"), false, "a longer name is another part's")
S.eq(rt.within("ur.joint_data.q_actual", "ur.joint_data"), true, "within: under")
S.eq(rt.within("ur.joint_data_x", "ur.joint_data"), false, "within: not under")

-- The entries of a list the names want, kept for the same list and names; nil names: the list.
local list = { { "actual_q" }, { "actual_qd" }, { "robot_status_bits" }, { "always" } }
local function part_of(entry) return entry[1] ~= "always" and "rtde." .. entry[1] or nil end
local function firsts(t)
    local out = {}
    for i, entry in ipairs(t) do out[i] = entry[1] end
    return table.concat(out, " ")
end
local kept = rt.wanted_entries(list, chosen, part_of)
S.eq(firsts(kept), "actual_q robot_status_bits always", "the named entries and those always built, in order")
S.eq(rt.wanted_entries(list, chosen, part_of), kept, "worked out once for the same names")
S.eq(firsts(rt.wanted_entries(list, { ["rtde.actual_qd"] = true }, part_of)), "actual_qd always", "again for others")
S.eq(rt.wanted_entries(list, nil, part_of), list, "every entry")

-- Found once per run from this process's command line (lua is not tshark here: every field); the
-- preference off wants every field too.
S.eq(rt.wanted_names("ur."), nil, "lua is not tshark")
rt.named_only(false)
S.eq(rt.wanted_names("ur."), nil, "preference off")
rt.named_only(true)
S.eq(rt.wanted_names("rtde."), nil, "on again: the command line's")
print("ok")
