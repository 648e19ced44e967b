-- A version as a preference holds it: "5.9", "3.15.2" or "2.10.0", blanks around it allowed, a
-- missing third number 0 (runtime/epan/dotted_version.c reads it alike). Each kind makes its
-- own version number of the three parts: how far a part may run is the kind's rule.
local spec, rt = ...

-- " 3.15.2 " -> 3, 15, 2; "5.9" -> 5, 9, 0; nil for anything else ("5", "5.9 beta", "latest").
local function dotted_version(text)
    local major, minor, bugfix = string.match(text or "", "^%s*(%d+)%.(%d+)%.?(%d*)%s*$")
    if not major then return nil end
    return tonumber(major), tonumber(minor), tonumber(bugfix) or 0
end

rt.dotted_version = dotted_version
