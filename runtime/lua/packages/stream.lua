-- State of each TCP stream: the software version its Version message announced or its layout
-- sizes showed (nil: none yet; `implied` names the versions of the form whose size showed it),
-- whether the dissector is resynchronising after a bad header, and the bytes carried over
-- from earlier segments while it does (a carry, runtime/lua/packages/carry.lua). First pass: the state moves
-- along. Later passes (tshark -2, clicks in the GUI, in any order) must start each dissector
-- call (frame number and tvb length) with the state its first-pass call started with.
-- That state changes rarely (a Version message, a bad header, the calls that carry bytes), so
-- it is kept only where it changes: a frame in which some call starts with another state than
-- the call before it is kept, with a snapshot per call and the snapshot its last call started
-- with; a frame that keeps nothing starts with that of the last frame kept before it (found by
-- bisection). A capture in step costs memory per stream, not per frame.
-- Streams are keyed by both addresses and both ports ("192.168.56.101 192.168.56.1 30001 50000"),
-- so that two robots, or two clients of one robot, never share a state, even on the same port
-- numbers. A stream starts over, as the native plugin's conversation does, where Wireshark's TCP
-- starts a new conversation on the same addresses and ports (a SYN, even a mutated one on the
-- client's side): the first pass sees it as a new tcp.stream index. Field.new("tcp.stream") gives
-- nothing on a first pass without a tree (tshark -2 with no filter), and Conversation only exists
-- from Wireshark 4.6: there a reused address and port pair starts over only with its Version message.
local spec, rt = ...
local floor = math.floor

local CALL_SPAN = 1048576   -- a call's key: frame number * CALL_SPAN + tvb length mod CALL_SPAN
local tcp_stream_index = rt.tcp_stream_index

-- A snapshot: { version, implied, resync, carry, carried = how many bytes the carry held }.
-- NONE: a stream that nothing has happened on yet.
local NONE = { resync = false }

local streams    -- by port pair: its state now, and what later passes need (see stream_of)
local at_call    -- snapshots of the calls of kept frames, by call key
local at_frame   -- the snapshot of the first call of each kept frame, by frame number

-- A new capture: forget every stream.
local last_frame   -- the frame of the last stream key made (stream_key, below)

local function reset()
    streams, at_call, at_frame = {}, {}, {}
    last_frame = nil
end
reset()

-- s: the state now (version, implied, resync, carry); last: the snapshot the latest call
-- started with; frame: that call's frame, keeping: whether that frame is kept, and while it is
-- not, its calls so far (keys[1..n], snaps[1..n]); kept: the kept frames in order, after: the
-- snapshot the last call of each started with.
local function stream_of(key)
    local s = streams[key]
    if not s then
        s = { resync = false, last = NONE, frame = -1, keeping = false, keys = {}, snaps = {}, n = 0,
              kept = {}, after = {} }
        streams[key] = s
    end
    return s
end

local function same(snap, version, implied, resync, carry, carried)
    return snap.version == version and snap.implied == implied and snap.resync == resync
        and snap.carry == carry and snap.carried == carried
end

-- The snapshot a frame that kept nothing started with.
local function before(s, frame)
    local kept = s.kept
    local lo, hi, found = 1, #kept, nil
    while lo <= hi do
        local mid = floor((lo + hi) / 2)
        if kept[mid] < frame then found, lo = kept[mid], mid + 1 else hi = mid - 1 end
    end
    return found and s.after[found] or NONE
end

-- A later pass: the snapshot of the call, else of its frame's first call (TCP reassembly may
-- hand over other bytes than on the first pass), else of the frames before it.
local function recall(stream, key, frame)
    local snap = at_call[key] or at_frame[frame]
    if snap then return snap end
    local s = streams[stream]
    return s and before(s, frame) or NONE
end

-- The first pass: the call starts with the stream's state now; kept when it differs from the
-- state the call before it started with, and so is every call of its frame.
local function note(s, key, frame)
    local version, implied, resync, carry = s.version, s.implied, s.resync, s.carry
    local carried = carry and carry.size
    local snap, changed = s.last, false
    if not same(snap, version, implied, resync, carry, carried) then
        snap = { version = version, implied = implied, resync = resync, carry = carry, carried = carried }
        changed = true
    end
    s.last = snap
    if frame ~= s.frame then s.frame, s.keeping, s.n = frame, false, 0 end
    if changed and not s.keeping then
        s.keeping = true
        s.kept[#s.kept + 1] = frame
        local keys, snaps = s.keys, s.snaps
        for i = 1, s.n do
            if at_call[keys[i]] == nil then at_call[keys[i]] = snaps[i] end
        end
        if s.n > 0 then at_frame[frame] = snaps[1] end
    end
    if s.keeping then
        if at_call[key] == nil then at_call[key] = snap end
        if at_frame[frame] == nil then at_frame[frame] = snap end
        s.after[frame] = snap
    else
        local n = s.n + 1
        s.n, s.keys[n], s.snaps[n] = n, key, snap
    end
    return snap
end

-- The stream's key: its addresses as text and its ports. Making the text costs more than the rest
-- of a call's bookkeeping, so the last key is kept with the frame, addresses and ports it was made
-- from (Address objects compare in C) and given again while they recur, as they do call after
-- call: the calls of one frame are one TCP segment's, and the frames of a stream follow each other.
local last_src, last_dst, last_ports, last_key = nil, nil, nil, nil
local function stream_key(pinfo)
    if pinfo.number == last_frame then return last_key end
    last_frame = pinfo.number
    local src, dst, ports = pinfo.src, pinfo.dst, pinfo.src_port * 65536 + pinfo.dst_port
    if ports ~= last_ports or src ~= last_src or dst ~= last_dst then
        last_src, last_dst, last_ports = src, dst, ports
        last_key = tostring(src) .. " " .. tostring(dst) .. " " .. ports
    end
    return last_key
end

-- First pass: a stream whose TCP conversation is not the one it was seen in last starts over.
local function follow_conversation(s)
    local index = tcp_stream_index()
    if index == nil then return end
    if s.conversation ~= nil and s.conversation ~= index then
        s.version, s.implied, s.resync, s.carry = nil, nil, false, nil
    end
    s.conversation = index
end

-- The state as a call with n bytes starts: version, implied, resync, carry, how many bytes of
-- the carry are this call's (nil: no carry), and the stream's key for stream_save.
local function stream_load(pinfo, n)
    local stream = stream_key(pinfo)
    local frame = pinfo.number
    local key = frame * CALL_SPAN + n % CALL_SPAN
    local snap
    if pinfo.visited then
        snap = recall(stream, key, frame)
    else
        local s = stream_of(stream)
        follow_conversation(s)
        snap = note(s, key, frame)
    end
    return snap.version, snap.implied, snap.resync, snap.carry, snap.carried, stream
end

-- The state as a call ends; kept on the first pass only.
local function stream_save(pinfo, stream, version, implied, resync, carry)
    if not pinfo.visited then
        local s = stream_of(stream)
        s.version, s.implied, s.resync, s.carry = version, implied, resync, carry
    end
end

-- How many snapshots later passes keep (for tests: it grows with changes, not frames).
local function stream_kept()
    local n = 0
    for _ in pairs(at_call) do n = n + 1 end
    return n
end

spec.proto.init = reset
rt.stream_load, rt.stream_save, rt.stream_reset, rt.stream_kept = stream_load, stream_save, reset, stream_kept
