-- The Info column. It is written on every pass, tree or not, so it reads the raw bytes and
-- builds no tree: the descriptors marked `show` of a message layout, and the enums a
-- robot-state package lists in its `info`. One buffer of parts is reused for every message.
local spec, rt = ...
local fmt, byte = string.format, string.byte
local be_int, be_uint = rt.be_int, rt.be_uint
local PACKAGE_HEADER = spec.package_header_size
local PACKAGE_LENGTH = spec.package_length_size

local parts = {}

-- The fields marked `show` of a layout from o to e, each after its text: "PROGRAM_STARTED:
-- demo". Stops at the first field it cannot step over without walking it.
local function layout_summary(tvb, raw, o, e, layout)
    local n = 0
    for _, d in ipairs(layout) do
        local k, size = d.k, nil
        if k == "scalar" or k == "bits" then size = d.n
        elseif k == "array" then size = d.n * d.count
        elseif k == "group" and d.count and d.size then size = d.count * d.size
        end
        if size then
            if o + size > e then break end
            if d.show then
                local v = d.signed and be_int(raw, o, d.n) or be_uint(raw, o, d.n)
                n = n + 1
                parts[n] = d.show .. (d.vs and (d.vs[v] or fmt("%d", v)) or fmt("%d", v))
            end
            o = o + size
        elseif k == "pstring" then
            if o + d.n > e then break end
            local len = d.signed and be_int(raw, o, d.n) or be_uint(raw, o, d.n)
            if len < 0 or o + d.n + len > e then break end
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
        else
            break
        end
    end
    return table.concat(parts, "", 1, n)
end

-- The enums that the robot-state packages from p to e list in their `info` (per body size,
-- one form of the package each: { at = offset in the body, n = size, vs = value string }),
-- joined by ", ". Stops at the first package whose length does not fit.
local function package_summary(raw, p, e, packages)
    local n = 0
    while e - p >= PACKAGE_HEADER do
        local size, code = be_int(raw, p, PACKAGE_LENGTH), byte(raw, p + PACKAGE_LENGTH + 1)
        if size < PACKAGE_HEADER or size > e - p then break end
        local pk = packages[code]
        -- The form of the package's size, else (extra bytes of a newer release) the newest form.
        local info = pk and pk.info and (pk.info[size - PACKAGE_HEADER] or pk.info_newest)
        if info then
            for _, i in ipairs(info) do
                if i.at + i.n <= size - PACKAGE_HEADER then
                    local v = be_int(raw, p + PACKAGE_HEADER + i.at, i.n)
                    n = n + 1
                    parts[n] = i.vs[v] or fmt("%d", v)
                end
            end
        end
        p = p + size
    end
    return table.concat(parts, ", ", 1, n)
end

-- "Label" alone, or "Label: text".
local function labelled(label, text)
    if text == "" then return label end
    return label .. ": " .. text
end

-- TCP may call the dissector twice for one frame (a reassembled message, then the rest of the
-- segment): the first message of the later call appends to what the earlier one wrote.
local info_frame, info_text = -1, ""
local function set_info(pinfo, first, text)
    if first and not (info_frame == pinfo.number and tostring(pinfo.cols.info) == info_text) then
        info_text = text
        pinfo.cols.info:set(text)
    else
        info_text = info_text .. "; " .. text
        pinfo.cols.info:append("; " .. text)
    end
    info_frame = pinfo.number
end

rt.layout_summary, rt.package_summary, rt.labelled, rt.set_info = layout_summary, package_summary, labelled, set_info
