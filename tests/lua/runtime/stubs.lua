-- Stand-ins for the few Wireshark objects the runtime touches, so that each runtime file runs
-- under plain lua5.2, lua5.3 and lua5.4. Fields are plain strings in these tests ("ur.a.b"),
-- so a tree dumps to readable lines.
local S = {}

S.RUNTIME = assert(os.getenv("URWIRE_RUNTIME"), "set URWIRE_RUNTIME to runtime/lua")

-- Run one runtime file as the generated dissector does: a chunk called with (spec, rt).
function S.load(name, spec, rt)
    rt = rt or {}
    local chunk = assert(loadfile(S.RUNTIME .. "/" .. name))
    chunk(spec or {}, rt)
    return rt
end

-- A string of bytes from numbers: S.bytes(0, 0, 0, 5, 20).
function S.bytes(...)
    return string.char(...)
end

-- A tvb over a Lua string: tvb(o, n) is a range, tvb() the whole of it.
function S.tvb(raw)
    local tvb = { raw_bytes = raw }
    local function range(o, n)
        o = o or 0
        n = n or #raw - o
        return {
            offset = o, len = n,
            string = function() return string.sub(raw, o + 1, o + n) end,
            float = function()   -- big-endian float32 (enough for the tests: normal numbers)
                local b1, b2, b3, b4 = string.byte(raw, o + 1, o + 4)
                local sign = b1 >= 128 and -1 or 1
                local exp = (b1 % 128) * 2 + math.floor(b2 / 128)
                local mant = ((b2 % 128) * 256 + b3) * 256 + b4
                if exp == 0 and mant == 0 then return 0.0 end
                return sign * (1 + mant / 8388608) * 2 ^ (exp - 127)
            end,
        }
    end
    function tvb:len() return #raw end
    function tvb:range(o, n) return range(o, n) end
    function tvb:raw() return raw end
    return setmetatable(tvb, { __call = function(_, o, n) return range(o, n) end })
end

-- A tree that records what is added to it.
local Node = {}
Node.__index = Node

local function node(f, range, value)
    if type(range) ~= "table" then range, value = nil, range end   -- tree:add(f, value): generated
    return setmetatable({ f = f, offset = range and range.offset, len = range and range.len, value = value,
                          children = {}, experts = {}, visible = true }, Node)
end

function S.tree(visible)
    local t = node("root")
    t.visible = visible ~= false
    t.asked = {}   -- fields a filter "references"
    return t
end

