-- runtime/rtde_state.lua: the protocol version negotiated, setup replies matched to their requests
-- in order, recipes per direction, refusals and a refused start.
local S = dofile("stubs.lua")
local spec = {
    default_protocol = 2,
    max_pending_setups = 4,
    recipe_kinds = {
        { name = "outputs", from_robot = true, requests = { "setup_outputs", "setup_outputs_v1" },
          replies = { "setup_outputs_reply", "setup_outputs_reply_v1" } },
        { name = "inputs", from_robot = false, requests = { "setup_inputs" }, replies = { "setup_inputs_reply" } },
    },
    refusals = { NOT_FOUND = true, IN_USE = true },
    value_types = { DOUBLE = {}, VECTOR6D = {}, INT32 = {} },
}
local rt = S.load("rtde_state.lua", spec)

S.eq(table.concat(rt.split("a,b,c", ","), "|"), "a|b|c", "split")
S.eq(#rt.split("", ","), 0, "no names")

local st = rt.new_state()
S.eq(rt.protocol_of(st), 2, "the spec's default until negotiated")
rt.follow(st, "request_protocol_version", { protocol_version = 2 }, 1)
rt.follow(st, "request_protocol_version_reply", { accepted = 0 }, 2)
S.eq(rt.protocol_of(st), 1, "refused: protocol 1 stays")
rt.follow(st, "request_protocol_version", { protocol_version = 2 }, 3)
rt.follow(st, "request_protocol_version_reply", { accepted = 1 }, 4)
S.eq(rt.protocol_of(st), 2, "accepted: the protocol asked for")

-- Two output setups in flight: the replies take their requests in order.
rt.follow(st, "setup_outputs", { variables = "timestamp,actual_q,nope" }, 5)
rt.follow(st, "setup_outputs", { variables = "timestamp,actual_q" }, 6)
local notes = rt.follow(st, "setup_outputs_reply", { recipe_id = 0, types = "DOUBLE,VECTOR6D,NOT_FOUND" }, 7)
S.eq(notes.refused[1][1] .. "=" .. notes.refused[1][2], "nope=NOT_FOUND", "the refused name")
S.eq(rt.follow(st, "setup_outputs_reply", { recipe_id = 1, types = "DOUBLE,VECTOR6D" }, 8), nil, "a good reply")
local recipe = rt.recipe_for(st, true, 1)
S.eq(recipe.names[2] .. ":" .. recipe.types[2] .. "@" .. recipe.frame, "actual_q:VECTOR6D@8", "recipe 1 by its reply")
S.eq(rt.recipe_for(st, false, 1), nil, "inputs are another direction's recipes")
S.eq(rt.recipe_for(st, true, 0), nil, "a refused setup makes no recipe")

rt.follow(st, "setup_inputs", { variables = "input_int_register_24" }, 9)
notes = rt.follow(st, "setup_inputs_reply", { recipe_id = 0, types = "IN_USE" }, 10)
S.eq(notes.refused[1][2], "IN_USE", "in use")
notes = rt.follow(st, "setup_inputs_reply", { recipe_id = 3, types = "DOUBLE" }, 11)
S.eq(notes.warning ~= nil, true, "a reply without its request is flagged")

-- Protocol 1's output recipe has no id.
rt.follow(st, "setup_outputs_v1", { variables = "timestamp" }, 12)
rt.follow(st, "setup_outputs_reply_v1", { types = "DOUBLE" }, 13)
S.eq(rt.recipe_for(st, true, nil).frame, 13, "the one output recipe")
S.eq(rt.follow(st, "start_reply", { accepted = 0 }, 14).warning, "the robot refused to start", "refused start")
S.eq(rt.follow(st, "start_reply", { accepted = 1 }, 15), nil, "a start")
S.eq(rt.new_state().recipes.outputs[1], nil, "every conversation starts empty")
print("ok")
