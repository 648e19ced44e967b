-- runtime/lua/packages/versions.lua: parse, show and compare versions (major.minor.bugfix as one
-- number); choose a value table, an enum's names and a package's form by the version, else by the
-- length; read the version a Version message announces.
local S = dofile("stubs.lua")
local rt = S.base_rt({ default_version = "5.9" })

S.eq(rt.parse_version("5.9"), 5009000, "5.9")
S.eq(rt.parse_version("5.25.1"), 5025001, "5.25.1")
S.eq(rt.parse_version(" 5.10.2"), 5010002, "leading space and a bugfix")
S.eq(rt.parse_version("3.15"), 3015000, "3.15")
S.eq(rt.parse_version("5.9.4000"), 5009999, "a bugfix past 999 is any bugfix")
S.eq(rt.parse_version("five"), nil, "no version")
S.eq(rt.parse_version(""), nil, "empty: no version")
S.eq(rt.parse_version(nil), nil, "nil")
S.eq(rt.default_version, 5009000, "the spec's default version, parsed at load")
S.eq(rt.version_number(5, 25, 1), 5025001, "a number from its parts")
S.eq(rt.version_text(5009000), "5.9", "5.9 as text")
S.eq(rt.version_text(5010000), "5.10", "5.10 as text")
S.eq(rt.version_text(5025001), "5.25.1", "a bugfix release as text")
S.eq(rt.version_text(5008999), "5.8", "an upper bound: any 5.8.x")
S.eq(rt.version_text(10000000), "10.0", "PolyScope X")
S.eq(rt.version_text(rt.parse_version("3.3")), "3.3", "round trip")
S.eq(rt.version_text(rt.parse_version("5.25.1")), "5.25.1", "round trip with a bugfix")

S.eq(rt.version_in(5009000, nil, nil), true, "open range")
S.eq(rt.version_in(5009000, 5009000, nil), true, "low bound inclusive")
S.eq(rt.version_in(5008999, 5009000, nil), false, "below low")
S.eq(rt.version_in(5008999, nil, 5008999), true, "high bound inclusive")
S.eq(rt.version_in(5008003, nil, 5008999), true, "5.8.3 is within 'until 5.8'")
S.eq(rt.version_in(5009000, 3003000, 5008999), false, "above high")

local old, mid, new = { name = "old" }, { name = "mid" }, { name = "new" }
local tables = { { high = 3002999, kinds = old }, { low = 3003000, high = 5008999, kinds = mid }, { low = 5009000, kinds = new } }
S.eq(rt.value_table(tables, 3002000).kinds, old, "3.2")
S.eq(rt.value_table(tables, 5000000).kinds, mid, "5.0")
S.eq(rt.value_table(tables, 5008007).kinds, mid, "5.8.7")
S.eq(rt.value_table(tables, 5012000).kinds, new, "5.12")
S.eq(rt.value_table({ { low = 5009000, kinds = new }, { low = 6000000, kinds = old } }, 1000000).kinds, old,
     "no range: the last table")

-- Enum names by version: the table in force, else the newest.
local NEWEST, EARLY = { [240] = "READY_FOR_POWER_OFF" }, { [240] = "EMERGENCY_STOPPED" }
local NAMES = { newest = NEWEST, { high = 5000999, names = EARLY }, { low = 5001000, names = NEWEST } }
S.eq(rt.enum_names(NAMES, 3002000), EARLY, "early names")
S.eq(rt.enum_names(NAMES, 5001000), NEWEST, "newest names")
S.eq(rt.enum_names({ newest = NEWEST, { low = 6000000, names = EARLY } }, 5000000), NEWEST, "no range: the newest")
S.eq(rt.named_in_any(NAMES, 240), true, "named in some version")
S.eq(rt.named_in_any(NAMES, 7), false, "named in none")

