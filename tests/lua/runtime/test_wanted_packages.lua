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
local rt = S.load("common/wanted.lua")
S.load("packages/wanted.lua", spec, rt)

local function set(t)
    local out = {}
    for k in pairs(t or {}) do out[#out + 1] = type(k) == "table" and k.name or k end
    table.sort(out)
    return table.concat(out, " ")
end

-- The packages the names of a tshark -T fields run need; nil: every one.
local function packages(...)
    return rt.packages_named(rt.named_fields({ "tshark", "-T", "fields", ... }, "ur."))
end
S.eq(set(packages("-e", "ur.joint_data.q_actual")), "joint_data", "the package of a field")
S.eq(set(packages("-e", "ur.joint_data.q_actual", "-Y", "ur.tool_data")), "joint_data tool_data", "and a package's item")
S.eq(set(packages("-e", "ur.key.title", "-e", "ur.length")), "", "message fields: no package")
S.eq(packages("-e", "ur.raw"), nil, "a field that shows inside any package: every one")
S.eq(packages("-Y", "ur.malformed"), nil, "an expert's name: every one")
S.eq(packages("-e", "ur.package.type"), nil, "package headers: every one")
S.eq(packages("-T", "json", "-e", "ur.joint_data.q_actual"), nil, "another output: every one")

-- Worked out for this process's command line (lua is not tshark here: every package); the
-- preference off builds every package too.
S.eq(rt.wanted_packages(), nil, "lua is not tshark")
rt.named_only(false)
S.eq(rt.wanted_packages(), nil, "preference off")
print("ok")
