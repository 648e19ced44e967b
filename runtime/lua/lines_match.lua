-- Lines, commands and replies of the dashboard server, as the spec's tables say: which command
-- a line is, which reply a line is (the common replies first, then the command's own), whether
-- a software version has a command, and the version a version reply tells. Pure functions of
-- the tables; no Wireshark API, so that it runs alone under Lua 5.2-5.4.
local spec, rt = ...

local find, sub = string.find, string.sub

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

-- The command a line is (its index in spec.commands) and its argument, or nil.
local function find_command(text)
    for _, index in ipairs(spec.lookup) do
        local command = spec.commands[index]
        local words = command.text
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
    if version >= spec.e_series_from then since = c.since_e_series else since = c.since_cb end
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
    local major, minor, bugfix = string.match(text or "", "^%s*(%d+)%.(%d+)%.?(%d*)%s*$")
    if not major then return nil end
    return version_number(tonumber(major), tonumber(minor), tonumber(bugfix) or 0)
end

rt.matches, rt.find_command, rt.classify = matches, find_command, classify
rt.available, rt.version_in, rt.parse_version = available, version_in, parse_version
