-- runtime/lua/packages/declare.lua and runtime/lua/packages/preferences.lua: what is registered
-- with Wireshark at load time.
local S = dofile("stubs.lua")
S.wireshark_globals()

local ur = Proto("ur", "UR")
local spec = { proto = ur, fields = { "ur.length", "ur.type", "ur.key.text" }, title = "Universal Robots",
               default_ports = "30001,30002", default_version = "5.9", max_message_length = 4096 }
local rt = S.base_rt(spec)
S.load("packages/declare.lua", spec, rt)
S.eq(table.concat(ur.fields, " "), "ur.length ur.type ur.key.text ur.raw ur.extra ur.skipped ur.software_version " ..
     "ur.version_assumed ur.unknown_package ur.urscript", "the spec's fields, then the dissector's own")
S.eq(#ur.experts, 10, "experts")
S.eq(rt.E.items_hidden, "ur.items_hidden", "more items than a message shows")
S.eq(rt.E.by_length, "ur.layout_by_length", "a form chosen by its length")
S.eq(rt.X.raw, "ur.raw", "extra fields exported")
S.eq(rt.E.assumed, "ur.assumed_version", "experts exported")

local assumed, named_only
rt.assume_version = function(v) assumed = v end
rt.named_only = function(on) named_only = on end
S.load("common/register.lua", spec, rt)
S.load("packages/preferences.lua", spec, rt)
S.eq(ur.prefs.named_fields_only, true, "tshark -T fields builds the packages it names, by default")
S.eq(ur.prefs.ports, "30001,30002", "ports preference from the spec")
S.eq(ur.prefs.version, "", "no version preference: the layout sizes, else the spec's default")
S.eq(ur.prefs.max_length, 4096, "maximum length from the spec")
S.eq(S.ports["tcp.port"], "30001,30002", "ports registered")
S.eq(S.plugin_info.description, "Universal Robots (urwire, generated from the spec)", "plugin info")

rawset(getmetatable(ur.prefs).__index, "version", "5.12")
rawset(getmetatable(ur.prefs).__index, "ports", "40000")
ur.prefs_changed()
S.eq(assumed, 5012000, "a new version preference")
S.eq(named_only, true, "the named-fields preference is passed on")
S.eq(S.ports["tcp.port"], "40000", "ports registered again")
rawset(getmetatable(ur.prefs).__index, "version", "5.25.1")
ur.prefs_changed()
S.eq(assumed, 5025001, "a bugfix release")
rawset(getmetatable(ur.prefs).__index, "version", "latest")
ur.prefs_changed()
S.eq(assumed, nil, "no version in the preference: none assumed")
print("ok")
