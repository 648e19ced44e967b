-- Which TCP conversation a frame belongs to, as Wireshark's TCP numbers them (tcp.stream): a new
-- connection on the same addresses and ports is a new number, so that a dissector's state per
-- conversation starts afresh there, as the native plugins' conversations do.
local spec, rt = ...

local tcp_stream = Field.new("tcp.stream")

-- The frame's innermost tcp.stream (the last in the tree: TCP inside a tunnel comes after the
-- outer one), nil when the tree lacks it (a first pass without a tree: tshark -2, no filter).
local function tcp_stream_index()
    local all = { tcp_stream() }
    local last = all[#all]
    return last and last.value
end

rt.tcp_stream_index = tcp_stream_index
