-- runtime/info.lua: the Info column from raw bytes, and its text across two calls for a frame.
local S = dofile("stubs.lua")
local rt = S.base_rt({ package_header_size = 5, package_length_size = 4 })
S.load("info.lua", { package_header_size = 5, package_length_size = 4 }, rt)

local MODE = { [-1] = "NO_CONTROLLER", [7] = "RUNNING" }
local L = {
    { k = "scalar", f = "ur.k.code", n = 4, path = "code", signed = true },
    { k = "scalar", f = "ur.k.level", n = 1, path = "level", signed = true, vs = MODE, show = "" },
    { k = "array", f = "ur.k.a", n = 2, count = 2, path = "a" },
    { k = "pstring", f = "ur.k.title", n = 1, signed = false, path = "title", show = " " },
    { k = "string", f = "ur.k.text", path = "text", show = ": " },
}
local raw = S.bytes(0, 0, 0, 1, 7, 0, 0, 0, 0, 5) .. "Hello" .. "world"
S.eq(rt.layout_summary(S.tvb(raw), raw, 0, #raw, L), "RUNNING Hello: world", "shown fields")
raw = S.bytes(0, 0, 0, 1, 0xff, 0, 0, 0, 0, 0)
S.eq(rt.layout_summary(S.tvb(raw), raw, 0, #raw, L), "NO_CONTROLLER ", "signed enum, empty title, no text")
raw = S.bytes(0, 0, 0, 1, 9, 0, 0, 0, 0, 9) .. "cut"
S.eq(rt.layout_summary(S.tvb(raw), raw, 0, #raw, L), "9", "a number without a name; stops at a title that does not fit")
S.eq(rt.layout_summary(S.tvb(raw), raw, 0, 3, L), "", "nothing fits")
S.eq(rt.layout_summary(S.tvb(raw), raw, 0, #raw, { { k = "values" }, L[2] }), "", "stops at a kind it cannot step over")
local long = string.rep("x", 200)
S.eq(#rt.layout_summary(S.tvb(long), long, 0, #long, { L[5] }), 2 + 120, "a text is cut at 120 bytes")

-- Robot-state packages: the enums each package lists in its info.
local PACKAGES = {
    [0] = { info = { { at = 1, n = 1, vs = MODE } } },
    [3] = { info = { { at = 0, n = 1, vs = { [5] = "NORMAL" } } } },
    [1] = {},
}
local function package(code, body) return S.bytes(0, 0, 0, 5 + #body, code) .. body end
raw = package(1, "abc") .. package(0, S.bytes(9, 7)) .. package(3, S.bytes(5)) .. package(0, S.bytes(1))
S.eq(rt.package_summary(raw, 0, #raw, PACKAGES), "RUNNING, NORMAL", "enums in package order; one too short is skipped")
raw = package(0, S.bytes(9, 0xff)) .. S.bytes(0, 0, 0, 99, 3, 5)
S.eq(rt.package_summary(raw, 0, #raw, PACKAGES), "NO_CONTROLLER", "stops at a length that does not fit")
S.eq(rt.labelled("Robot state", ""), "Robot state", "label alone")
S.eq(rt.labelled("Key", "PROGRAM_STARTED"), "Key: PROGRAM_STARTED", "label and text")

-- Two calls for one frame join; a new frame starts over; a reassembled frame called again
-- after its column was reset starts over too.
local pinfo = S.pinfo(7)
rt.set_info(pinfo, true, "Text: first")
rt.set_info(pinfo, false, "Text: second")
S.eq(tostring(pinfo.cols.info), "Text: first; Text: second", "one call, two messages")
rt.set_info(pinfo, true, "Text: third")
S.eq(tostring(pinfo.cols.info), "Text: first; Text: second; Text: third", "second call of the frame appends")
local other = S.pinfo(8)
rt.set_info(other, true, "Robot state")
S.eq(tostring(other.cols.info), "Robot state", "next frame")
local again = S.pinfo(8)
rt.set_info(again, true, "Robot state")
S.eq(tostring(again.cols.info), "Robot state", "the frame dissected again with a fresh column")
print("ok")
