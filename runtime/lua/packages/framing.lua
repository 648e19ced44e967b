-- Framing: split the robot's bytes into messages over TCP, reassemble the split ones, and
-- resynchronise after a bad header. Client-to-robot bytes are URScript text. Everything the
-- dissector does per call starts in dissect(), behind a pcall guard.
local spec, rt = ...
local fmt, byte = string.format, string.byte
local be_int, info_begin, set_info, announced_version = rt.be_int, rt.info_begin, rt.set_info, rt.announced_version
local enum_names, rename = rt.enum_names, rt.rename
local items_begin, items_hidden, MAX_TREE_ITEMS = rt.items_begin, rt.items_hidden, rt.MAX_TREE_ITEMS
local stream_load, stream_save = rt.stream_load, rt.stream_save
local carry_new, carry_add, carry_bytes = rt.carry_new, rt.carry_add, rt.carry_bytes
local X, E, handlers = rt.X, rt.E, rt.handlers
local tree_add, append_text, range_of = rt.tree_add, rt.append_text, rt.range_of
local wanted_packages = rt.wanted_packages
local ur, F = spec.proto, spec.F
local HEADER, LENGTH = spec.header_size, spec.length_size
local KNOWN_TYPE, VERSION = spec.known_types, spec.version_reader
local MESSAGE_TYPES, MESSAGE_TYPE_TABLES = spec.message_types, spec.message_type_tables
local DEFAULT_VERSION, BUGFIX_ANY, version_text = rt.default_version, rt.BUGFIX_ANY, rt.version_text

-- The version the ur.version preference gives until a Version message is seen; nil when the
-- preference is empty: then the layout sizes tell the version where they can, else the default.
local pref_version = nil
local function assume_version(v) pref_version = v end

-- The message being dissected, reused for every message: its raw bytes and first byte; the
-- software version it is read with (version: it may move on within a robot state, when layout
-- sizes tell it), and how that version is known: announced (a Version message), from_pref, or
-- neither (known is false: then implied, when set, names the versions the layout sizes showed);
-- message_version and message_implied: the version shown on the message.
-- call: counts dissector calls (what is asked of a tree is asked once per call); only: the
-- packages a tshark -T fields run needs (runtime/lua/packages/wanted.lua), nil for all.
local st = { raw = "", base = 0, version = DEFAULT_VERSION, known = false, announced = false, from_pref = false,
             call = 0, only = nil }

-- st as a message starts, from the stream's version (nil: none yet) and how it was found.
local function begin(version, implied)
    st.version = version or pref_version or DEFAULT_VERSION
    st.implied = implied
    st.announced = version ~= nil and implied == nil
    st.from_pref = not st.announced and pref_version ~= nil
    st.known = st.announced or st.from_pref
end

local function plausible(raw, o, max_length)
    local size = be_int(raw, o, LENGTH)
    return size >= HEADER and size <= max_length and KNOWN_TYPE[byte(raw, o + LENGTH + 1)] == true
end

-- What is wrong with an implausible header at o: its expert and text.
local function header_fault(raw, o, max_length)
    local size = be_int(raw, o, LENGTH)
    if size < HEADER then return E.bad_length, fmt("length %d is below %d", size, HEADER) end
    if size > max_length then return E.bad_length, fmt("length %d is above %d", size, max_length) end
    return E.bad_type, fmt("unknown message type %d", byte(raw, o + LENGTH + 1))
end

-- How many bytes carry c must hold before a call can go on with it: its message's length once
-- its header is whole (a carry only starts at a plausible header), else a header's.
local function carry_need(c, max_length)
    if #c.head == HEADER and plausible(c.head, 0, max_length) then return be_int(c.head, 0, LENGTH) end
    return HEADER
end

