-- runtime/lua/sized_packets/dissect.lua: the version preference read, the same_size rule choosing
-- among the layouts of one size, the ports taken and taken again when the preferences change.
local S = dofile("stubs.lua")
S.wireshark_globals()

local proto = Proto("ur_realtime", "Real-time")
local spec = {
    proto = proto, name = "ur_realtime", title = "Real-time", ports = "30003,30013", fields = { message_size = "size" },
    size_field = "message_size", labels = {}, units = {}, enum_of = {}, items = {}, flags = {},
    layouts = { { name = "old", size = 20, slots = {} }, { name = "new", size = 20, slots = {} } },
    forms_by_size = { [20] = { { 0, 3002999, 1, {} }, { 3003000, 5999999, 2, {} } } },
    size_field_bytes = 4, min_message_size = 12, max_message_size = 100,
}
local rt = S.load("common/register.lua", spec)
S.load("common/dotted_version.lua", spec, rt)
S.load("common/info_column.lua", spec, rt)
S.load("common/guard.lua", spec, rt)
S.load("common/wanted.lua", spec, rt)
S.load("sized_packets/dissect.lua", spec, rt)

S.eq(rt.version_number("5.9"), 5009000, "major.minor")
S.eq(rt.version_number(" 3.15.2 "), 3015002, "major.minor.bugfix, blanks around")
S.eq(rt.version_number("3.15.1234"), 3015999, "a bugfix past 999 stands for any")
S.eq(rt.version_number("5"), nil, "no minor")
S.eq(rt.version_number("5.9 beta"), nil, "words after it")
S.eq(rt.form_of(20)[3], 2, "no version preference: the last form of the size")
S.eq(rt.form_of(24), nil, "a size no layout has")
S.eq(S.ports["tcp.port"], "30003,30013", "the spec's ports")

rawset(getmetatable(proto.prefs).__index, "version", "3.2")
rawset(getmetatable(proto.prefs).__index, "ports", "40003")
proto.prefs_changed()
S.eq(rt.form_of(20)[3], 1, "a version preference: the form whose versions hold it")
S.eq(S.ports["tcp.port"], "40003", "the ports taken again")
print("ok")
