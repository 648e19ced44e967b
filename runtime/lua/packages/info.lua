-- The Info column. It is written on every pass, tree or not, so it reads the raw bytes and
-- builds no tree: the descriptors marked `show` of a layout (a message's, or a robot-state
-- package's whose layout has a summary). One buffer of parts is reused for every message.
local spec, rt = ...
local fmt, byte = string.format, string.byte
local be_int, be_uint = rt.be_int, rt.be_uint
local version_in, enum_names, pick = rt.version_in, rt.enum_names, rt.pick
local PACKAGE_HEADER = spec.package_header_size
local PACKAGE_LENGTH = spec.package_length_size

local parts = {}

-- How many descriptors of a layout the summary walks: up to its last shown one (a `cond`
-- holding one counts). Found once per layout and kept.
local reach = {}
local function shown_in(layout)
    for i = 1, #layout do
        local d = layout[i]
        if d.show or (d.k == "cond" and shown_in(d.fields)) then return true end
    end
    return false
end
local function reach_of(layout)
    local n = reach[layout]
    if not n then
        n = 0
        for i = 1, #layout do
            local d = layout[i]
            if d.show or (d.k == "cond" and shown_in(d.fields)) then n = i end
        end
        reach[layout] = n
    end
    return n
end

-- The fields marked `show` of descriptors 1..last from o to e, for software version v, each
-- after its text, into parts from n + 1 ("PROGRAM_STARTED: demo"). Returns the offset after
-- them and the new n; the offset is nil where it stopped at a field it cannot step over
-- without walking it, or one that does not fit.
local function summarise(tvb, raw, o, e, layout, last, v, n)
    for i = 1, last do
        local d = layout[i]
        local k, size = d.k, nil
        if k == "scalar" or k == "bits" then size = d.n
        elseif k == "array" then size = d.n * d.count
        elseif k == "group" and d.count and d.size then size = d.count * d.size
        end
        if size then
            if o + size > e then return nil, n end
            if d.show then
                local x = d.signed and be_int(raw, o, d.n) or be_uint(raw, o, d.n)
                local names = d.tables and enum_names(d.tables, v) or d.vs
                n = n + 1
                parts[n] = d.show .. (names and (names[x] or fmt("%d", x)) or fmt("%d", x))
            end
            o = o + size
        elseif k == "pstring" then
            if o + d.n > e then return nil, n end
            local len = d.signed and be_int(raw, o, d.n) or be_uint(raw, o, d.n)
            if len < 0 or o + d.n + len > e then return nil, n end
            if d.show then
                n = n + 1
                parts[n] = d.show .. tvb(o + d.n, len):string(ENC_UTF_8)
            end
            o = o + d.n + len
        elseif k == "string" then
            if d.show and e > o then
                local len = e - o
                if len > 120 then len = 120 end
                n = n + 1
                parts[n] = d.show .. tvb(o, len):string(ENC_UTF_8)
            end
            o = e
        elseif k == "cond" and not d.present_if then
            if version_in(v, d.low, d.high) then
                o, n = summarise(tvb, raw, o, e, d.fields, #d.fields, v, n)
                if not o then return nil, n end
            end
        else
            return nil, n
        end
    end
    return o, n
end

-- The summary of a layout from o to e for version v: its shown fields, each after its text.
local function layout_summary(tvb, raw, o, e, layout, v)
    local _, n = summarise(tvb, raw, o, e, layout, reach_of(layout), v, 0)
    return table.concat(parts, "", 1, n)
end

-- The summaries of the robot-state packages from p to e, joined by ", ". packages: the forms
-- of each package type (see versions.lua), `summary` when one of them has a summary. Each
-- package's form is chosen as the tree chooses it (pick), so that layout sizes set the
-- version of a stream that has not told it, tree or not; with `text` false, only that is done
-- (no column to write). Stops at the first package whose length does not fit: such a robot
-- state is malformed, and what its sizes showed is not taken for the stream (st keeps the
-- version it started with).
local function package_summary(tvb, raw, p, e, packages, st, text)
    if not (text or not st.known) then return nil end
    local n = 0
    local version, implied = st.version, st.implied
    while e - p >= PACKAGE_HEADER do
        local size, code = be_int(raw, p, PACKAGE_LENGTH), byte(raw, p + PACKAGE_LENGTH + 1)
        if size < PACKAGE_HEADER or size > e - p then break end
        local forms = packages[code]
        if forms and ((text and forms.summary) or not st.known) then
            local form, use = pick(forms, size - PACKAGE_HEADER, st)
            local part = form.of
            if text and part.summary then
                local first = n + 1
                local _
                _, n = summarise(tvb, raw, p + PACKAGE_HEADER, p + size, part.layout, reach_of(part.layout), use, n)
                if n > first then
                    parts[first] = table.concat(parts, "", first, n)
                    n = first
                end
            end
        end
        p = p + size
    end
    if p < e then st.version, st.implied = version, implied end
    if not text then return nil end
    return table.concat(parts, ", ", 1, n)
end

-- "Label" alone, or "Label: text".
local function labelled(label, text)
    if text == "" then return label end
    return label .. ": " .. text
end

-- The Info column of the call being dissected, and whether Wireshark builds columns at all: a
-- Column without them prints as "(info)" (tshark -V, -T fields, taps that read no column).
-- Without columns, no Info text is made.
local info_col, columns = nil, true
local function info_begin(pinfo)
    info_col = pinfo.cols.info
    columns = tostring(info_col) ~= "(info)"
    return columns
end

-- A call's messages, "; " between them; the first message of a call appends to what an
-- earlier call for the same frame wrote (runtime/lua/common/info_column.lua).
local write_info = rt.info_writer("; ")
local function set_info(pinfo, first, text)
    if columns then write_info(pinfo, info_col, text, not first) end
end

rt.layout_summary, rt.package_summary, rt.labelled = layout_summary, package_summary, labelled
rt.info_begin, rt.set_info = info_begin, set_info
