-- Port registration, as every dissector does it: the protocol takes its TCP ports from the
-- tcp.port table, and when they change (a preference) gives up the ones it held and takes the
-- new ones. Each generated file is a plugin of its own and joins its own copy of this file.
local spec, rt = ...

local tcp_port = DissectorTable.get("tcp.port")
local registered = nil   -- the ports this plugin's protocol holds

-- Take `ports` (a port, or a range as text or a preference: "30001-30004,30011") for proto.
local function register_ports(proto, ports)
    if registered then tcp_port:remove(registered, proto) end
    registered = ports
    tcp_port:add(registered, proto)
end

-- The ports as the range preference <name>.tcp.port, as the native twin's
-- dissector_add_uint_range_with_preference names it (tshark -o ur_dashboard.tcp.port:40000),
-- defaulting to `ports`; taken again when it changes. For a protocol with no prefs_changed of its own.
local function register_port_preference(proto, name, ports)
    proto.prefs["tcp.port"] = Pref.range("TCP port(s)", ports, name:upper() .. " TCP port(s)", 65535)
    function proto.prefs_changed()
        register_ports(proto, proto.prefs["tcp.port"])
    end
    register_ports(proto, ports)
end

rt.register_ports, rt.register_port_preference = register_ports, register_port_preference
