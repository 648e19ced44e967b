-- runtime/versions.lua: parse, show and compare versions; choose a value table; read the
-- version a Version message announces.
local S = dofile("stubs.lua")
local rt = S.base_rt({ default_version = "5.9" })

S.eq(rt.parse_version("5.9"), 5009, "5.9")
S.eq(rt.parse_version(" 5.10.2"), 5010, "leading space and a third part")
S.eq(rt.parse_version("3.15"), 3015, "3.15")
S.eq(rt.parse_version("five"), nil, "no version")
S.eq(rt.parse_version(nil), nil, "nil")
S.eq(rt.default_version, 5009, "the spec's default version, parsed at load")
S.eq(rt.version_text(5009), "5.9", "5009 as text")
S.eq(rt.version_text(5010), "5.10", "5010 as text")
S.eq(rt.version_text(rt.parse_version("3.3")), "3.3", "round trip")

S.eq(rt.version_in(5009, nil, nil), true, "open range")
S.eq(rt.version_in(5009, 5009, nil), true, "low bound inclusive")
S.eq(rt.version_in(5008, 5009, nil), false, "below low")
S.eq(rt.version_in(5008, nil, 5008), true, "high bound inclusive")
S.eq(rt.version_in(5009, 3003, 5008), false, "above high")

local old, mid, new = { name = "old" }, { name = "mid" }, { name = "new" }
local tables = { { high = 3002, kinds = old }, { low = 3003, high = 5008, kinds = mid }, { low = 5009, kinds = new } }
S.eq(rt.value_table(tables, 3002), old, "3.2")
S.eq(rt.value_table(tables, 5000), mid, "5.0")
S.eq(rt.value_table(tables, 5008), mid, "5.8")
S.eq(rt.value_table(tables, 5012), new, "5.12")
S.eq(rt.value_table({ { low = 5009, kinds = new }, { low = 6000, kinds = old } }, 1000), old, "no range: the last table")

-- A Version message: header (5), timestamp (8), source (1), subtype 3, name (length 9), major 5,
-- minor 0, then 8 bytes (bugfix, build); as in the spec's reader.
local reader = { message = 20, subtype = 3, subtype_offset = 14, tail = 0, rest = 8,
                 steps = { { fixed = 15, prefix = 1, signed = true } } }
local msg = S.bytes(0, 0, 0, 45, 20, 0, 0, 0, 0, 0, 0, 0, 0, 0xfe, 3, 9) .. "URControl" ..
            S.bytes(5, 0, 0, 0, 0, 0, 0, 0, 0, 2)
S.eq(rt.announced_version(msg, 0, #msg, reader), 5000, "URControl 5.0")
S.eq(rt.announced_version("xx" .. msg, 2, #msg + 2, reader), 5000, "at an offset")
S.eq(rt.announced_version(msg, 0, #msg - 1, reader), nil, "one byte short of the rest")
S.eq(rt.announced_version(msg, 0, 14, reader), nil, "cut before the subtype")
local other = msg:sub(1, 14) .. S.bytes(7) .. msg:sub(16)
S.eq(rt.announced_version(other, 0, #other, reader), nil, "another subtype")
local bad = msg:sub(1, 15) .. S.bytes(0xff) .. msg:sub(17)
S.eq(rt.announced_version(bad, 0, #bad, reader), nil, "a negative name length")
print("ok")
