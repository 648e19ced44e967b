-- Preferences and registration: the robot-side ports (taken over from MRCPv2, which claims
-- TCP 30000-30200 in Wireshark 4.0; "Decode As" works on others), the software version assumed
-- until a Version message is seen (empty: none), and the longest plausible message.
local spec, rt = ...
local ur = spec.proto
local parse_version, assume_version = rt.parse_version, rt.assume_version

ur.prefs.ports = Pref.range("TCP ports", spec.default_ports, "Robot-side TCP ports of the primary/secondary interfaces", 65535)
ur.prefs.version = Pref.string("Software version", "", "Controller software version (major.minor or major.minor.bugfix, as 5.25.1) assumed until a Version message is seen on a stream: it chooses the layouts, the enum names and the global-variable value types. Empty: the layout sizes tell it where they can, else " .. spec.default_version .. ".")
ur.prefs.max_length = Pref.uint("Maximum message length", spec.max_message_length, "Longer declared lengths are treated as malformed, and the dissector resynchronises")

local tcp_port = DissectorTable.get("tcp.port")
local registered = nil

local function register_ports()
    if registered then tcp_port:remove(registered, ur) end
    registered = ur.prefs.ports
    tcp_port:add(registered, ur)
end

function ur.prefs_changed()
    assume_version(parse_version(ur.prefs.version))
    register_ports()
end

register_ports()

set_plugin_info({
    version = "0.1.0",
    description = spec.title .. " (urwire, generated from the spec)",
    repository = "urwire",
})
