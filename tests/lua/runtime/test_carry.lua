-- runtime/lua/packages/carry.lua: bytes carried by hand, kept as parts and joined once.
local S = dofile("stubs.lua")
local rt = S.load("packages/carry.lua", { header_size = 5 })

local c = rt.carry_new("ab")
S.eq(c.size, 2, "a new carry holds its bytes"); S.eq(c.head, "ab", "less than a header")
rt.carry_add(c, "cd")
rt.carry_add(c, "efg")
S.eq(c.size, 7, "each call's bytes are added"); S.eq(c.head, "abcde", "the head stops at a header's size")
S.eq(#c.parts, 3, "nothing is joined while carrying")
S.eq(rt.carry_bytes(c, 7), "abcdefg", "joined when asked")
S.eq(#c.parts, 1, "and kept joined")
S.eq(rt.carry_bytes(c, 4), "abcd", "the bytes a call started with")
S.eq(rt.carry_bytes(c, 7), "abcdefg", "again, from the joined bytes")
rt.carry_add(c, "h")
S.eq(rt.carry_bytes(c, 8), "abcdefgh", "a carry joined once can grow on")

-- Many one-byte parts: the parts are the bytes, and the join is one string.
local big = rt.carry_new("x")
for i = 1, 9999 do rt.carry_add(big, string.char(97 + i % 26)) end
S.eq(big.size, 10000, "ten thousand bytes"); S.eq(#big.parts, 10000, "one part per call")
local all = rt.carry_bytes(big, 10000)
S.eq(#all, 10000, "joined"); S.eq(all:sub(1, 3), "xbc", "in order")
print("ok")
