-- runtime/lua/packages/collector.lua: the collector's pace is set as the file loads.
local S = dofile("stubs.lua")
collectgarbage("setpause", 200)
collectgarbage("setstepmul", 200)
local rt = S.load("packages/collector.lua")
local pace = rt.collector_pace
S.eq(pace.pause < 200 and pace.stepmul > 200, true, "sooner and larger than Lua's default")
-- Setting a value answers the one before it (Lua 5.4 keeps the pause in steps of 4).
local pause = collectgarbage("setpause", 200)
S.eq(pause >= pace.pause - 3 and pause <= pace.pause, true, "the pause is set")
S.eq(collectgarbage("setstepmul", 200), pace.stepmul, "the step multiplier is set")
print("ok")
