-- A reference for make bench-lua: a dissector for the robot's ports that only frames the
-- messages (asks TCP to reassemble the ones split over segments) and shows nothing. What it
-- costs tshark in memory is TCP reassembly's, which the real dissector pays as well.
local ur = Proto("ur", "UR messages, framed only")
local HEADER = 5
-- The field make bench-lua prints with -T fields, declared so that the same command runs here;
-- it is never added, so nothing is printed.
ur.fields = { ProtoField.double("ur.joint_data.q_actual", "q_actual") }

function ur.dissector(tvb, pinfo, tree)
    if pinfo.src_port ~= pinfo.match_uint then return tvb:len() end
    local raw = tvb:raw()
    local n, o = #raw, 0
    while o < n do
        if n - o < HEADER then
            pinfo.desegment_offset, pinfo.desegment_len = o, DESEGMENT_ONE_MORE_SEGMENT
            break
        end
        local b1, b2, b3, b4 = string.byte(raw, o + 1, o + 4)
        local size = ((b1 * 256 + b2) * 256 + b3) * 256 + b4
        if size < HEADER then break end
        if size > n - o then
            pinfo.desegment_offset, pinfo.desegment_len = o, size - (n - o)
            break
        end
        o = o + size
    end
    return n
end

DissectorTable.get("tcp.port"):add("30001,30002,30011,30012", ur)
