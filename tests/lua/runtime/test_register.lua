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
print("ok")
