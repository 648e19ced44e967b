-- State of each TCP stream: the software version its Version message announced or its layout
-- sizes showed (nil: none yet; `implied` names the versions of the form whose size showed it),
-- whether the dissector is resynchronising after a bad header, and the bytes carried over
-- from earlier segments while it does (a carry, runtime/carry.lua). First pass: the state moves
-- along, and a snapshot of it is kept for each dissector call (frame number and tvb length): a
-- carry is kept once, and a snapshot holds it with how many of its bytes the call started
-- with. Later passes (tshark -2, clicks in the GUI, in any order) reuse the snapshot, so both
-- agree.
-- Streams are keyed by their two ports (a number: no string is made per packet). Field.new(
-- "tcp.stream") gives nothing on a first pass without a tree (tshark -2), and Conversation only
-- exists from Wireshark 4.6. Two robots talking to clients that use the same port number at the
-- same time would share a state; a reused port pair starts over with its Version message.
local spec, rt = ...

local CALL_SPAN = 1048576   -- a call's key: frame number * CALL_SPAN + tvb length mod CALL_SPAN

local stream_version, stream_implied, stream_resync, stream_carry = {}, {}, {}, {}
-- by call (frame, tvb length), and by -frame
local snap_version, snap_implied, snap_resync, snap_carry, snap_carried = {}, {}, {}, {}, {}

-- A new capture: forget every stream.
local function reset()
    stream_version, stream_implied, stream_resync, stream_carry = {}, {}, {}, {}
    snap_version, snap_implied, snap_resync, snap_carry, snap_carried = {}, {}, {}, {}, {}
end

-- The state a call starts with, kept under a call's key or a frame's.
local function snapshot(at, version, implied, resync, carry, carried)
    snap_version[at], snap_implied[at], snap_resync[at] = version, implied, resync
    snap_carry[at], snap_carried[at] = carry, carried
end

-- That state again, as stream_load returns it.
local function snapshot_at(at, stream)
    return snap_version[at], snap_implied[at], snap_resync[at], snap_carry[at], snap_carried[at], stream
end

-- The state as a call with n bytes starts: version, implied, resync, carry, how many bytes of
-- the carry are this call's (nil: no carry), and the stream's key for stream_save.
local function stream_load(pinfo, n)
    local stream = pinfo.src_port * 65536 + pinfo.dst_port
    local key = pinfo.number * CALL_SPAN + n % CALL_SPAN
    local frame = -pinfo.number
    if pinfo.visited and snap_resync[key] ~= nil then
        return snapshot_at(key, stream)
    elseif pinfo.visited and snap_resync[frame] ~= nil then
        -- Later passes may hand over other bytes than the first (TCP reassembly replays
        -- differently): fall back to the state of the frame's first call.
        return snapshot_at(frame, stream)
    end
    local version, implied = stream_version[stream], stream_implied[stream]
    local resync, carry = stream_resync[stream] or false, stream_carry[stream]
    local carried = carry and carry.size
    if snap_resync[key] == nil then snapshot(key, version, implied, resync, carry, carried) end
    if snap_resync[frame] == nil then snapshot(frame, version, implied, resync, carry, carried) end
    return version, implied, resync, carry, carried, stream
end

-- The state as a call ends; kept on the first pass only.
local function stream_save(pinfo, stream, version, implied, resync, carry)
    if not pinfo.visited then
        stream_version[stream], stream_implied[stream] = version, implied
        stream_resync[stream], stream_carry[stream] = resync, carry
    end
end

spec.proto.init = reset
rt.stream_load, rt.stream_save, rt.stream_reset = stream_load, stream_save, reset
