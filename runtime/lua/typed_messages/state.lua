-- RTDE's state of one conversation, as plain Lua (no Wireshark object): the protocol version
-- negotiated, the setup requests waiting for their replies, and the recipes that replies make.
-- runtime/lua/typed_messages/dissect.lua keeps one per conversation and calls rt.follow on each
-- message, in capture order, on the first pass.
local spec, rt = ...

local KIND_OF_REQUEST, KIND_OF_REPLY, KIND_OF_DATA = {}, {}, {}
for _, kind in ipairs(spec.recipe_kinds) do
    for _, name in ipairs(kind.requests) do KIND_OF_REQUEST[name] = kind.name end
    for _, name in ipairs(kind.replies) do KIND_OF_REPLY[name] = kind.name end
    KIND_OF_DATA[kind.from_robot] = kind.name
end

-- Protocol 1's one output recipe has no id: it is kept under this key.
local NO_ID = -1

-- Requests awaiting their replies (runtime/lua/common/pending.lua), with the words that say
-- how many a conversation keeps.
local push, pop = rt.pending_push, rt.pending_pop
local function queue(size, what)
    local q = rt.pending_queue(size)
    q.overflow = "more than " .. size .. " " .. what .. " awaited replies"
    return q
end

function rt.new_state()
    local state = { protocol = nil, asked = queue(spec.max_pending_version_requests, "protocol version requests"),
                    pending = {}, recipes = {} }
    for _, kind in ipairs(spec.recipe_kinds) do
        state.pending[kind.name] = queue(spec.max_pending_setups, "setups")
        state.recipes[kind.name] = {}
    end
    return state
end

-- The protocol version in force: negotiated, or the spec's default for a capture that starts later.
function rt.protocol_of(state)
    return state.protocol or spec.default_protocol
end

-- "a,b,c" -> { "a", "b", "c" }; "" -> {}.
function rt.split(text, separator)
    local out = {}
    if text == "" then return out end
    local at = 1
    while true do
        local cut = string.find(text, separator, at, true)
        if not cut then
            out[#out + 1] = string.sub(text, at)
            return out
        end
        out[#out + 1] = string.sub(text, at, cut - 1)
        at = cut + #separator
    end
end

-- The recipe a data package follows: by direction, and its id (nil: protocol 1's output recipe).
function rt.recipe_for(state, from_robot, recipe_id)
    return state.recipes[KIND_OF_DATA[from_robot]][recipe_id or NO_ID]
end

-- A protocol version reply: only a version with layouts is taken (a robot accepting 0 or 300 leaves
-- the one in force, and the reply says so).
local function version_reply(state, values)
    local paired, asked = pop(state.asked)
    local notes = nil
    if not paired then
        notes = { not_kept = "reply to a protocol version request that was not kept: " .. state.asked.overflow }
    end
    if values.accepted ~= 0 and asked then
        if spec.protocol_versions[asked] then
            state.protocol = asked
        else
            notes = { protocol_error = "protocol version " .. asked .. " accepted, which has no layouts: protocol "
                                       .. rt.protocol_of(state) .. " stays in force" }
        end
    elseif values.accepted == 0 and state.protocol == nil then
        state.protocol = 1   -- the robot keeps protocol 1 until a request is accepted
    end
    return notes
end

-- What a message changes. `values` holds the message's fields as read (numbers and texts);
-- `frame` is its frame number. Returns what the dissector should show: { names = the variables a
-- setup reply's types answer, refused = { {name, word} }, retyped = { text }, warning = text,
-- not_kept = text, protocol_error = text } or nil.
function rt.follow(state, name, values, frame)
    if name == "request_protocol_version" then
        if not push(state.asked, values.protocol_version) then
            return { not_kept = "protocol version request not kept: " .. state.asked.overflow }
        end
    elseif name == "request_protocol_version_reply" then
        return version_reply(state, values)
    elseif KIND_OF_REQUEST[name] then
        local pending = state.pending[KIND_OF_REQUEST[name]]
        local names = {}
        for _, name in ipairs(rt.split(values.variables, ",")) do
            if name ~= "" then names[#names + 1] = name end   -- an empty name names no variable
        end
        if not push(pending, { names = names, frame = frame }) then
            return { not_kept = "setup not kept: " .. pending.overflow }
        end
    elseif KIND_OF_REPLY[name] then
        return rt.make_recipe(state, KIND_OF_REPLY[name], values, frame)
    elseif name == "start_reply" and values.accepted == 0 then
        return { warning = "the robot refused to start" }
    end
    return nil
end

-- A reply the robot set up something with but whose recipe cannot be made (its request not kept or
-- unknown, names and types differing in number) removes the recipe its id had, so that data packages
-- of that id are not read by it. A refusal sets up nothing (recipe id 0): the recipe in force stays.
function rt.make_recipe(state, kind, values, frame)
    local paired, request = pop(state.pending[kind])
    local types = rt.split(values.types, ",")
    local notes = nil
    if not paired then
        notes = { not_kept = "reply to a setup that was not kept: " .. state.pending[kind].overflow }
    elseif not request then
        notes = { warning = "a setup reply without a request seen: its recipe's names are unknown" }
    elseif #types ~= #request.names then
        notes = { warning = "names asked and types answered differ in number" }
    end
    if notes then
        state.recipes[kind][values.recipe_id or NO_ID] = nil
        return notes
    end
    local shown = { names = request.names }
    local refused = {}
    for i, t in ipairs(types) do
        if spec.refusals[t] or not spec.value_types[t] then refused[#refused + 1] = { request.names[i], t } end
    end
    if #refused > 0 then
        shown.refused = refused
        return shown
    end
    local id = values.recipe_id
    local offsets, size = rt.value_offsets(types)
    state.recipes[kind][id or NO_ID] = { id = id, names = request.names, types = types, frame = frame,
                                         request_frame = request.frame, offsets = offsets, size = size }
    local retyped = {}
    for i, t in ipairs(types) do
        local text = rt.retyped(request.names[i], t)
        if text then retyped[#retyped + 1] = text end
    end
    if #retyped > 0 then shown.retyped = retyped end
    return shown
end

-- Where each value of a recipe starts among a data package's values, and their size in all: worked
-- out once, when the recipe is set up, so that a data package is read at known offsets.
function rt.value_offsets(types)
    local offsets, at = {}, 0
    for i, t in ipairs(types) do
        local vt = spec.value_types[t]
        offsets[i] = at
        at = at + vt.size * vt.count
    end
    return offsets, at
end

-- What to say of a variable the reply types otherwise than the variable table, or nil: its value is
-- shown by the reply's type, under a field of that type.
function rt.retyped(name, type_name)
    local table_type = spec.variable_types[name]
    if table_type and table_type ~= type_name then
        return name .. ": " .. type_name .. " by the setup reply, " .. table_type .. " in the variable table"
    end
    return nil
end
