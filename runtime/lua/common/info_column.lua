-- The Info column of a frame that the dissector is called for more than once: TCP calls it for
-- a message reassembled from earlier segments, then again for the rest of the segment. A later
-- call adds its words to the earlier one's while the column still holds them; a later pass, or
-- the GUI dissecting the frame again, starts from a fresh column and writes it anew.
local spec, rt = ...

-- A writer of the Info column that joins words with `separator`: write(pinfo, col, words,
-- append) puts words after the column's text when `append` (a call's later message) or when
-- the column holds what this writer last wrote for the same frame, else in its place.
local function info_writer(separator)
    local frame, text = -1, ""
    return function(pinfo, col, words, append)
        if append or (frame == pinfo.number and tostring(col) == text) then
            text = text .. separator .. words
            col:append(separator .. words)
        else
            text = words
            col:set(words)
        end
        frame = pinfo.number
    end
end

rt.info_writer = info_writer
