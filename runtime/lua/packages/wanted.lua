-- Which robot-state packages a `tshark -T fields` run needs (runtime/lua/common/wanted.lua finds
-- the ur names its command line gives): a package is built when a field of it is named
-- ("ur.joint_data.q_actual" names joint_data), or its item ("ur.joint_data"). Every package is
-- built when the names may need any: a ur name that is not a field of the spec (ur.raw, ur.extra,
-- ur.malformed, ... show inside any package), package headers (ur.package.*), or when the
-- ur.named_fields_only preference is off.
local spec, rt = ...
local find = string.find
local within, wanted_names = rt.within, rt.wanted_names

local PREFIX = "ur."

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
            if within(name, PREFIX .. pk.name) then chosen[pk], found = true, true end
        end
        if not found and (not fields[name] or find(name, "^ur%.package%.")) then return nil end
    end
    return chosen
end

-- The packages a visible tree needs (a set), or nil for every one: worked out again only when
-- the names change (the preference).
local from, chosen = false, nil
local function wanted_packages()
    local names = wanted_names(PREFIX)
    if names ~= from then from, chosen = names, packages_named(names) end
    return chosen
end

rt.wanted_packages, rt.packages_named = wanted_packages, packages_named
