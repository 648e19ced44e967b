-- The pace of Lua's garbage collector, set once at load (Wireshark runs every Lua plugin in one
-- state, so it is theirs too). Every field the tree shows leaves two Wireshark objects with a
-- finalizer, its TvbRange and its TreeItem, and five blocks of C memory: some 600 objects per
-- robot state under tshark -V, dead as the call returns. At Lua's default pace (a cycle once the
-- heap has doubled, stepmul 200) they wait many messages for their cycle, while glibc hands their
-- memory out again from all over a heap that grows with the capture (TCP reassembly keeps what
-- it reassembled): the collector's passes over them and malloc's over their chunks miss the cache
-- more and more, and each message cost more the further into the capture it was. Under -V, the
-- last 24k frames of the half of 100k messages cut at random took 1.48 times the first 24k of that
-- half at the default pace, 1.02 at this one (the Lua heap stays flat at either: nothing is kept
-- per frame). A cycle started sooner and run in larger steps frees them while they are few and
-- close: -V takes a tenth less time, -T fields a sixth, and no tree the same (make bench-lua).
local spec, rt = ...

local PAUSE = 150     -- a new cycle once the heap is 1.5 times what the last one kept
local STEPMUL = 1000  -- each step collects five times as much as Lua's default step

collectgarbage("setpause", PAUSE)
collectgarbage("setstepmul", STEPMUL)

rt.collector_pace = { pause = PAUSE, stepmul = STEPMUL }