-- Forms: one up to 3.1 (29 bytes), one from 3.2 (46 or 52 bytes, a flag's part in or out), one
-- open-ended from 5.1 (at least 60 bytes). The segments of the version axis start at 1.9, 3.0,
-- 3.2 and 5.1 (as the generator cuts them for every type code of the spec).
local frt = S.base_rt({ default_version = "5.9", segment_starts = { "1.9", "3.0", "3.2", "5.1" } })
S.eq(frt.segment_of(1008000), 1, "below the first start: segment 1")
S.eq(frt.segment_of(3000000), 3, "a start is its segment's first version")
S.eq(frt.segment_of(3001999), 3, "any 3.1.x")
S.eq(frt.segment_of(5001000), 5, "the last segment has no end")
S.eq(frt.segment_of(99000000), 5, "nor an end far above")
local A = { sizes = { [29] = true }, min = 29, rep = "3.1", versions = "up to 3.1" }
local B = { sizes = { [46] = true, [52] = true }, min = 46, rep = "5.0", versions = "3.2 to 5.0" }
local C = { min = 60, rep = "5.9", versions = "5.1 and later" }
local FORMS = { segments = { 1, 1, 1, 2, 3 }, by_length = { [29] = 1, [46] = 2, [52] = 2 }, A, B, C }
local function chose(size, v, form, use, by_length)
    local f, u, b = frt.choose(FORMS, size, v)
    S.eq(f, form, string.format("form for %d bytes at %s", size, frt.version_text(v)))
    S.eq(u, use, string.format("version for %d bytes at %s", size, frt.version_text(v)))
    S.eq(b, by_length, string.format("by length for %d bytes at %s", size, frt.version_text(v)))
end
chose(46, 3004000, B, 3004000, false)     -- the version's form fits
chose(52, 3004000, B, 3004000, false)     -- with its flagged part
chose(29, 3004000, A, 3001000, true)      -- only A fits: its version
chose(29, 5009000, A, 3001000, true)
chose(70, 3004000, B, 3004000, false)     -- open-ended C fits too much to be recognised by length
chose(30, 3004000, B, 3004000, false)     -- none fits: the version's form, flagged later
chose(30, 1008000, A, 1008000, false)
chose(61, 5009000, C, 5009000, false)
local gap = { segments = { 1, -1, 2, 2, 2 }, by_length = {},
              { sizes = { [10] = true }, min = 10, rep = "1.8", versions = "up to 1.8" },
              { sizes = { [10] = true }, min = 10, rep = "5.9", versions = "3.0 and later" } }
local f, u, b = frt.choose(gap, 10, 2000000)
S.eq(f, gap[1], "no form for the version: the nearest below"); S.eq(u, 1008000, "read as its version")
S.eq(b, false, "not by length")
local single = { single = true, { sizes = { [4] = true }, min = 4, rep = "5.9", versions = "all versions" } }
f, u, b = frt.choose(single, 9, 3002000)
S.eq(f, single[1], "one form for every version"); S.eq(u, 3002000, "read with the stream's version"); S.eq(b, false, "never by length")

-- pick: a stream whose version is not known takes the version of a form chosen by length.
local st = { version = 5009000, known = false }
f, u, b = frt.pick(FORMS, 29, st)
S.eq(st.version, 3001000, "unknown: the form's version for the rest of the message")
S.eq(st.implied, "up to 3.1", "and where it came from")
f, u, b = frt.pick(FORMS, 46, st)
S.eq(f, B, "the next package by its length"); S.eq(st.version, 5000000, "moves on again"); S.eq(st.implied, "3.2 to 5.0", "")
st = { version = 5009000, known = true }
f, u, b = frt.pick(FORMS, 29, st)
S.eq(f, A, "known: the form by length"); S.eq(u, 3001000, "read with its version"); S.eq(b, true, "by length")
S.eq(st.version, 5009000, "a known version stays"); S.eq(st.implied, nil, "nothing implied")

-- A Version message: header (5), timestamp (8), source (1), subtype 3, name (length 9), major 5,
-- minor 0, then 8 bytes (bugfix, build); as in the spec's reader.
local reader = { message = 20, subtype = 3, subtype_offset = 14, tail = 0, rest = 8,
                 steps = { { fixed = 15, prefix = 1, signed = true } } }
local function version_message(major, minor, bugfix)
    return S.bytes(0, 0, 0, 45, 20, 0, 0, 0, 0, 0, 0, 0, 0, 0xfe, 3, 9) .. "URControl" ..
           S.bytes(major, minor, 0, 0, 0, bugfix, 0, 0, 0, 2)
end
local msg = version_message(5, 0, 0)
S.eq(rt.announced_version(msg, 0, #msg, reader), 5000000, "URControl 5.0")
S.eq(rt.announced_version("xx" .. msg, 2, #msg + 2, reader), 5000000, "at an offset")
S.eq(rt.announced_version(msg, 0, #msg - 1, reader), nil, "one byte short of the rest")
S.eq(rt.announced_version(msg, 0, 14, reader), nil, "cut before the subtype")
local other = msg:sub(1, 14) .. S.bytes(7) .. msg:sub(16)
S.eq(rt.announced_version(other, 0, #other, reader), nil, "another subtype")
local bad = msg:sub(1, 15) .. S.bytes(0xff) .. msg:sub(17)
S.eq(rt.announced_version(bad, 0, #bad, reader), nil, "a negative name length")
msg = version_message(5, 25, 1)
S.eq(rt.announced_version(msg, 0, #msg, reader), 5025000, "no bugfix in the reader: major.minor only")
-- The bugfix number from 3.3 on; before, the same bytes are an svn revision.
reader.bugfix = { n = 4, signed = true, low = 3003000 }
S.eq(rt.announced_version(msg, 0, #msg, reader), 5025001, "5.25.1")
msg = version_message(3, 2, 7)
S.eq(rt.announced_version(msg, 0, #msg, reader), 3002000, "3.2: an svn revision, not a bugfix")
msg = version_message(3, 3, 7)
S.eq(rt.announced_version(msg, 0, #msg, reader), 3003007, "3.3.7")
-- A bugfix out of range (below 0, above 999) is set aside: major.minor, then the number and
-- where it is.
local function with_bugfix(bytes4)
    local m = version_message(5, 0, 0)
    return m:sub(1, 27) .. bytes4 .. m:sub(32)
end
msg = with_bugfix(S.bytes(0xff, 0xff, 0xff, 0xff))
local v, bugfix, at = rt.announced_version(msg, 0, #msg, reader)
S.eq(v, 5000000, "bugfix -1: 5.0"); S.eq(bugfix, -1, "the number set aside"); S.eq(at, 27, "at its offset")
msg = with_bugfix(S.bytes(0, 0, 3, 0xe8))
v, bugfix, at = rt.announced_version(msg, 0, #msg, reader)
S.eq(v, 5000000, "bugfix 1000: 5.0"); S.eq(bugfix, 1000, "the number set aside")
msg = with_bugfix(S.bytes(0, 0, 3, 0xe7))
v, bugfix, at = rt.announced_version(msg, 0, #msg, reader)
S.eq(v, 5000999, "bugfix 999 is in range"); S.eq(bugfix, nil, "nothing set aside")
print("ok")
