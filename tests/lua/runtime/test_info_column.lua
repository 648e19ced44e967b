-- runtime/lua/common/info_column.lua: a frame's Info column across the calls for it.
local S = dofile("stubs.lua")
local rt = S.load("common/info_column.lua")

local write = rt.info_writer(", ")
local col = S.column()
write({ number = 1 }, col, "a", false)
S.eq(tostring(col), "a", "the first words of a frame")
write({ number = 1 }, col, "b", true)
S.eq(tostring(col), "a, b", "a call's later words: after them")
write({ number = 1 }, col, "c", false)
S.eq(tostring(col), "a, b, c", "a later call for the frame, the column still holding its words: after them")

local fresh = S.column()
write({ number = 1 }, fresh, "d", false)
S.eq(tostring(fresh), "d", "a later pass over the frame starts from a fresh column: in its place")
write({ number = 2 }, fresh, "e", false)
S.eq(tostring(fresh), "e", "another frame: in its place")
fresh:set("written by another dissector")
write({ number = 2 }, fresh, "f", false)
S.eq(tostring(fresh), "f", "a column that holds other words: in their place")

-- Each writer keeps its own last words, with its own separator.
local other = rt.info_writer("; ")
local two = S.column()
other({ number = 2 }, two, "x", false)
write({ number = 2 }, two, "y", false)
S.eq(tostring(two), "y", "a writer appends only to its own words")
print("ok")
