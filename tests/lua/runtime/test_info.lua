-- runtime/lua/packages/info.lua: the Info column from raw bytes, and its text across two calls for
-- a frame.
local S = dofile("stubs.lua")
-- Two series of forms: up to 1.8, and from 3.0 (1.9 to 3.0 is no one's).
local rt = S.base_rt({ package_header_size = 5, package_length_size = 4, segment_starts = { "1.9", "3.0" } })
S.load("common/info_column.lua", {}, rt)
S.load("packages/info.lua", { package_header_size = 5, package_length_size = 4 }, rt)

local MODE = { [-1] = "NO_CONTROLLER", [7] = "RUNNING" }
local L = {
    { k = "scalar", f = "ur.k.code", n = 4, path = "code", signed = true },
    { k = "scalar", f = "ur.k.level", n = 1, path = "level", signed = true, vs = MODE, show = "" },
    { k = "array", f = "ur.k.a", n = 2, count = 2, path = "a" },
    { k = "pstring", f = "ur.k.title", n = 1, signed = false, path = "title", show = " " },
    { k = "string", f = "ur.k.text", path = "text", show = ": " },
}
local V = 5009000
local function summary(raw, o, e, layout, v) return rt.layout_summary(S.tvb(raw), raw, o, e, layout, v or V) end
local raw = S.bytes(0, 0, 0, 1, 7, 0, 0, 0, 0, 5) .. "Hello" .. "world"
S.eq(summary(raw, 0, #raw, L), "RUNNING Hello: world", "shown fields")
raw = S.bytes(0, 0, 0, 1, 0xff, 0, 0, 0, 0, 0)
S.eq(summary(raw, 0, #raw, L), "NO_CONTROLLER ", "signed enum, empty title, no text")
raw = S.bytes(0, 0, 0, 1, 9, 0, 0, 0, 0, 9) .. "cut"
S.eq(summary(raw, 0, #raw, L), "9", "a number without a name; stops at a title that does not fit")
S.eq(summary(raw, 0, 3, L), "", "nothing fits")
S.eq(summary(raw, 0, #raw, { { k = "values" }, L[2] }), "", "stops at a kind it cannot step over")
S.eq(summary(raw, 0, #raw, { L[2], { k = "values" } }), "0", "walks no further than its last shown field")
local long = string.rep("x", 200)
S.eq(#summary(long, 0, #long, { L[5] }), 2 + 120, "a text is cut at 120 bytes")

-- Fields gated by version are stepped over or into; names follow the version.
local EARLY = { [7] = "EARLY_RUNNING" }
local GATED = {
    { k = "cond", high = 3001999, fields = { { k = "scalar", f = "ur.k.old", n = 2, path = "old", signed = true } } },
    { k = "cond", low = 3002000, fields = { { k = "scalar", f = "ur.k.new", n = 4, path = "new", signed = true } } },
    { k = "scalar", f = "ur.k.level", n = 1, path = "level", signed = true, vs = MODE, show = "",
      tables = { newest = MODE, { high = 1008999, names = EARLY }, { low = 3000000, names = MODE } }, label = "level" },
}
raw = S.bytes(0, 0, 7)
S.eq(summary(raw, 0, #raw, GATED, 1008000), "EARLY_RUNNING", "1.8: the two-byte form, the early names")
raw = S.bytes(0, 0, 0, 0, 7)
S.eq(summary(raw, 0, #raw, GATED, 5009000), "RUNNING", "5.9: the four-byte form")
S.eq(summary(raw, 0, #raw, { { k = "cond", present_if = "flag", fields = {} }, L[2] }), "", "a flag's fields: stops")

-- Robot-state packages: each package's summary, by its form.
local function part(layout, summary_) return { layout = layout, summary = summary_ } end
local function forms(...) return { single = true, summary = true, { of = part(...), min = 0, rep = V, versions = "all versions" } } end
local PACKAGES = {
    [0] = forms({ { k = "scalar", f = "ur.m.pad", n = 1, path = "pad", signed = false },
                  { k = "scalar", f = "ur.m.mode", n = 1, path = "mode", signed = true, vs = MODE, show = "" } }, true),
    [3] = forms({ { k = "scalar", f = "ur.s.safety", n = 1, path = "safety", signed = false, vs = { [5] = "NORMAL" }, show = "" } }, true),
    [1] = { single = true, summary = false, { of = part({}, false), min = 0, rep = V, versions = "all versions" } },
}
local function package(code, body) return S.bytes(0, 0, 0, 5 + #body, code) .. body end
local function packages(raw, st, text)
    return rt.package_summary(S.tvb(raw), raw, 0, #raw, PACKAGES, st or S.st(raw), text ~= false)
end
raw = package(1, "abc") .. package(0, S.bytes(9, 7)) .. package(3, S.bytes(5)) .. package(0, S.bytes(1))
S.eq(packages(raw), "RUNNING, NORMAL", "summaries in package order; one too short is skipped")
raw = package(0, S.bytes(9, 0xff)) .. S.bytes(0, 0, 0, 99, 3, 5)
S.eq(packages(raw), "NO_CONTROLLER", "stops at a length that does not fit")
raw = package(7, "x") .. package(3, S.bytes(5))
S.eq(packages(raw), "NORMAL", "a package type without forms is passed over")

-- A version not known: each package's form is chosen as the tree does, and a form chosen by
-- its length tells the version, for the summaries that follow too.
local OLD_MODE = { [2] = "OLD_RUNNING" }
local EARLY_STATE = { of = part({ { k = "scalar", f = "ur.e.mode", n = 1, path = "mode", signed = true, vs = MODE, show = "",
                                    tables = { newest = MODE, { high = 1008999, names = OLD_MODE }, { low = 3000000, names = MODE } },
                                    label = "mode" } }, true),
                      sizes = { [1] = true }, min = 1, rep = "1.8", versions = "up to 1.8" }
local NEW_STATE = { of = part({ { k = "scalar", f = "ur.n.pad", n = 1, path = "pad", signed = false } }, false),
                    sizes = { [2] = true }, min = 2, rep = "5.9", versions = "3.0 and later" }
PACKAGES[5] = { single = false, summary = true, segments = { 1, -1, 2 }, by_length = { [1] = 1, [2] = 2 }, EARLY_STATE,
                NEW_STATE }
PACKAGES[6] = forms({ { k = "scalar", f = "ur.x.mode", n = 1, path = "mode", signed = true, vs = MODE, show = "",
                        tables = { newest = MODE, { high = 1008999, names = OLD_MODE }, { low = 3000000, names = MODE } },
                        label = "mode" } }, true)
raw = package(6, S.bytes(2)) .. package(5, S.bytes(2)) .. package(6, S.bytes(2))
local st = S.st(raw)
st.known = false
S.eq(packages(raw, st), "2, OLD_RUNNING, OLD_RUNNING", "names follow the version the layout sizes show, from there on")
S.eq(st.version, 1008000, "the version they show"); S.eq(st.implied, "up to 1.8", "and which form showed it")
st = S.st(raw)
S.eq(packages(raw, st), "2, OLD_RUNNING, 2", "a known version: only the form chosen by length reads with its version")
S.eq(st.implied, nil, "a known version is not overruled")
-- Without a column to write, the layout sizes still tell the version.
st = S.st(raw)
st.known = false
S.eq(packages(raw, st, false), nil, "no text")
S.eq(st.version, 1008000, "the version the sizes show, without text"); S.eq(st.implied, "up to 1.8", "and its form")
S.eq(rt.labelled("Robot state", ""), "Robot state", "label alone")
S.eq(rt.labelled("Key", "PROGRAM_STARTED"), "Key: PROGRAM_STARTED", "label and text")

-- Two calls for one frame join; a new frame starts over; a reassembled frame called again
-- after its column was reset starts over too.
local pinfo = S.pinfo(7)
S.eq(rt.info_begin(pinfo), true, "columns are built")
rt.set_info(pinfo, true, "Text: first")
rt.set_info(pinfo, false, "Text: second")
S.eq(tostring(pinfo.cols.info), "Text: first; Text: second", "one call, two messages")
rt.set_info(pinfo, true, "Text: third")
S.eq(tostring(pinfo.cols.info), "Text: first; Text: second; Text: third", "second call of the frame appends")
local other = S.pinfo(8)
rt.info_begin(other)
rt.set_info(other, true, "Robot state")
S.eq(tostring(other.cols.info), "Robot state", "next frame")
local again = S.pinfo(8)
rt.info_begin(again)
rt.set_info(again, true, "Robot state")
S.eq(tostring(again.cols.info), "Robot state", "the frame dissected again with a fresh column")

-- Without columns (a Column then prints as "(info)"), nothing is written.
local bare = S.pinfo(9)
bare.cols.info.text = "(info)"
S.eq(rt.info_begin(bare), false, "no columns")
rt.set_info(bare, true, "Robot state")
S.eq(tostring(bare.cols.info), "(info)", "no text written")
print("ok")
