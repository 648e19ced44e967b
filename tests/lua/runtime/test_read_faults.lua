-- runtime/lua/packages/read_faults.lua: the texts of a read that does not fit in its message.
local S = dofile("stubs.lua")
local rt = S.load("packages/read_faults.lua")

local st = { base = 10 }
S.eq(rt.short(st, "joints[2].q_actual", 30, 8, 34), "joints[2].q_actual at offset 20: needs 8 bytes, 4 left", "short")
S.eq(rt.short(st, "x", 40, 1, 34), "x at offset 30: needs 1 bytes, 0 left", "short past the end")
S.eq(rt.negative(st, "title", 12, -3), "title at offset 2: negative length -3", "negative")
print("ok")
