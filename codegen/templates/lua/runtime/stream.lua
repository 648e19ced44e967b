-- State of each TCP stream: the software version its Version message announced or its layout
-- sizes showed (nil: none yet; `implied` names the versions of the form whose size showed it),
-- whether the dissector is resynchronising after a bad header, and the bytes carried over
-- from earlier segments while it does. First pass: the state moves along, and a snapshot of it
-- is kept for each dissector call (frame number and tvb length). Later passes (tshark -2, clicks
-- in the GUI, in any order) reuse the snapshot, so both agree.
-- Streams are keyed by their two ports (a number: no string is made per packet). Field.new(
-- "tcp.stream") gives nothing on a first pass without a tree (tshark -2), and Conversation only
-- exists from Wireshark 4.6. Two robots talking to clients that use the same port number at the
-- same time would share a state; a reused port pair starts over with its Version message.
local spec, rt = ...

local CALL_SPAN = 1048576   -- a call's key: frame number * CALL_SPAN + tvb length mod CALL_SPAN

local stream_version, stream_implied, stream_resync, stream_carry = {}, {}, {}, {}
-- by call (frame, tvb length), and by -frame
local snap_version, snap_implied, snap_resync, snap_carry = {}, {}, {}, {}

-- A new capture: forget every stream.
local function reset()
    stream_version, stream_implied, stream_resync, stream_carry = {}, {}, {}, {}
    snap_version, snap_implied, snap_resync, snap_carry = {}, {}, {}, {}
end

-- The state as a call with n bytes starts: version, implied, resync, carry, and the stream's
-- key for stream_save.
local function stream_load(pinfo, n)
    local stream = pinfo.src_port * 65536 + pinfo.dst_port
    local key = pinfo.number * CALL_SPAN + n % CALL_SPAN
    local frame = -pinfo.number
    if pinfo.visited and snap_resync[key] ~= nil then
        return snap_version[key], snap_implied[key], snap_resync[key], snap_carry[key], stream
    elseif pinfo.visited and snap_resync[frame] ~= nil then
        -- Later passes may hand over other bytes than the first (TCP reassembly replays
        -- differently): fall back to the state of the frame's first call.
        return snap_version[frame], snap_implied[frame], snap_resync[frame], snap_carry[frame], stream
    end
    local version, implied = stream_version[stream], stream_implied[stream]
    local resync, carry = stream_resync[stream] or false, stream_carry[stream]
    if snap_resync[key] == nil then
        snap_version[key], snap_implied[key], snap_resync[key], snap_carry[key] = version, implied, resync, carry
    end
    if snap_resync[frame] == nil then
        snap_version[frame], snap_implied[frame], snap_resync[frame], snap_carry[frame] = version, implied, resync, carry
    end
    return version, implied, resync, carry, stream
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
