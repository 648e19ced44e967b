-- runtime/lua/int32_records/dissect.lua: records cut by the release's layout, scaled values beside
-- their raw int32, a record cut by the segment waiting for the rest, the release preference read.
local S = dofile("stubs.lua")
S.wireshark_globals()

local spec = {
    name = "ur_trajectory", title = "Trajectory", short = "UR_TRAJECTORY", ports = {50003},
    default_release = 2014000, default_text = "2.14",
    enums = {result_code = {[0] = "SUCCESS"}},
    fields = {{name = "positions", label = "Positions", scaled = true},
              {name = "duration", label = "Duration", scaled = true, unit = "s"},
              {name = "result", label = "Result", enum = "result_code"}},
    to_robot = {label = "Trajectory point", starts = {2010000}, layouts = {
        {size = 12, slots = {{field = "positions", index = 0, count = 2, scale = 1000000, scale_name = "MULT_JOINTSTATE"},
                             {field = "duration", index = 2, count = 1, scale = 1000, scale_name = "MULT_TIME"}}},
        {size = 12, slots = {{field = "positions", index = 0, count = 2, scale = 1000000, scale_name = "MULT_JOINTSTATE"},
                             {field = "duration", index = 2, count = 1, scale = 1000000, scale_name = "MULT_TIME"}}}}},
    from_robot = {label = "Trajectory result", starts = {}, layouts = {
        {size = 4, slots = {{field = "result", index = 0, count = 1}}}}},
}
spec.fields_by_name = {}
for _, f in ipairs(spec.fields) do spec.fields_by_name[f.name] = f end

local made
local make_proto = Proto
Proto = function(...) made = make_proto(...); return made end
local rt = S.load("common/register.lua", spec)
S.load("common/guard.lua", spec, rt)
S.load("common/dotted_version.lua", spec, rt)
S.load("int32_records/dissect.lua", spec, rt)
S.eq(rt.parse_release("2.9"), 2009000, "a release preference")
S.eq(rt.parse_release("latest"), nil, "not a release")
S.eq(rt.parse_release(" 2.10.1234 "), 2011234, "a patch past 999 carries into the minor (no clamp)")
S.eq(rt.layout_of(spec.to_robot, 2009000).slots[2].scale, 1000, "the layout before 2.10")
S.eq(rt.layout_of(spec.to_robot, 2010000).slots[2].scale, 1000000, "the layout from 2.10")
S.eq(S.ports["tcp.port"], "50003", "the port registered")

-- A tvb whose ranges read big-endian int32s.
local function tvb(raw)
    local base = S.tvb(raw)
    return setmetatable({len = function() return #raw end, raw = function() return raw end}, {__call = function(_, o, n)
        local r = base(o, n)
        r.int = function()
            local b1, b2, b3, b4 = string.byte(raw, o + 1, o + 4)
            local u = ((b1 * 256 + b2) * 256 + b3) * 256 + b4
            return u >= 2147483648 and u - 4294967296 or u
        end
        return r
    end})
end
local function be(...)
    local out = {}
    for _, v in ipairs({...}) do
        if v < 0 then v = v + 4294967296 end
        out[#out + 1] = string.char(math.floor(v / 16777216) % 256, math.floor(v / 65536) % 256,
                                    math.floor(v / 256) % 256, v % 256)
    end
    return table.concat(out)
end
local function dissect(raw, to_port)
    local tree = S.tree()
    local p = {number = 1, visited = false, src_port = to_port and 40000 or 50003, dst_port = to_port and 50003 or 40000,
               match_uint = 50003, can_desegment = 2, cols = {info = S.column(), protocol = S.column()}}
    made.dissector(tvb(raw), p, tree)
    local dump = S.dump(tree)
    assert(not dump:find("internal_error", 1, true), dump)
    return dump, p
end

-- From the robot (bytes to the port): the result.
local out = dissect(be(0), true)
assert(out:find("ur_trajectory.result @0+4", 1, true), out)
-- From the PC: a point of the default release, then 5 bytes of the next.
local p
out, p = dissect(be(1500000, -1, 2500000) .. "\0\0\0\0\0", false)
assert(out:find("ur_trajectory.positions @0+4 = 1.5", 1, true), out)
assert(out:find("(raw 1500000, scaled by MULT_JOINTSTATE = 1000000)", 1, true), out)
assert(out:find("ur_trajectory.positions_raw @4+4 = -1", 1, true), out)
assert(out:find("ur_trajectory.duration @8+4 = 2.5", 1, true), out)
S.eq(p.desegment_offset, 12, "the next record waits")
S.eq(p.desegment_len, 7, "for the rest of its bytes")
S.eq(tostring(p.cols.info), "Trajectory point", "the Info column")
print("ok")
