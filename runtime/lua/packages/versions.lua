-- Software versions as one number, (major * 1000 + minor) * 1000 + bugfix (5.9 is 5009000,
-- 5.25.1 is 5025001; an upper bound written 5.8 is 5008999, any 5.8.x): parsed from the
-- preference's text, shown back as text, tested against a range. What follows the version: the
-- value-type table and the names of an enum whose codes depend on it, and the form (layout) of
-- a package or subtype, chosen by the version or else by the length. And the version a Version
-- message announces, read from its raw bytes.
local spec, rt = ...
local fmt, byte, floor = string.format, string.byte, math.floor
local be_int, be_uint = rt.be_int, rt.be_uint

local BUGFIX_ANY = 999   -- a bugfix number that stands for every bugfix release of its minor

local function version_number(major, minor, bugfix)
    if bugfix > BUGFIX_ANY then bugfix = BUGFIX_ANY end
    if bugfix < 0 then bugfix = 0 end
    return (major * 1000 + minor) * 1000 + bugfix
end

-- "5.9" -> 5009000, "5.25.1" -> 5025001 (leading spaces allowed); nil when it is no version.
local function parse_version(text)
    local major, minor, rest = string.match(text or "", "^%s*(%d+)%.(%d+)(.*)$")
    if not major then return nil end
    local bugfix = string.match(rest, "^%.(%d+)") or "0"
    return version_number(tonumber(major), tonumber(minor), tonumber(bugfix))
end

-- 5009000 -> "5.9", 5025001 -> "5.25.1", 5008999 (any 5.8.x) -> "5.8".
local function version_text(v)
    local bugfix = v % 1000
    local minor = floor(v / 1000) % 1000
    local major = floor(v / 1000000)
    if bugfix == 0 or bugfix == BUGFIX_ANY then return fmt("%d.%d", major, minor) end
    return fmt("%d.%d.%d", major, minor, bugfix)
end

-- True when v is inside the inclusive range; a nil bound is open.
local function version_in(v, low, high)
    return (low == nil or v >= low) and (high == nil or v <= high)
end

-- The entry of a list of { low, high, ... } tables that holds version v, else the last.
local function in_force(tables, v)
    for i = 1, #tables do
        local t = tables[i]
        if version_in(v, t.low, t.high) then return t end
    end
    return tables[#tables]
end

-- The value types of version v: { kinds = { [code] = ... }, min_size = the fewest bytes a value takes }.
local function value_table(tables, v)
    return in_force(tables, v)
end

-- The names of an enum whose codes depend on the version ({ newest = <value string>,
-- { low, high, names }, ... }) for version v. The last answer per enum is kept: a stream keeps
-- its version.
local names_memo = {}
local function enum_names(tables, v)
    local m = names_memo[tables]
    if m and m.v == v then return m.names end
    local names = tables.newest
    for i = 1, #tables do
        local t = tables[i]
        if version_in(v, t.low, t.high) then names = t.names; break end
    end
    if not m then m = {}; names_memo[tables] = m end
    m.v, m.names = v, names
    return names
end

-- True when some version's table names the code.
local function named_in_any(tables, code)
    for i = 1, #tables do
        if tables[i].names[code] ~= nil then return true end
    end
    return false
end

-- Where every segment of the version axis but the first starts (spec.segment_starts, as text):
-- within a segment every type code sends one form, so a version's form is a lookup.
local segment_starts = {}
for i, text in ipairs(spec.segment_starts or {}) do segment_starts[i] = parse_version(text) end

-- The segment that holds version v: 1 below the first start, else 1 + the starts at or below v.
-- The last answer is kept: a stream keeps its version.
local last_v, last_segment
local function segment_of(v)
    if v == last_v then return last_segment end
    local lo, hi = 1, #segment_starts + 1
    while lo < hi do
        local mid = floor((lo + hi) / 2)
        if segment_starts[mid] <= v then lo = mid + 1 else hi = mid end
    end
    last_v, last_segment = v, lo
    return lo
end

-- The forms of a package type or subtype: a list of { of = <its layout's data>, sizes = {
-- [body size] = true } or nil when open-ended (then at least min), rep = the version a stream
-- is taken to run when this form is recognised by its length alone (text), versions = the
-- versions that send it }; `single` when one form serves every version; `segments`, the form of
-- each segment (negative: none is sent there, the form is the nearest version's below);
-- `by_length`, the body sizes that recognise one form.
local function fits(form, size)
    if form.sizes then return form.sizes[size] == true end
    return size >= form.min
end

-- The form of a body of `size` bytes for version v, the version to read it with, and whether
-- the length chose it: the version's form when it fits; else the one form whose exact size it
-- is; else the version's form, whose short or extra bytes are then reported.
local function choose_form(forms, size, v)
    local k = forms.segments[segment_of(v)]
    local mine = forms[k < 0 and -k or k]
    if k < 0 then v = parse_version(mine.rep) end   -- read as the version it stands for
    if fits(mine, size) then return mine, v, false end
    local n = forms.by_length[size]
    if n then return forms[n], parse_version(forms[n].rep), true end
    return mine, v, false
end

-- choose_form(), with the last answer per package type or subtype kept: a stream keeps its
-- version and a type its size.
local choice_memo = {}
local function choose(forms, size, v)
    if forms.single then return forms[1], v, false end
    local m = choice_memo[forms]
    if m and m.size == size and m.v == v then return m.form, m.use, m.by_length end
    local form, use, by_length = choose_form(forms, size, v)
    if not m then m = {}; choice_memo[forms] = m end
    m.size, m.v, m.form, m.use, m.by_length = size, v, form, use, by_length
    return form, use, by_length
end

-- choose() for the message being dissected (st): when the stream's version is not known (no
-- Version message, no preference), a form chosen by length sets it for the rest of the message
-- (st.version), and says so (st.implied: the form's versions).
local function pick(forms, size, st)
    local form, use, by_length = choose(forms, size, st.version)
    if by_length and not st.known then st.version, st.implied = use, form.versions end
    return form, use, by_length
end

-- The version a Version message from o to e announces, or nil when it is not one or is
-- malformed. r (spec.version_reader) says where its numbers are: the subtype byte, then steps
-- over fixed bytes and length-prefixed texts, then the major and minor bytes, then (in the
-- versions r.bugfix names) the bugfix number. A bugfix below 0 or above BUGFIX_ANY cannot
-- compare with the spec's bounds: the version is then major.minor.0, and the bugfix number and
-- its offset come after it, for the message to flag.
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
    local major, minor = byte(raw, p + 1), byte(raw, p + 2)
    local v = version_number(major, minor, 0)
    local b = r.bugfix
    if b and version_in(v, b.low, b.high) and p + 2 + b.n <= e then
        local bugfix
        if b.signed then bugfix = be_int(raw, p + 2, b.n) else bugfix = be_uint(raw, p + 2, b.n) end
        if bugfix < 0 or bugfix > BUGFIX_ANY then return v, bugfix, p + 2 end
        v = version_number(major, minor, bugfix)
    end
    return v
end

rt.version_number, rt.parse_version, rt.version_text, rt.version_in =
    version_number, parse_version, version_text, version_in
rt.value_table, rt.enum_names, rt.named_in_any = value_table, enum_names, named_in_any
rt.choose, rt.pick, rt.announced_version, rt.segment_of = choose, pick, announced_version, segment_of
rt.BUGFIX_ANY = BUGFIX_ANY
-- The version assumed when neither a Version message, the preference nor the layout sizes give one.
rt.default_version = parse_version(spec.default_version)
