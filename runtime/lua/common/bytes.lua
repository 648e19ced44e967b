-- Big-endian numbers read from a message's raw bytes (the Lua string of tvb:raw(), offsets
-- counted from 0 as in the tvb). string.byte on the raw string costs a seventh of
-- tvb(o, n):uint() in tshark 4.0.
local spec, rt = ...
local byte = string.byte

-- An unsigned integer of n bytes at offset o.
local function be_uint(raw, o, n)
    local v = 0
    for i = o + 1, o + n do v = v * 256 + byte(raw, i) end
    return v
end

-- 2^(8n - 1) for n = 1..4, made by multiplying so that it stays an integer on Lua 5.3 and 5.4:
-- be_int then returns integers there (Wireshark's TreeItem:add takes them as they are).
local HALF = {}
for n = 1, 4 do
    local h = 1
    for _ = 1, 8 * n - 1 do h = h * 2 end
    HALF[n] = h
end

-- A two's-complement integer of n bytes at offset o.
local function be_int(raw, o, n)
    local v = be_uint(raw, o, n)
    local half = HALF[n] or 2 ^ (8 * n - 1)
    if v >= half then v = v - 2 * half end
    return v
end

rt.be_uint, rt.be_int = be_uint, be_int
