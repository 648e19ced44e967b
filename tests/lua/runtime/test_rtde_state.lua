-- runtime/lua/typed_messages/state.lua: the protocol version negotiated, setup replies matched to
-- their requests in order, recipes per direction, refusals and a refused start; requests beyond the
-- bounds not kept and their replies paired with nothing; versions with no layouts; variables
-- retyped; a recipe's value offsets worked out at its setup.
local S = dofile("stubs.lua")
local spec = {
    default_protocol = 2,
    max_pending_setups = 4,
    max_pending_version_requests = 2,
    protocol_versions = { [1] = true, [2] = true },
    variable_types = { timestamp = "DOUBLE", actual_q = "VECTOR6D" },
    recipe_kinds = {
        { name = "outputs", from_robot = true, requests = { "setup_outputs", "setup_outputs_v1" },
          replies = { "setup_outputs_reply", "setup_outputs_reply_v1" } },
        { name = "inputs", from_robot = false, requests = { "setup_inputs" }, replies = { "setup_inputs_reply" } },
    },
    refusals = { NOT_FOUND = true, IN_USE = true },
    value_types = { DOUBLE = { size = 8, count = 1 }, VECTOR6D = { size = 8, count = 6 },
                    INT32 = { size = 4, count = 1 } },
}
local rt = S.load("common/pending.lua", spec)
S.load("typed_messages/state.lua", spec, rt)

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
notes = rt.follow(st, "setup_outputs_reply", { recipe_id = 1, types = "DOUBLE,VECTOR6D" }, 8)
S.eq(notes.names[2] .. "/" .. #notes.names, "actual_q/2", "a good reply names the variables its types answer")
S.eq(notes.refused == nil and notes.warning == nil and notes.retyped == nil, true, "and says nothing else")
local recipe = rt.recipe_for(st, true, 1)
S.eq(recipe.names[2] .. ":" .. recipe.types[2] .. "@" .. recipe.frame, "actual_q:VECTOR6D@8", "recipe 1 by its reply")
S.eq(table.concat(recipe.offsets, ",") .. "/" .. recipe.size, "0,8/56", "its values' offsets, worked out at setup")
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

-- A version with no layouts changes nothing, and says so.
st = rt.new_state()
rt.follow(st, "request_protocol_version", { protocol_version = 300 }, 1)
notes = rt.follow(st, "request_protocol_version_reply", { accepted = 1 }, 2)
S.eq(notes.protocol_error, "protocol version 300 accepted, which has no layouts: protocol 2 stays in force", "300")
S.eq(st.protocol, nil, "the protocol in force stays")

-- Version requests beyond the bound (2 here): not kept, and their replies pair with nothing.
st = rt.new_state()
for frame = 1, 3 do
    notes = rt.follow(st, "request_protocol_version", { protocol_version = frame == 3 and 1 or 2 }, frame)
end
S.eq(notes.not_kept, "protocol version request not kept: more than 2 protocol version requests awaited replies",
     "the third request")
rt.follow(st, "request_protocol_version_reply", { accepted = 1 }, 4)
rt.follow(st, "request_protocol_version_reply", { accepted = 1 }, 5)
notes = rt.follow(st, "request_protocol_version_reply", { accepted = 1 }, 6)
S.eq(notes.not_kept ~= nil and rt.protocol_of(st), 2, "the third reply pairs with nothing: protocol 1 never asked")

-- Setups beyond the bound (4 here): the fifth and, while its reply is ahead, the sixth are not kept.
st = rt.new_state()
for frame = 1, 5 do rt.follow(st, "setup_outputs", { variables = "v" .. frame }, frame) end
for id = 1, 4 do rt.follow(st, "setup_outputs_reply", { recipe_id = id, types = "DOUBLE" }, 10 + id) end
S.eq(rt.recipe_for(st, true, 4).names[1], "v4", "reply 4 keeps its own request's names")
notes = rt.follow(st, "setup_outputs", { variables = "v6" }, 20)
S.eq(notes.not_kept, "setup not kept: more than 4 setups awaited replies", "the sixth, behind a lost one")
rt.follow(st, "setup_outputs", { variables = "v" }, 21)
st.recipes.outputs[5] = { names = { "old" } }
notes = rt.follow(st, "setup_outputs_reply", { recipe_id = 5, types = "DOUBLE" }, 22)
S.eq(notes.not_kept, "reply to a setup that was not kept: more than 4 setups awaited replies", "reply 5")
S.eq(rt.recipe_for(st, true, 5), nil, "its id has no recipe: not the one it replaced")

-- A variable the reply types otherwise than the table.
S.eq(rt.retyped("timestamp", "UINT8"), "timestamp: UINT8 by the setup reply, DOUBLE in the variable table", "retyped")
S.eq(rt.retyped("timestamp", "DOUBLE"), nil, "as the table types it")
S.eq(rt.retyped("a_newer_one", "UINT8"), nil, "a name the table lacks")
print("ok")
