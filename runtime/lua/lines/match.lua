-- Lines, commands and replies of the dashboard server, as the spec's tables say: which command
-- a line is, which reply a line is (the common replies first, then the command's own), whether
-- a software version has a command, and the version a version reply tells. Pure functions of
-- the tables; no Wireshark API, so that it runs alone under Lua 5.2-5.4.
local spec, rt = ...

local find, sub = string.find, string.sub
local dotted_version = rt.dotted_version

-- The whole text is the pattern: its first piece opens it, its last ends it, the others follow
-- in order between them, and each placeholder takes any text.
local function matches(pieces, text)
    local n = #pieces
    if n == 1 then return text == pieces[1] end
    local first, last = pieces[1], pieces[n]
    if #text < #first + #last or sub(text, 1, #first) ~= first or sub(text, #text - #last + 1) ~= last then
        return false
    end
    local at, stop = #first + 1, #text - #last
    for i = 2, n - 1 do
        local s, e = find(text, pieces[i], at, true)
        if not s or e > stop then return false end
        at = e + 1
    end
    return true
end

-- The command a line is (its index in spec.commands) and its argument, or nil. A command with no
-- text (interpreter mode's statement), tried last, is any line, its argument the whole line.
local function find_command(text)
    for _, index in ipairs(spec.lookup) do
        local command = spec.commands[index]
        local words = command.text
        if words == "" then return index, text end
        if text == words then return index, nil end
        if command.argument and sub(text, 1, #words + 1) == words .. " " then
            return index, sub(text, #words + 2)
        end
    end
    return nil, nil
end

-- The reply a line is, given the command it answers (an index or nil), or nil.
local function classify(command, text)
    for _, reply in ipairs(spec.common) do
        if matches(reply.pieces, text) then return reply end
    end
    if command then
        for _, reply in ipairs(spec.commands[command].replies) do
            if matches(reply.pieces, text) then return reply end
        end
    end
    return nil
end

local function version_number(major, minor, bugfix)
    return (major * 1000 + math.min(minor, 999)) * 1000 + math.min(bugfix, 999)
end

-- Whether the software version (a version_number) has the command.
local function available(command, version)
    local c = spec.commands[command]
    local since
    if version >= spec.polyscope_x_from then since = c.since_polyscope_x
    elseif version >= spec.e_series_from then since = c.since_e_series
    else since = c.since_cb end
    return since ~= nil and version >= since
end

-- "URSoftware 5.11.1.108318 (Nov 26 2021)" -> the version_number of 5.11.1, or nil: the word
-- after the prefix, split at its dots, whose first two or three parts are 1 to 3 digits.
local function version_in(text)
    local prefix = spec.version_prefix
    if sub(text, 1, #prefix) ~= prefix then return nil end
    local word = string.match(sub(text, #prefix + 1), "^[^ ]*")
    local parts, at = {}, 1
    while #parts < 3 do
        local dot = find(word, ".", at, true)
        parts[#parts + 1] = sub(word, at, (dot or #word + 1) - 1)
        if not dot then break end
        at = dot + 1
    end
    if #parts < 2 then return nil end
    for _, part in ipairs(parts) do
        if not string.match(part, "^%d%d?%d?$") then return nil end
    end
    return version_number(tonumber(parts[1]), tonumber(parts[2]), tonumber(parts[3] or "0"))
end

-- "5.11" or "5.11.1" -> its version_number; nil for anything else.
local function parse_version(text)
    local major, minor, bugfix = dotted_version(text)
    if not major then return nil end
    return version_number(major, minor, bugfix)
end

-- Text as every output shows it: up to its first NUL (as C strings end), in UTF-8, each
-- ill-formed sequence replaced by one U+FFFD per maximal subpart (the Unicode Standard's Table 3-7,
-- as Wireshark's ENC_UTF_8 and Python's decode("utf-8", "replace") do).
local REPLACEMENT = "\239\191\189"
local function shown(text)
    local nul = find(text, "\0", 1, true)
    if nul then text = sub(text, 1, nul - 1) end
    if not find(text, "[\128-\255]") then return text end
    local out, at, start, n = {}, 1, 1, #text
    while at <= n do
        local b = string.byte(text, at)
        if b < 0x80 then
            at = at + 1
        else
            -- how many continuation bytes the lead byte wants, and the range of the first of them
            local need, lo, hi = 0, 0x80, 0xBF
            if b >= 0xC2 and b <= 0xDF then need = 1
            elseif b == 0xE0 then need, lo = 2, 0xA0
            elseif (b >= 0xE1 and b <= 0xEC) or b == 0xEE or b == 0xEF then need = 2
            elseif b == 0xED then need, hi = 2, 0x9F
            elseif b == 0xF0 then need, lo = 3, 0x90
            elseif b >= 0xF1 and b <= 0xF3 then need = 3
            elseif b == 0xF4 then need, hi = 3, 0x8F
            end
            local next_at, got = at + 1, 0
            while got < need do
                local c = string.byte(text, next_at)
                if not c or c < lo or c > hi then break end
                lo, hi = 0x80, 0xBF
                next_at, got = next_at + 1, got + 1
            end
            if need == 0 or got < need then
                out[#out + 1] = sub(text, start, at - 1) .. REPLACEMENT
                start = next_at
            end
            at = next_at
        end
    end
    out[#out + 1] = sub(text, start)
    return table.concat(out)
end

rt.matches, rt.find_command, rt.classify, rt.shown = matches, find_command, classify, shown
rt.available, rt.version_in, rt.parse_version = available, version_in, parse_version