-- Resynchronising: scan buf (bytes carried from earlier segments, then this tvb's) from p for
-- the next plausible header. Returns its position, or nil and the first position not tested.
local function scan(buf, p, max_length)
    local n = #buf
    while n - p >= HEADER do
        if plausible(buf, p, max_length) then return p end
        p = p + 1
    end
    return nil, p
end

-- Client to robot: URScript text, not UR messages.
local function dissect_client(tvb, pinfo, tree)
    pinfo.cols.protocol:set("UR")
    local n = tvb:len()
    local item = tree:add(ur, tvb())
    item:add_packet_field(X.urscript, tvb(), ENC_UTF_8)
    local line = tvb(0, n > 60 and 60 or n):string(ENC_UTF_8)
    pinfo.cols.info:set("URScript: " .. (string.match(line, "^[^\n]*") or ""))
    return n
end

-- The Info column of a message type the spec names but does not lay out.
local function unlaid_info(mtype, v)
    local names = MESSAGE_TYPE_TABLES and enum_names(MESSAGE_TYPE_TABLES, v) or MESSAGE_TYPES
    return fmt("Type %d (%s)", mtype, names[mtype] or "named in another version")
end

local ur_handle = nil
-- The call being dissected: the stream's version (nil: none yet) and, when the layout sizes
-- told it, the versions of the form that did; whether columns are built (else no Info text).
local cur = { version = nil, implied = nil, first = true, detail = false, columns = true }

-- One whole message from o to e (its declared length): version, Info column, tree.
local function message(tvb, raw, pinfo, tree, o, e, mtype)
    local h = handlers[mtype]
    local bad_bugfix, bugfix_at   -- a Version message's bugfix out of range, set aside
    if mtype == VERSION.message then
        local v
        v, bad_bugfix, bugfix_at = announced_version(raw, o, e, VERSION)
        if v then cur.version, cur.implied = v, nil end
    end
    local version, implied = cur.version, cur.implied
    st.raw, st.base = raw, o
    begin(version, implied)
    local text = h and h.info(h.m, tvb, raw, o, e, st, cur.columns)
    if cur.columns then set_info(pinfo, cur.first, text or unlaid_info(mtype, st.version)) end
    cur.first = false
    -- Layout sizes told the version of a stream that had not: this message and the next ones.
    if st.implied and not st.known then cur.version, cur.implied = st.version, st.implied end
    if not cur.detail then return end
    local item = tree_add(tree, ur, range_of(tvb, o, e - o))
    tree_add(item, F.length, range_of(tvb, o, LENGTH))
    local type_item = tree_add(item, F.type, range_of(tvb, o + LENGTH, HEADER - LENGTH))
    if MESSAGE_TYPE_TABLES then rename(type_item, "Type", MESSAGE_TYPE_TABLES, st.version, mtype) end
    -- The tree walks the message again from the version it started with.
    st.message_version, st.message_implied = st.version, st.implied
    begin(version, implied)
    st.visible = tree.visible
    st.only = st.visible and wanted_packages() or nil
    if h then
        append_text(item, h.suffix)
        items_begin(item)
        local fields = h.tree(h.m, tvb, item, o, e, st) or item
        if bad_bugfix then
            fields:add_tvb_expert_info(E.version_range, range_of(tvb, bugfix_at, VERSION.bugfix.n),
                fmt("bugfix version %d is out of range (0 to %d); the stream is read as %s", bad_bugfix, BUGFIX_ANY,
                    version_text(cur.version)))
        end
        local hidden = items_hidden()
        if hidden > 0 then
            item:add_proto_expert_info(E.items_hidden,
                fmt("%d more items not shown (a message shows at most %d)", hidden, MAX_TREE_ITEMS))
        end
    elseif e - o > HEADER then
        -- A known type without a layout (e.g. 24): kept raw, not an error.
        item:add(X.raw, tvb(o + HEADER, e - o - HEADER))
    end
end

-- Bytes skipped while resynchronising, or carried over to the next segment.
local function data_item(tree, data, o, len)
    tree:add(ur, data(o, len)):add(X.skipped, data(o, len))
end

local function dissect(tvb, pinfo, tree)
    if pinfo.src_port ~= pinfo.match_uint then return dissect_client(tvb, pinfo, tree) end
    local raw = tvb:raw()
    local n = #raw
    local max_length = ur.prefs.max_length
    ur_handle = ur_handle or Dissector.get("ur")
    -- Field work only when someone looks: a visible tree, or a filter or column naming ur.
    cur.detail = tree.visible or tree:referenced(ur_handle)
    cur.first = true
    cur.columns = info_begin(pinfo)
    st.call = st.call + 1

    -- The stream's state as this call starts.
    local resync, carry, carried, stream
    cur.version, cur.implied, resync, carry, carried, stream = stream_load(pinfo, n)

    if cur.columns then pinfo.cols.protocol:set("UR") end
    -- Once this call has met a fault, the rest of the stream is carried over by hand (in the
    -- stream state) until it is back in step, instead of by TCP reassembly: asking TCP for more
    -- bytes after a fault makes later passes hand over other bytes, and the fault would not
    -- show there. Carried bytes come first, in a tvb of their own, made once the message they
    -- start is whole.
    local by_hand = carry ~= nil or resync
    local data, buf = tvb, raw
    if carry then
        if not resync and carried + n < carry_need(carry, max_length) then
            -- Still inside the carried message: keep these bytes too, and show nothing yet.
            if not pinfo.visited then carry_add(carry, raw) end
            stream_save(pinfo, stream, cur.version, cur.implied, resync, carry)
            return n
        end
        buf = carry_bytes(carry, carried) .. raw
        data = ByteArray.new(buf, true):tvb("UR bytes carried over")
    end
    n = #buf
    carry = nil
    local o = 0
    if resync then
        -- Go on scanning for the next plausible header.
        local p, stop = scan(buf, 0, max_length)
        if p then
            if p > 0 and cur.detail then data_item(tree, data, 0, p) end
            o, resync = p, false
        else
            -- Nothing yet: keep the last bytes, which may start a header.
            if stop > 0 and cur.detail then data_item(tree, data, 0, stop) end
            set_info(pinfo, true, "Resynchronising: no message header yet")
            cur.first = false
            o, carry = n, carry_new(string.sub(buf, stop + 1))
        end
    end
    while o < n do
        local left = n - o
        local size, mtype = 0, 0
        if left >= HEADER then size, mtype = be_int(buf, o, LENGTH), byte(buf, o + LENGTH + 1) end
        if left >= HEADER and (size < HEADER or size > max_length or not KNOWN_TYPE[mtype]) then
            local ex, text = header_fault(buf, o, max_length)
            local item = tree:add(ur, data(o, HEADER))
            item:add(F.length, data(o, LENGTH))
            item:add(F.type, data(o + LENGTH, HEADER - LENGTH))
            item:add_proto_expert_info(ex, text)
            set_info(pinfo, cur.first, "Bad header: " .. text)
            cur.first = false
            by_hand = true
            -- Scan forward from the next byte; the skipped bytes belong to this fault.
            local p, stop = scan(buf, o + 1, max_length)
            if p then
                if p > o + 1 and cur.detail then data_item(tree, data, o + 1, p - o - 1) end
                o = p
            else
                if stop > o + 1 and cur.detail then data_item(tree, data, o + 1, stop - o - 1) end
                resync, carry = true, carry_new(string.sub(buf, stop + 1))
                o = n
            end
        elseif (left < HEADER or size > left) and by_hand then
            -- Carried as it is until the message is whole.
            carry = carry_new(string.sub(buf, o + 1))
            o = n
        elseif left < HEADER then
            -- A header split inside its first bytes: ask for one more segment.
            if pinfo.can_desegment > 0 then
                pinfo.desegment_offset = o
                pinfo.desegment_len = DESEGMENT_ONE_MORE_SEGMENT
            end
            break
        elseif size > left then
            if pinfo.can_desegment > 0 then
                pinfo.desegment_offset = o
                pinfo.desegment_len = size - left
                break
            end
            -- No reassembly possible (preference off): show what is there.
            tree:add(ur, data(o, left)):add(X.raw, data(o, left))
            set_info(pinfo, cur.first, "Continuation")
            break
        else
            message(data, buf, pinfo, tree, o, o + size, mtype)
            o = o + size
        end
    end
    stream_save(pinfo, stream, cur.version, cur.implied, resync, carry)
    return tvb:len()
end

ur.dissector = rt.guard(ur, dissect, E.internal, "urwire")

rt.plausible, rt.header_fault, rt.scan, rt.assume_version = plausible, header_fault, scan, assume_version
