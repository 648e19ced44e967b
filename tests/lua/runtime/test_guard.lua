-- runtime/lua/common/guard.lua: a dissector behind pcall; an error shows as an expert info with
-- the protocol's label, and the packet's bytes count as dissected.
local S = dofile("stubs.lua")
S.wireshark_globals()

local rt = S.load("common/guard.lua")
local proto = Proto("ur_dashboard", "Dashboard")

local seen
local dissector = rt.guard(proto, function(tvb, pinfo, tree)
    seen = pinfo
    return 3
end, "ur_dashboard.internal_error", "ur_dashboard")
local tree = S.tree()
S.eq(dissector(S.tvb("hello"), "pinfo", tree), 3, "what the dissector returns, when it does not fail")
S.eq(seen, "pinfo", "the dissector gets the call's arguments")
S.eq(S.dump(tree), "", "no item when nothing failed")

dissector = rt.guard(proto, function() error("bad byte", 0) end, "ur_dashboard.internal_error", "ur_dashboard")
tree = S.tree()
S.eq(dissector(S.tvb("hello"), {}, tree), 5, "a failed call counts every byte as dissected")
S.eq(S.dump(tree), "ur_dashboard @0+5\n  !ur_dashboard.internal_error: ur_dashboard: bad byte",
     "the error under the protocol's item, after the label")

dissector = rt.guard(proto, function() error({}) end, "x.internal_error", "urwire")
tree = S.tree()
dissector(S.tvb("ab"), {}, tree)
S.eq(S.dump(tree):match("!x.internal_error: urwire: table: ") ~= nil, true, "an error that is no string")
print("ok")
