-- runtime/lua/packages/wanted.lua: which robot-state packages a tshark -T fields command line needs.
local S = dofile("stubs.lua")

local JOINTS = { name = "joint_data" }
local MODE = { name = "robot_mode_data" }
local TOOL = { name = "tool_data" }
local function forms(part) return { single = true, { of = part } } end
local spec = {
    F = { ["joint_data.q_actual"] = 1, ["robot_mode_data.robot_mode"] = 2, ["tool_data.tool_mode"] = 3,
          ["key.title"] = 4, ["length"] = 5, ["package.type"] = 6 },
    messages = {
        [16] = { kind = "packages", packages = { [1] = forms(JOINTS), [0] = forms(MODE), [2] = forms(TOOL) } },
        [20] = { kind = "subtypes" },
    },
}
local rt = S.load("packages/wanted.lua", spec, {})

local function names(...) return rt.named_fields({ ... }) end
local function set(t)
    local out = {}
    for k in pairs(t or {}) do out[#out + 1] = type(k) == "table" and k.name or k end
    table.sort(out)
    return table.concat(out, " ")
end

-- The ur names of a tshark -T fields run, from every argument.
S.eq(set(names("tshark", "-r", "x.pcap", "-T", "fields", "-e", "ur.joint_data.q_actual")), "ur.joint_data.q_actual",
     "one field")
S.eq(set(names("/usr/bin/tshark", "-Tfields", "-eur.joint_data.q_actual", "-Y", "ur.robot_mode_data.robot_mode == 7")),
     "ur.joint_data.q_actual ur.robot_mode_data.robot_mode", "joined options, and a display filter's fields")
S.eq(set(names("tshark", "-T", "fields", "-e", "frame.number", "-X", "lua_script:/x/urwire.lua")), "",
     "no ur field: the plugin's path is not one")
S.eq(names("tshark", "-V"), nil, "another output: every field")
S.eq(names("tshark", "-T", "json", "-e", "ur.joint_data.q_actual"), nil, "-e with -T json: every field")
S.eq(names("wireshark", "-T", "fields"), nil, "not tshark")
S.eq(names("tshark", "-T", "fields", "-e", "frame.number", "-z", "expert"), nil, "expert infos: every package")
S.eq(names("tshark", "-T", "fields", "-e", "frame.number", "-Y", "${robot}"), nil, "a filter macro: every package")
S.eq(names(), nil, "no command line")

-- The packages they name; nil: every one.
local function packages(...) return rt.packages_named(names("tshark", "-T", "fields", ...)) end
S.eq(set(packages("-e", "ur.joint_data.q_actual")), "joint_data", "the package of a field")
S.eq(set(packages("-e", "ur.joint_data.q_actual", "-Y", "ur.tool_data")), "joint_data tool_data", "and a package's item")
S.eq(set(packages("-e", "ur.key.title", "-e", "ur.length")), "", "message fields: no package")
S.eq(packages("-e", "ur.raw"), nil, "a field that shows inside any package: every one")
S.eq(packages("-Y", "ur.malformed"), nil, "an expert's name: every one")
S.eq(packages("-e", "ur.package.type"), nil, "package headers: every one")

-- Found once per run from this process's command line (not tshark here: every package); the
-- preference off builds every package too.
S.eq(rt.wanted_packages(), nil, "lua is not tshark")
rt.named_only(false)
S.eq(rt.wanted_packages(), nil, "preference off")
print("ok")
