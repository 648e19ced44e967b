-- Preferences and registration: the robot-side ports (taken over from MRCPv2, which claims
-- TCP 30000-30200 in Wireshark 4.0; "Decode As" works on others), the software version assumed
-- until a Version message is seen (empty: none), whether tshark -T fields builds only the
-- packages its command line names (runtime/lua/{common,packages}/wanted.lua), and the longest plausible message.
local spec, rt = ...
local ur = spec.proto
local parse_version, assume_version, named_only = rt.parse_version, rt.assume_version, rt.named_only
local register_ports = rt.register_ports

ur.prefs.ports = Pref.range("TCP ports", spec.default_ports,
    "Robot-side TCP ports of the primary/secondary interfaces", 65535)
ur.prefs.version = Pref.string("Software version", "",
    "Controller software version (major.minor or major.minor.bugfix, as 5.25.1) assumed until a \z
    Version message is seen on a stream: it chooses the layouts, the enum names and the \z
    global-variable value types. Empty: the layout sizes tell it where they can, else " .. spec.default_version .. ".")
ur.prefs.named_fields_only = Pref.bool("Only the fields tshark -T fields names", true,
    "With tshark -T fields, build only the robot-state packages whose fields the command line names \z
    (-e, -Y, -R, -z, -o); off: build every field, as for another Lua script reading ur fields with Field.new")
ur.prefs.max_length = Pref.uint("Maximum message length", spec.max_message_length,
    "Longer declared lengths are treated as malformed, and the dissector resynchronises")

function ur.prefs_changed()
    assume_version(parse_version(ur.prefs.version))
    named_only(ur.prefs.named_fields_only)
    register_ports(ur, ur.prefs.ports)
end

register_ports(ur, ur.prefs.ports)

set_plugin_info({
    version = "0.1.0",
    description = spec.title .. " (urwire, generated from the spec)",
    repository = "urwire",
})