function Node:add(f, range, value)
    local child = node(f, range, value)
    child.asked = self.asked
    self.children[#self.children + 1] = child
    return child
end
function Node:add_packet_field(f, range, enc) return self:add(f, range, range:string()) end
function Node:set_text(text) self.text = text end
function Node:append_text(text) self.text = (self.text or "") .. text end
function Node:set_len(n) self.len = n end
function Node:set_generated() self.generated = true; return self end
function Node:add_proto_expert_info(e, text) self.experts[#self.experts + 1] = { e = e, text = text } end
function Node:add_tvb_expert_info(e, range, text)
    local child = self:add(e, range)
    child:add_proto_expert_info(e, text)
    return child
end
function Node:referenced(f) return self.asked[f] == true end

-- Wireshark's class tables, from which the runtime takes the methods it calls for every field.
TreeItem = { add = Node.add, append_text = Node.append_text, set_text = Node.set_text }
Tvb = { range = function(tvb, o, n) return tvb(o, n) end }

-- The tree as lines "<indent><field> @<offset>+<len>[ = value][ (text)][ !expert: text]".
function S.dump(t)
    local out = {}
    local function walk(n, indent)
        for _, c in ipairs(n.children) do
            local line = indent .. tostring(c.f) .. " @" .. tostring(c.offset) .. "+" .. tostring(c.len)
            if c.value ~= nil then line = line .. " = " .. tostring(c.value) end
            if c.text then line = line .. " (" .. c.text .. ")" end
            out[#out + 1] = line
            for _, e in ipairs(c.experts) do out[#out + 1] = indent .. "  !" .. tostring(e.e) .. ": " .. e.text end
            walk(c, indent .. "  ")
        end
    end
    for _, e in ipairs(t.experts) do out[#out + 1] = "!" .. tostring(e.e) .. ": " .. e.text end
    walk(t, "")
    return table.concat(out, "\n")
end

-- A column of the packet list: set, append, tostring.
function S.column()
    local col = { text = "" }
    function col:set(text) self.text = text end
    function col:append(text) self.text = self.text .. text end
    return setmetatable(col, { __tostring = function(c) return c.text end })
end

-- The message being dissected, as the walker sees it.
function S.st(raw, version)
    return { raw = raw, base = 0, version = version or 5009000, known = true, announced = true, visible = true,
             message_version = version or 5009000 }
end

-- The expert infos and extra fields of runtime/lua/packages/declare.lua, as plain strings.
S.X = { raw = "ur.raw", extra = "ur.extra", skipped = "ur.skipped", version = "ur.software_version",
        assumed = "ur.version_assumed", unknown_package = "ur.unknown_package", urscript = "ur.urscript" }
S.E = { bad_length = "bad_length", bad_type = "bad_type", malformed = "malformed", extra = "extra",
        unknown = "unknown", assumed = "assumed", by_length = "by_length", internal = "internal" }

-- rt after bytes.lua, read_faults.lua, versions.lua and items.lua, and after the walker.
function S.base_rt(spec)
    spec = spec or {}
    spec.default_version = spec.default_version or "5.9"
    spec.max_tree_items = spec.max_tree_items or 10000
    local rt = S.load("common/bytes.lua", spec)
    S.load("packages/read_faults.lua", spec, rt)
    S.load("packages/versions.lua", spec, rt)
    S.load("packages/items.lua", spec, rt)
    return rt, spec
end

function S.walker_rt(spec)
    local rt
    rt, spec = S.base_rt(spec)
    spec.max_value_depth = spec.max_value_depth or 8
    spec.value_tables = spec.value_tables or { { kinds = {}, min_size = 1 } }
    S.load("packages/walk.lua", spec, rt)
    S.load("packages/values.lua", spec, rt)
    return rt, spec
end

ENC_UTF_8 = ENC_UTF_8 or 0x2

-- Field.new: an extractor giving the value S.fields holds for its field now (nil: none, as on a
-- first pass without a tree); each value a table with .value, as a FieldInfo has.
S.fields = {}
Field = Field or { new = function(name) return function() return S.fields[name] end end }

-- The Wireshark globals a whole dissector uses at load time, as recorders: a ProtoField is its
-- filter name, a preference its default value, registered ports are kept in S.ports.
function S.wireshark_globals()
    local names = setmetatable({}, { __index = function(_, k) return k end })
    base, expert = names, { group = names, severity = names }
    ProtoField = setmetatable({}, { __index = function(_, ctor)
        return function(abbr) return abbr end
    end })
    ProtoExpert = { new = function(abbr) return abbr end }
    Proto = function(name, desc)
        local prefs = {}
        local values = {}
        setmetatable(prefs, { __newindex = function(_, k, pref) values[k] = pref.default end,
                              __index = values })
        return setmetatable({ name = name, description = desc, prefs = prefs },
                            { __tostring = function(proto) return proto.name end })
    end
    Pref = {
        range = function(label, default) return { default = default } end,
        string = function(label, default) return { default = default } end,
        uint = function(label, default) return { default = default } end,
        bool = function(label, default) return { default = default } end,
    }
    S.ports = {}
    DissectorTable = { get = function(name)
        return {
            add = function(_, ports, proto) S.ports[name] = ports end,
            remove = function(_, ports, proto) S.ports[name] = nil end,
        }
    end }
    Dissector = { get = function(name) return "dissector:" .. name end }
    ByteArray = { new = function(bytes, raw)
        return { tvb = function(_, name) return S.tvb(bytes) end }
    end }
    S.plugin_info = nil
    set_plugin_info = function(info) S.plugin_info = info end
    DESEGMENT_ONE_MORE_SEGMENT = 0x0fffffff
    frametype = names
    local nstime = { __tostring = function(t) return string.format("%d.%09d", t.secs, t.nsecs) end }
    NSTime = { new = function(secs, nsecs) return setmetatable({ secs = secs, nsecs = nsecs }, nstime) end }
end

-- A pinfo for a call from the robot (port 30001) to a client; `robot` its address (a string
-- stands in for Wireshark's Address, which tostring() turns into the same text).
function S.pinfo(number, visited, robot)
    return { number = number, visited = visited or false, src_port = 30001, dst_port = 50000,
             src = robot or "192.168.56.101", dst = "192.168.56.1",
             match_uint = 30001, can_desegment = 2,
             cols = { info = S.column(), protocol = S.column() } }
end

-- Checks: each failure names what was compared.
function S.eq(actual, expected, what)
    if actual ~= expected then
        error(string.format("%s:\n  expected: %s\n  actual:   %s", what or "value", tostring(expected), tostring(actual)), 2)
    end
end

function S.lines(...)
    return table.concat({ ... }, "\n")
end

return S
