-- The joined file, generated/lua/urwire.lua, loads and dissects under this Lua with stub
-- Wireshark globals (tshark 4.0 embeds Lua 5.2 only; later Wiresharks embed 5.3 and 5.4).
local S = dofile("stubs.lua")
S.wireshark_globals()
local plugin = assert(os.getenv("URWIRE_PLUGIN"), "set URWIRE_PLUGIN to generated/lua/urwire.lua")

local protos = {}
local real_proto = Proto
Proto = function(name, desc)
    local p = real_proto(name, desc)
    protos[#protos + 1] = p
    return p
end
local before = {}
for k in pairs(_G) do before[k] = true end
dofile(plugin)
for k in pairs(_G) do
    if not before[k] then error("the dissector leaked the global " .. tostring(k)) end
end
local ur = protos[1]
S.eq(#protos, 1, "one protocol")
S.eq(type(ur.dissector), "function", "a dissector")
S.eq(type(ur.init), "function", "an init")
S.eq(S.ports["tcp.port"], "30001,30002,30011,30012", "the spec's ports")

local function hex(text)
    return (text:gsub("%x%x", function(h) return string.char(tonumber(h, 16)) end))
end
local version = hex("0000002d140000000000000000fe0309555243" .. "6f6e74726f6c05000000000200000064" .. "30312d30312d32303138")
local update = hex("000000131900000000000000070100000c010a")   -- 0x0c: BOOL in 3.3-5.8, POSE from 5.9
local pinfo, tree = S.pinfo(1), S.tree()
ur.dissector(S.tvb(version .. update), pinfo, tree)
local dump = S.dump(tree)
S.eq(dump:match("internal") == nil, true, "no internal error:\n" .. dump)
S.eq(tostring(pinfo.cols.info), "Version: URControl 5.0.2.100; Global variables update", "Info")
S.eq(dump:match("ur.global_variables_update.value_bool @62%+1") ~= nil, true, "BOOL, as the Version message says:\n" .. dump)
S.eq(dump:match("ur.software_version @nil%+nil = 5.0") ~= nil, true, "the version it was read with")

-- Another stream, no Version message: the spec's default version, 5.9, where 0x0c is a POSE.
pinfo, tree = S.pinfo(2), S.tree()
pinfo.dst_port = 50001
ur.dissector(S.tvb(update), pinfo, tree)
dump = S.dump(tree)
S.eq(dump:match("assuming software 5.9") ~= nil, true, "assumed version:\n" .. dump)
S.eq(dump:match("variables%[0%] at offset 17: needs 24 bytes") ~= nil, true, "POSE in 5.9:\n" .. dump)
print("ok")
