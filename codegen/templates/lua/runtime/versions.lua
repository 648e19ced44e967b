-- Software versions as one number, major * 1000 + minor (5.9 is 5009): parsed from the
-- preference's text, shown back as text, tested against a range; the value-type table that
-- a version uses; and the version a Version message announces, read from its raw bytes.
local spec, rt = ...
local fmt, byte = string.format, string.byte
local be_int, be_uint = rt.be_int, rt.be_uint

-- "5.9" (leading spaces and a third part allowed) -> 5009; nil when it is no version.
local function parse_version(text)
    local major, minor = string.match(text or "", "^%s*(%d+)%.(%d+)")
    if not major then return nil end
    return tonumber(major) * 1000 + tonumber(minor)
end

local function version_text(v)
    return fmt("%d.%d", math.floor(v / 1000), v % 1000)
end

-- True when v is inside the inclusive range; a nil bound is open.
local function version_in(v, low, high)
    return (low == nil or v >= low) and (high == nil or v <= high)
end

-- The value-type codes of version v: the first table whose range holds it, else the last.
local function value_table(tables, v)
    for _, t in ipairs(tables) do
        if version_in(v, t.low, t.high) then return t.kinds end
    end
    return tables[#tables].kinds
end

-- The version a Version message from o to e announces, or nil when it is not one or is
-- malformed. r (spec.version_reader) says where its numbers are: the subtype byte, then
-- steps over fixed bytes and length-prefixed texts, then the major and minor bytes.
local function announced_version(raw, o, e, r)
    if e - o <= r.subtype_offset or byte(raw, o + r.subtype_offset + 1) ~= r.subtype then return nil end
    local p = o
    local steps = r.steps
    for i = 1, #steps do
        local s = steps[i]
        p = p + s.fixed
        if p + s.prefix > e then return nil end
        local n
        if s.signed then n = be_int(raw, p, s.prefix) else n = be_uint(raw, p, s.prefix) end
        if n < 0 then return nil end
        p = p + s.prefix + n
    end
    p = p + r.tail
    if p + 2 + r.rest > e then return nil end
    return byte(raw, p + 1) * 1000 + byte(raw, p + 2)
end

rt.parse_version, rt.version_text, rt.version_in = parse_version, version_text, version_in
rt.value_table, rt.announced_version = value_table, announced_version
-- The version assumed when neither a Version message nor the preference gives one.
rt.default_version = parse_version(spec.default_version)
