-- generated/lua/rtde.lua (with runtime/lua/typed_messages/state.lua and
-- runtime/lua/typed_messages/dissect.lua joined) loads on its own under this Lua with stub
-- Wireshark globals: one protocol, its port, its fields, no global.
local S = dofile("stubs.lua")
S.wireshark_globals()
local plugin = assert(os.getenv("URWIRE_PLUGIN"), "set URWIRE_PLUGIN"):gsub("urwire%.lua$", "rtde.lua")

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
S.eq(#protos, 1, "one protocol")
local rtde = protos[1]
S.eq(rtde.name, "rtde", "named rtde")
S.eq(type(rtde.dissector), "function", "a dissector")
S.eq(type(rtde.init), "function", "an init")
S.eq(S.ports["tcp.port"], "30004", "the spec's port")
local names = {}
for _, f in ipairs(rtde.fields) do names[f] = true end
for _, f in ipairs({ "rtde.recipe_id", "rtde.actual_q", "rtde.actual_TCP_pose", "rtde.input_bit_register_64",
                     "rtde.speed_slider_fraction", "rtde.types", "rtde.recipe_frame" }) do
    S.eq(names[f], true, f .. " is registered")
end
local file = assert(io.open(plugin))
local text = file:read("*a")
file:close()
for _, name in ipairs({ "typed_messages/state.lua", "typed_messages/dissect.lua" }) do
    S.eq(text:find("-- ---- runtime/lua/" .. name .. " ----", 1, true) ~= nil, true, name .. " is joined")
end
print("ok")
