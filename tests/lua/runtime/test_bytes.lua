-- runtime/lua/packages/bytes.lua: big-endian reads from a raw string, and the texts of a read that
-- does not fit.
local S = dofile("stubs.lua")
local rt = S.load("packages/bytes.lua")

local raw = S.bytes(0x00, 0x00, 0x01, 0x02, 0xff, 0xfe, 0x80, 0x00, 0x00, 0x00, 0x7f)
S.eq(rt.be_uint(raw, 0, 4), 258, "uint32 00 00 01 02")
S.eq(rt.be_uint(raw, 4, 1), 255, "uint8 ff")
S.eq(rt.be_int(raw, 4, 1), -1, "int8 ff")
S.eq(rt.be_int(raw, 4, 2), -2, "int16 ff fe")
S.eq(rt.be_uint(raw, 4, 2), 65534, "uint16 ff fe")
S.eq(rt.be_int(raw, 6, 4), -2147483648, "int32 80 00 00 00")
S.eq(rt.be_uint(raw, 6, 4), 2147483648, "uint32 80 00 00 00")
S.eq(rt.be_int(raw, 10, 1), 127, "int8 7f")
S.eq(rt.be_int(raw, 0, 0), 0, "no bytes")
S.eq(string.format("%d", rt.be_int(raw, 4, 2)), "-2", "a negative read prints with %d on every Lua")
S.eq(tostring(rt.be_int(raw, 4, 2)), "-2", "an integer on every Lua (no -2.0 on 5.3 and 5.4)")
S.eq(tostring(rt.be_int(raw, 6, 4)), "-2147483648", "int32 as an integer too")

local st = { base = 10 }
S.eq(rt.short(st, "joints[2].q_actual", 30, 8, 34), "joints[2].q_actual at offset 20: needs 8 bytes, 4 left", "short")
S.eq(rt.short(st, "x", 40, 1, 34), "x at offset 30: needs 1 bytes, 0 left", "short past the end")
S.eq(rt.negative(st, "title", 12, -3), "title at offset 2: negative length -3", "negative")
print("ok")
