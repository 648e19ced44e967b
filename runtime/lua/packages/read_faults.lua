-- The canonical texts of a read that does not fit in its message, as every target words them.
local spec, rt = ...
local fmt = string.format

-- "<path> at offset <o>: needs <need> bytes, <left> left"; offsets from the message's first
-- byte (st.base).
local function short(st, path, o, need, e)
    local left = e - o
    if left < 0 then left = 0 end
    return fmt("%s at offset %d: needs %d bytes, %d left", path, o - st.base, need, left)
end

-- A length prefix, list count or matrix size below zero.
local function negative(st, path, o, n)
    return fmt("%s at offset %d: negative length %d", path, o - st.base, n)
end

rt.short, rt.negative = short, negative
