-- runtime/lua/packages/framing.lua: header faults, the resynchronising scan, and whole calls of the
-- dissector over a stub tvb: messages split, packed, and after a bad header.
local S = dofile("stubs.lua")
S.wireshark_globals()

local seen = {}
local handler = {
    m = { label = "Text" }, suffix = ", Text",
    info = function(m, tvb, raw, o, e) return "Text: " .. string.sub(raw, o + 6, e) end,
    tree = function(m, tvb, tree, o, e, st) seen[#seen + 1] = st.version end,
}
local ur = Proto("ur", "UR")
ur.prefs.max_length = { default = 100 }
local spec = { proto = ur, F = { length = "ur.length", type = "ur.type" }, header_size = 5, length_size = 4,
               known_types = { [16] = true, [20] = true, [24] = true }, message_types = { [24] = "SAFETY" },
               version_reader = { message = 99 }, default_version = "5.9" }
local rt = S.base_rt(spec)
rt.X, rt.E, rt.handlers = S.X, S.E, { [20] = handler }
S.load("common/info_column.lua", spec, rt)
S.load("packages/info.lua", spec, rt)
S.load("packages/carry.lua", spec, rt)
S.load("common/tcp_stream.lua", spec, rt)
S.load("packages/stream.lua", spec, rt)
S.load("common/wanted.lua", spec, rt)
S.load("packages/wanted.lua", spec, rt)
S.load("common/guard.lua", spec, rt)
S.load("packages/framing.lua", spec, rt)

local function header(len, mtype) return S.bytes(0, 0, 0, len, mtype) end
S.eq(rt.plausible(header(5, 20), 0, 100), true, "a plausible header")
S.eq(rt.plausible(header(4, 20), 0, 100), false, "too short")
S.eq(rt.plausible(header(101, 20), 0, 100), false, "too long")
S.eq(rt.plausible(header(9, 21), 0, 100), false, "unknown type")
local e, text = rt.header_fault(header(2, 20), 0, 100)
S.eq(e, "bad_length", "below the header: expert"); S.eq(text, "length 2 is below 5", "below the header: text")
e, text = rt.header_fault(S.bytes(0x7f, 0xff, 0xff, 0xff, 16), 0, 1048576)
S.eq(e, "bad_length", "above the maximum: expert"); S.eq(text, "length 2147483647 is above 1048576", "above the maximum")
e, text = rt.header_fault(S.bytes(0xff, 0xff, 0xff, 0xff, 16), 0, 100)
S.eq(text, "length -1 is below 5", "a negative length")
e, text = rt.header_fault(header(9, 21), 0, 100)
S.eq(e, "bad_type", "unknown type: expert"); S.eq(text, "unknown message type 21", "unknown type: text")
S.eq(rt.scan("xx" .. header(6, 20) .. "a", 0, 100), 2, "the next plausible header")
local p, stop = rt.scan("xxxx" .. header(6, 20):sub(1, 3), 0, 100)
S.eq(p, nil, "none yet"); S.eq(stop, 3, "the last bytes may start a header")

local function msg(text) return header(5 + #text, 20) .. text end
local function call(number, bytes, visited)
    local pinfo, tree = S.pinfo(number, visited), S.tree()
    S.eq(ur.dissector(S.tvb(bytes), pinfo, tree), #bytes, "the whole tvb is taken")
    return pinfo, tree
end

-- Two messages in one segment, then one split over two: TCP is asked for the rest.
local pinfo, tree = call(1, msg("a") .. msg("bc") .. msg("def"):sub(1, 4))
S.eq(tostring(pinfo.cols.info), "Text: a; Text: bc", "Info of both")
S.eq(tostring(pinfo.cols.protocol), "UR", "protocol column")
S.eq(pinfo.desegment_offset, 13, "reassembly from the split message")
S.eq(pinfo.desegment_len, DESEGMENT_ONE_MORE_SEGMENT, "a split header asks for one more segment")
S.eq(S.dump(tree):match("ur.length @0%+4") ~= nil, true, "header fields")
S.eq(seen[1], 5009000, "no Version message: the default version")
pinfo = call(2, msg("ghij"):sub(1, 7))
S.eq(pinfo.desegment_len, 2, "the bytes still missing")

-- A known type without a layout is kept raw.
pinfo, tree = call(3, header(7, 24) .. "zz")
S.eq(tostring(pinfo.cols.info), "Type 24 (SAFETY)", "Info of a type without a layout")
S.eq(S.dump(tree):match("ur.raw @5%+2") ~= nil, true, "raw")

-- A bad header: expert, skipped bytes, and the stream carried by hand until back in step.
pinfo, tree = call(4, header(2, 20) .. "junk" .. msg("ok") .. header(9, 20))
S.eq(tostring(pinfo.cols.info), "Bad header: length 2 is below 5; Text: ok", "Info")
S.eq(S.dump(tree):match("!bad_length: length 2 is below 5") ~= nil, true, "expert")
S.eq(S.dump(tree):match("ur.skipped @1%+8") ~= nil, true, "skipped bytes: from after the fault to the next plausible header")
S.eq(pinfo.desegment_len, nil, "after a fault, no reassembly is asked for")
pinfo, tree = call(5, "wxyz")
S.eq(tostring(pinfo.cols.info), "Text: wxyz", "the carried header completes the message")

-- A bad header, then a message carried over one-byte calls: the calls inside it keep their
-- byte and show nothing; the last one shows the message, on the first pass and on later ones.
local long = msg(string.rep("q", 40))
pinfo = call(100, header(2, 20) .. long:sub(1, 6))
S.eq(tostring(pinfo.cols.info), "Bad header: length 2 is below 5", "the fault, and the next header found")
for i = 7, #long - 1 do
    pinfo, tree = call(100 + i, long:sub(i, i))
    S.eq(tostring(pinfo.cols.info) .. S.dump(tree), "", "inside the carried message: nothing shown")
end
local last = long:sub(-1) .. msg("z")
pinfo, tree = call(100 + #long, last)
S.eq(tostring(pinfo.cols.info), "Text: " .. string.rep("q", 40) .. "; Text: z", "the last byte completes it")
S.eq(S.dump(tree):match("^ur @0%+45") ~= nil, true, "the message from the first carried byte")
S.eq(pinfo.desegment_len, nil, "back in step: nothing carried, nothing asked")
pinfo = call(100 + #long - 1, long:sub(-2, -2), true)
S.eq(tostring(pinfo.cols.info), "", "a later pass: still nothing inside")
pinfo, tree = call(100 + #long, last, true)
S.eq(tostring(pinfo.cols.info), "Text: " .. string.rep("q", 40) .. "; Text: z", "a later pass: the same message")

-- Client to robot: URScript text.
pinfo = S.pinfo(60)
pinfo.src_port, pinfo.dst_port = 50000, 30001
ur.dissector(S.tvb("def main():\n  popup(1)\nend\n"), pinfo, S.tree())
S.eq(tostring(pinfo.cols.info), "URScript: def main():", "URScript line")

-- A Lua error inside is shown as an expert, not thrown at Wireshark.
handler.tree = function() error("boom") end
pinfo, tree = call(61, msg("x"))
S.eq(S.dump(tree):match("!internal: urwire: .*boom") ~= nil, true, "internal error expert")

-- A robot state whose layout sizes tell the version (as KINDS.packages does, in its Info and
-- again in its tree): this message's tree starts from the version it started with, is shown
-- with what the sizes told, and later messages of the stream are read with it.
local shown = {}
handler.tree = function(m, tvb, tree, o, e, st)
    seen[#seen + 1] = st.version
    shown[#shown + 1] = st.message_implied or "-"
end
rt.handlers[16] = {
    m = { label = "State" }, suffix = ", State",
    info = function(m, tvb, raw, o, e, st)
        if not st.known then st.version, st.implied = 3004999, "3.2 to 3.4" end
        return "State"
    end,
    tree = function(m, tvb, tree, o, e, st)
        seen[#seen + 1] = st.version
        shown[#shown + 1] = st.message_implied or "-"
    end,
}
local count = #seen
local function session(number, port)
    local pinfo = S.pinfo(number)
    pinfo.dst_port = port
    ur.dissector(S.tvb(msg("a") .. header(5, 16) .. msg("b")), pinfo, S.tree())
end
session(8, 50100)
S.eq(table.concat(seen, " ", count + 1), "5009000 5009000 3004999", "the default, then the version the sizes told")
S.eq(table.concat(shown, " "), "- 3.2 to 3.4 3.2 to 3.4", "shown on the message that told it, and after")
session(9, 50100)
S.eq(seen[#seen], 3004999, "kept for the stream's next calls")

-- The version preference: a known version, which the layout sizes do not overrule.
rt.assume_version(5012000)
count = #seen
session(10, 50200)
S.eq(table.concat(seen, " ", count + 1), "5012000 5012000 5012000", "the assumed version follows the preference")
rt.assume_version(nil)
print("ok")
