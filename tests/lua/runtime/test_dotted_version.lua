-- runtime/lua/common/dotted_version.lua: the three numbers of a version preference, or nil.
local S = dofile("stubs.lua")
local rt = S.load("common/dotted_version.lua")

local function parts(text) return table.concat({ rt.dotted_version(text) }, " ") end
S.eq(parts("5.9"), "5 9 0", "major.minor: the bugfix is 0")
S.eq(parts("3.15.2"), "3 15 2", "major.minor.bugfix")
S.eq(parts(" \t2.10.0  "), "2 10 0", "blanks around it")
S.eq(parts("5.9."), "5 9 0", "a dot with no bugfix after it")
S.eq(parts("1.1234.99999"), "1 1234 99999", "parts as written: the kind clamps them")
S.eq(parts("007.08"), "7 8 0", "leading zeros")
for _, text in ipairs({ "", "5", "5.", ".9", "5.9.1.2", "5.9 beta", "v5.9", "5,9", "latest" }) do
    S.eq(rt.dotted_version(text), nil, "not a version: '" .. text .. "'")
end
S.eq(rt.dotted_version(nil), nil, "no text")
S.eq(math.type and math.type((rt.dotted_version("5.9"))) or "integer", "integer", "integers on Lua 5.3 and 5.4")
print("ok")
