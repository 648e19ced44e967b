-- Which of a protocol's fields a `tshark -T fields` run needs. tshark builds the tree visible for
-- -T fields, and TreeItem:referenced() then answers true for every field (Wireshark 4.0 gives a
-- Lua dissector no other way to ask), so without this every item would be built to print one
-- field. The fields are named on tshark's command line (-e, -Y, -R, -z, -o), where the system
-- shows it (/proc/self/cmdline). Every field is wanted when the command line may need any: not
-- tshark, or not -T fields; a display filter macro or field reference ("$"), or expert infos
-- ("expert"). A part of a message (a robot-state package, an RTDE variable, a real-time slot) is
-- wanted when its item or a field under it is named: "ur.joint_data" or "ur.joint_data.q_actual"
-- wants the package joint_data. What else a name wants is the dissector's to say.
local spec, rt = ...
local find, sub, match, gmatch, gsub = string.find, string.sub, string.match, string.gmatch, string.gsub

-- The arguments of this process, or nil where the system does not show them.
local function command_line()
    local file = io and io.open and io.open("/proc/self/cmdline", "rb")
    if not file then return nil end
    local text = file:read("*a")
    file:close()
    if not text or text == "" then return nil end
    local args, p = {}, 1
    while p <= #text do
        local z = find(text, "\0", p, true) or #text + 1
        args[#args + 1] = sub(text, p, z - 1)
        p = z + 1
    end
    return args
end

-- The names under `prefix` ("ur.", "rtde.") in a tshark -T fields command line, as a set; nil
-- when it may need any field.
local function named_fields(args, prefix)
    if not args or not args[1] then return nil end
    local program = match(args[1], "([^/\\]*)$")
    if not find(program, "^tshark") then return nil end
    local format
    for i = 2, #args do
        local a = args[i]
        if a == "-T" then format = args[i + 1]
        elseif sub(a, 1, 2) == "-T" then format = sub(a, 3) end
    end
    if format ~= "fields" then return nil end
    local pattern = gsub(prefix, "%p", "%%%0") .. "[%w_%.]*[%w_]"
    local names = {}
    for i = 2, #args do
        local a = args[i]
        if find(a, "$", 1, true) or find(a, "expert", 1, true) then return nil end
        for name in gmatch(a, pattern) do names[name] = true end
    end
    return names
end

-- Whether a name is the item filtered as `own` or a field under it.
local function within(name, own)
    return name == own or (sub(name, 1, #own + 1) == own .. ".")
end

-- Whether the names want the part whose item is filtered as `own`: it, or a field under it.
local function part_named(names, own)
    if names[own] then return true end
    for name in pairs(names) do
        if within(name, own) then return true end
    end
    return false
end

-- This run's names under a prefix, found once (the same set every time), or nil for every field.
local found, off = {}, false
local function wanted_names(prefix)
    if off then return nil end
    local names = found[prefix]
    if names == nil then
        names = named_fields(command_line(), prefix) or false
        found[prefix] = names
    end
    return names or nil
end

-- A preference that turns the rule off (the primary interface's ur.named_fields_only): every
-- field is wanted, as another Lua script reading fields with Field.new needs.
local function named_only(on)
    off = not on
end

-- The entries of `list` the names want, worked out once per list and names (nil names: the list
-- itself). part_of(entry) gives the filter name of an entry's item, or nil where it is always built.
local kept = setmetatable({}, { __mode = "k" })
local function wanted_entries(list, names, part_of)
    if not names then return list end
    local k = kept[list]
    if k and k.names == names then return k.list end
    local out = {}
    for _, entry in ipairs(list) do
        local own = part_of(entry)
        if not own or part_named(names, own) then out[#out + 1] = entry end
    end
    kept[list] = { names = names, list = out }
    return out
end

rt.named_fields, rt.part_named, rt.wanted_names, rt.named_only = named_fields, part_named, wanted_names, named_only
rt.within, rt.wanted_entries = within, wanted_entries
