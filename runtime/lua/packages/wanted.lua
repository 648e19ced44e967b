-- Which robot-state packages a `tshark -T fields` run needs. tshark builds the tree visible
-- for -T fields, and TreeItem:referenced() then answers true for every field (Wireshark 4.0
-- gives a Lua dissector no other way to ask), so without this every package would be built to
-- print one field. The fields are named on tshark's command line (-e, -Y, -R, -z, -o): where
-- the system shows it (/proc/self/cmdline), a package is built when a field of it is named
-- ("ur.joint_data.q_actual" names joint_data), or its item ("ur.joint_data"). Every package is
-- built when the command line may need any: not tshark, or not -T fields; a display filter
-- macro or field reference ("$"), expert infos ("expert"); a ur name that is not a field of
-- the spec (ur.raw, ur.extra, ur.malformed, ... show inside any package); package headers
-- (ur.package.*); or when the ur.named_fields_only preference is off.
local spec, rt = ...
local find, sub, match, gmatch = string.find, string.sub, string.match, string.gmatch

local PREFIX = "ur."

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

-- The ur names in a tshark -T fields command line, as a set; nil when it may need any field.
local function named_fields(args)
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
    local names = {}
    for i = 2, #args do
        local a = args[i]
        if find(a, "$", 1, true) or find(a, "expert", 1, true) then return nil end
        for name in gmatch(a, "ur%.[%w_%.]*[%w_]") do names[name] = true end
    end
    return names
end

-- Every package data table of the robot-state messages, and the spec's field names.
local function packages_and_fields()
    local parts, fields = {}, {}
    for _, m in pairs(spec.messages) do
        if m.kind == "packages" then
            for _, forms in pairs(m.packages) do
                for i = 1, #forms do parts[forms[i].of] = true end
            end
        end
    end
    for key in pairs(spec.F) do fields[PREFIX .. key] = true end
    return parts, fields
end

-- The packages the names need, as a set of package data tables; nil when they need every one.
local function packages_named(names)
    if not names then return nil end
    local parts, fields = packages_and_fields()
    local chosen = {}
    for name in pairs(names) do
        local found = false
        for pk in pairs(parts) do
            local own = PREFIX .. pk.name
            if name == own or sub(name, 1, #own + 1) == own .. "." then
                chosen[pk], found = true, true
            end
        end
        if not found and (not fields[name] or find(name, "^ur%.package%.")) then return nil end
    end
    return chosen
end

-- The packages a visible tree needs (a set), or nil for every one. Found once per run.
local found, chosen = false, nil
local function wanted_packages()
    if not found then
        found = true
        chosen = packages_named(named_fields(command_line()))
    end
    return chosen
end

-- The preference ur.named_fields_only: false builds every package whatever the command line.
local function named_only(on)
    found, chosen = not on, nil
end

rt.wanted_packages, rt.named_only = wanted_packages, named_only
rt.named_fields, rt.packages_named = named_fields, packages_named
