-- runtime/lua/packages/stream.lua: per-stream state on the first pass, snapshots on later ones.
local S = dofile("stubs.lua")
local spec = { proto = {}, header_size = 5 }
local rt = S.load("packages/carry.lua", spec)
S.load("common/tcp_stream.lua", spec, rt)
S.load("packages/stream.lua", spec, rt)
S.eq(spec.proto.init, rt.stream_reset, "ur.init forgets every stream")

local function call(number, n, visited)
    return rt.stream_load(S.pinfo(number, visited), n)
end

-- First pass: a new stream starts with nothing; what a call saves the next one loads.
local v, implied, resync, carry, carried, stream = call(1, 100)
S.eq(v, nil, "no version yet"); S.eq(implied, nil, "none implied"); S.eq(resync, false, "in step")
S.eq(carry, nil, "nothing carried"); S.eq(carried, nil, "no carried bytes")
S.eq(stream, "192.168.56.101 192.168.56.1 " .. (30001 * 65536 + 50000), "keyed by both addresses and ports")
rt.stream_save(S.pinfo(1), stream, 3004999, "3.2 to 3.4", false, nil)
v, implied = call(2, 50)
S.eq(v, 3004999, "a version the layout sizes showed moves along"); S.eq(implied, "3.2 to 3.4", "with its versions")
local ab = rt.carry_new("ab")
rt.stream_save(S.pinfo(2), stream, 5009000, nil, true, ab)
v, implied, resync, carry, carried = call(3, 10)
S.eq(v, 5009000, "an announced version"); S.eq(implied, nil, "replaces the implied one")
S.eq(resync, true, "resynchronising"); S.eq(carry, ab, "the carry"); S.eq(carried, 2, "its bytes so far")
-- The carry grows over the next calls: one carry, and each call knows where it started.
rt.carry_add(ab, "cdefghij")
rt.stream_save(S.pinfo(3), stream, 5009000, nil, false, ab)
v, implied, resync, carry, carried = call(4, 3)
S.eq(carry, ab, "the same carry"); S.eq(carried, 10, "ten bytes carried before frame 4")
rt.carry_add(ab, "klm")
rt.stream_save(S.pinfo(4), stream, 5010000, nil, false, nil)

-- Later passes, in any order: each call gets the state its first-pass call started with.
v, implied, resync, carry = call(2, 50, true)
S.eq(v, 3004999, "frame 2"); S.eq(implied, "3.2 to 3.4", "frame 2 implied")
S.eq(resync, false, "frame 2 in step"); S.eq(carry, nil, "frame 2 carried nothing")
v, implied, resync, carry, carried = call(3, 10, true)
S.eq(resync, true, "frame 3"); S.eq(carry, ab, "frame 3 carried"); S.eq(implied, nil, "frame 3 announced")
S.eq(carried, 2, "frame 3 started with two carried bytes")
v, implied, resync, carry, carried = call(4, 3, true)
S.eq(carried, 10, "frame 4 with ten"); S.eq(rt.carry_bytes(carry, carried), "abcdefghij", "which are still there")
v = call(1, 100, true)
S.eq(v, nil, "frame 1")
-- Other bytes for a known frame (reassembly replays differently): the frame's first call.
v, implied, resync, carry, carried = call(3, 77, true)
S.eq(carry, ab, "fallback to the frame's first call"); S.eq(carried, 2, "with its carried bytes")
-- Saving on a later pass changes nothing.
rt.stream_save(S.pinfo(3, true), stream, 1, "x", true, "zz")
S.eq((call(5, 1)), 5010000, "the first pass's state")

rt.stream_reset()
S.eq((call(5, 1)), nil, "a new capture starts over")

-- A new TCP conversation on the same addresses and ports (tcp.stream, where the tree has it)
-- starts the stream over, as the native plugin's conversation does; no index changes nothing.
rt.stream_reset()
S.fields["tcp.stream"] = { value = 0 }
_, _, _, _, _, stream = call(1, 10)
rt.stream_save(S.pinfo(1), stream, 5009000, nil, true, rt.carry_new("xy"))
S.fields["tcp.stream"] = nil
v, _, resync = call(2, 10)
S.eq(v, 5009000, "no index: the same stream"); S.eq(resync, true, "still resynchronising")
rt.stream_save(S.pinfo(2), stream, 5009000, nil, true, nil)
S.fields["tcp.stream"] = { value = 0 }
S.eq((call(3, 10)), 5009000, "the same conversation")
rt.stream_save(S.pinfo(3), stream, 5009000, nil, true, nil)
S.fields["tcp.stream"] = { value = 7 }
v, implied, resync, carry = call(4, 10)
S.eq(v, nil, "a new conversation: no version"); S.eq(resync, false, "in step")
S.eq(carry, nil, "nothing carried")
S.eq((call(3, 10, true)), 5009000, "a later pass: frame 3 still had the last conversation's")
S.eq((call(4, 10, true)), nil, "and frame 4 the new one's")
S.fields["tcp.stream"] = nil

-- A stream in step keeps snapshots where its state changes, not per frame: 10,000 frames after
-- a Version message keep the frame that first started with it, whatever the frames before.
rt.stream_reset()
local key
for f = 1, 10000 do
    local _
    _, _, _, _, _, key = call(f, 1000)
    if f == 3 then rt.stream_save(S.pinfo(f), key, 5009000, nil, false, nil) end
end
S.eq(rt.stream_kept(), 1, "one snapshot for 10,000 frames")
S.eq((call(2, 1000, true)), nil, "before the Version message")
S.eq((call(3, 1000, true)), nil, "the frame of the Version message")
S.eq((call(4, 1000, true)), 5009000, "the next frame")
S.eq((call(9999, 7, true)), 5009000, "any later frame, any bytes")

-- Two calls in one frame, the state changing between them: each gets its own on later passes.
rt.stream_reset()
call(1, 10)
call(2, 300)
rt.stream_save(S.pinfo(2), key, 5010000, nil, false, nil)
call(2, 20)
call(3, 5)
S.eq((call(2, 300, true)), nil, "the frame's first call, before the change")
S.eq((call(2, 20, true)), 5010000, "its second call, after it")
S.eq((call(3, 5, true)), 5010000, "and the frames after")
S.eq((call(1, 10, true)), nil, "and before")
-- Two robots on the same port numbers: two streams, each with its own state.
rt.stream_reset()
local _, robot_a, robot_b
_, _, _, _, _, robot_a = rt.stream_load(S.pinfo(1, false, "10.0.0.1"), 100)
rt.stream_save(S.pinfo(1, false, "10.0.0.1"), robot_a, 3015000, nil, false, nil)
_, _, _, _, _, robot_b = rt.stream_load(S.pinfo(2, false, "10.0.0.2"), 100)
rt.stream_save(S.pinfo(2, false, "10.0.0.2"), robot_b, 5011000, nil, false, nil)
S.eq((rt.stream_load(S.pinfo(3, false, "10.0.0.1"), 100)), 3015000, "robot A keeps its version")
S.eq((rt.stream_load(S.pinfo(4, false, "10.0.0.2"), 100)), 5011000, "robot B keeps its own")
S.eq((rt.stream_load(S.pinfo(3, true, "10.0.0.1"), 100)), 3015000, "and so on later passes")
print("ok")
