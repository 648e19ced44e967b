-- runtime/lua/common/tcp_stream.lua: the frame's innermost tcp.stream, or nil without one.
local S = dofile("stubs.lua")

local asked, values = nil, {}
Field = { new = function(name)
    asked = name
    return function() return table.unpack(values) end
end }
local rt = S.load("common/tcp_stream.lua")
S.eq(asked, "tcp.stream", "the extractor is made as the file loads")

S.eq(rt.tcp_stream_index(), nil, "no tcp.stream in the tree")
values = { { value = 4 } }
S.eq(rt.tcp_stream_index(), 4, "one TCP layer")
values = { { value = 0 } }
S.eq(rt.tcp_stream_index(), 0, "conversation 0 is one (not false)")
values = { { value = 2 }, { value = 9 } }
S.eq(rt.tcp_stream_index(), 9, "TCP in a tunnel: the innermost, the last")
print("ok")
