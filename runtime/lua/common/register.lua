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

rt.register_ports = register_ports
