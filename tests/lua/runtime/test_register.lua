-- runtime/lua/common/register.lua: a protocol takes its ports, and on a change gives up the ones
-- it held before it takes the new ones.
local S = dofile("stubs.lua")
S.wireshark_globals()

local calls = {}
DissectorTable = { get = function(name)
    return {
        add = function(_, ports, proto) calls[#calls + 1] = "add " .. name .. " " .. tostring(ports) .. " " .. proto.name end,
        remove = function(_, ports, proto)
            calls[#calls + 1] = "remove " .. name .. " " .. tostring(ports) .. " " .. proto.name
        end,
    }
end }

local rt = S.load("common/register.lua")
local proto = Proto("rtde", "RTDE")
rt.register_ports(proto, "30004")
S.eq(table.concat(calls, "; "), "add tcp.port 30004 rtde", "the first ports: taken, nothing given up")
rt.register_ports(proto, "30004,30014-30015")
S.eq(table.concat(calls, "; "), "add tcp.port 30004 rtde; remove tcp.port 30004 rtde; add tcp.port 30004,30014-30015 rtde",
     "new ports: the old ones given up first")
rt.register_ports(proto, "40000")
S.eq(calls[#calls - 1], "remove tcp.port 30004,30014-30015 rtde", "the ports held last are given up, not the first")

-- Each generated file joins its own copy: a second load holds nothing yet.
calls = {}
local other = S.load("common/register.lua")
other.register_ports(Proto("ur_dashboard", "Dashboard"), "29999")
S.eq(table.concat(calls, "; "), "add tcp.port 29999 ur_dashboard", "another plugin's copy starts empty")
-- A port preference: <name>.tcp.port, the spec's ports by default, taken again when it changes.
calls = {}
local third = S.load("common/register.lua")
local gripper = Proto("robotiq_gripper", "Gripper")
third.register_port_preference(gripper, "robotiq_gripper", "63352")
S.eq(gripper.prefs["tcp.port"], "63352", "the preference defaults to the spec's ports")
S.eq(table.concat(calls, "; "), "add tcp.port 63352 robotiq_gripper", "the spec's ports taken")
rawset(getmetatable(gripper.prefs).__index, "tcp.port", "40000")
gripper.prefs_changed()
S.eq(table.concat(calls, "; "), "add tcp.port 63352 robotiq_gripper; remove tcp.port 63352 robotiq_gripper; "
     .. "add tcp.port 40000 robotiq_gripper", "a changed preference: the old ports given up, the new taken")
print("ok")
