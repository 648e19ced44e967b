-- Bytes carried over by hand from segment to segment while a stream is out of step with TCP
-- reassembly (after a bad header). Each call's bytes are kept as one more part, and the parts
-- are joined once, when the message they hold is whole: carrying n bytes costs time and memory
-- in n, however small the segments. A carry starts at a message header (or holds less than
-- one) and is only appended to, so its first k bytes, where a call started, stay the same for
-- later passes; one carry is shared by every call it spans.
local spec, rt = ...
local concat, sub = table.concat, string.sub
local HEADER = spec.header_size

-- A carry holding the bytes s. head: its first bytes, up to a header's worth.
local function carry_new(s)
    return { parts = { s }, size = #s, head = sub(s, 1, HEADER) }
end

-- Carry c takes the bytes s of one more call.
local function carry_add(c, s)
    local parts = c.parts
    parts[#parts + 1] = s
    c.size = c.size + #s
    if #c.head < HEADER then c.head = sub(c.head .. s, 1, HEADER) end
end

-- The first n bytes of carry c as one string. The parts are joined once and kept joined.
local function carry_bytes(c, n)
    local parts = c.parts
    if #parts > 1 then
        parts = { concat(parts) }
        c.parts = parts
    end
    local all = parts[1]
    if n == #all then return all end
    return sub(all, 1, n)
end

rt.carry_new, rt.carry_add, rt.carry_bytes = carry_new, carry_add, carry_bytes
