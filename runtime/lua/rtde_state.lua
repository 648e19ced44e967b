-- RTDE's state of one conversation, as plain Lua (no Wireshark object): the protocol version
-- negotiated, the setup requests waiting for their replies, and the recipes that replies make.
-- runtime/lua/rtde_dissect.lua keeps one per conversation and calls rt.follow on each message,
-- in capture order, on the first pass.
local spec, rt = ...

local KIND_OF_REQUEST, KIND_OF_REPLY, KIND_OF_DATA = {}, {}, {}
for _, kind in ipairs(spec.recipe_kinds) do
    for _, name in ipairs(kind.requests) do KIND_OF_REQUEST[name] = kind.name end
    for _, name in ipairs(kind.replies) do KIND_OF_REPLY[name] = kind.name end
    KIND_OF_DATA[kind.from_robot] = kind.name
end

-- Protocol 1's one output recipe has no id: it is kept under this key.
local NO_ID = -1

local function queue() return { first = 1, last = 0 } end
local function push(q, v) q.last = q.last + 1; q[q.last] = v end
local function pop(q)
    if q.first > q.last then return nil end
    local v = q[q.first]
    q[q.first] = nil
    q.first = q.first + 1
    return v
end

function rt.new_state()
    local state = { protocol = nil, asked = queue(), pending = {}, recipes = {} }
    for _, kind in ipairs(spec.recipe_kinds) do
        state.pending[kind.name] = queue()
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

-- What a message changes. `values` holds the message's fields as read (numbers and texts);
-- `frame` is its frame number. Returns what the dissector should show: { refused = { {name, word} },
-- warning = text } or nil.
function rt.follow(state, name, values, frame)
    if name == "request_protocol_version" then
        push(state.asked, values.protocol_version)
    elseif name == "request_protocol_version_reply" then
        local asked = pop(state.asked)
        if values.accepted ~= 0 and asked then
            state.protocol = asked
        elseif values.accepted == 0 and state.protocol == nil then
            state.protocol = 1   -- the robot keeps protocol 1 until a request is accepted
        end
    elseif KIND_OF_REQUEST[name] then
        local pending = state.pending[KIND_OF_REQUEST[name]]
        if pending.last - pending.first + 1 >= spec.max_pending_setups then pop(pending) end   -- the oldest
        local names = {}
        for _, name in ipairs(rt.split(values.variables, ",")) do
            if name ~= "" then names[#names + 1] = name end   -- an empty name names no variable
        end
        push(pending, { names = names, frame = frame })
    elseif KIND_OF_REPLY[name] then
        return rt.make_recipe(state, KIND_OF_REPLY[name], values, frame)
    elseif name == "start_reply" and values.accepted == 0 then
        return { warning = "the robot refused to start" }
    end
    return nil
end

function rt.make_recipe(state, kind, values, frame)
    local request = pop(state.pending[kind])
    if not request then
        return { warning = "a setup reply without a request seen: its recipe's names are unknown" }
    end
    local types = rt.split(values.types, ",")
    if #types ~= #request.names then
        return { warning = "names asked and types answered differ in number" }
    end
    local refused = {}
    for i, t in ipairs(types) do
        if spec.refusals[t] or not spec.value_types[t] then refused[#refused + 1] = { request.names[i], t } end
    end
    if #refused > 0 then return { refused = refused } end
    local id = values.recipe_id
    state.recipes[kind][id or NO_ID] = { id = id, names = request.names, types = types, frame = frame,
                                         request_frame = request.frame }
    return nil
end
