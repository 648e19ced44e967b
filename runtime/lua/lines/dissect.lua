-- A dissector of text lines (the dashboard server, the driver's script sender): lines
-- reassembled across TCP segments, each shown as a request (command) or a reply, replies paired
-- with their requests and the software version learnt per conversation (both addresses and both
-- ports: two robots or two clients never share it), each reply linked with its request both ways
-- (runtime/lua/common/exchange.lua), expert infos for a reply that says an error, an unknown
-- command, a command the version lacks, a line too long.
local spec, rt = ...
local matches, find_command, classify, shown = rt.matches, rt.find_command, rt.classify, rt.shown
local available, version_in, parse_version = rt.available, rt.version_in, rt.parse_version
local pending_queue, push, pop = rt.pending_queue, rt.pending_push, rt.pending_pop
local exchange_request, exchange_reply = rt.exchange_request, rt.exchange_reply

local proto = Proto(spec.name, spec.title)
local L, D = spec.labels, spec.docs or {}
local function text_field(name)
    return ProtoField.string(spec.name .. "." .. name, L[name], base.NONE, D[name])
end
local function bool_field(name)
    return ProtoField.bool(spec.name .. "." .. name, L[name], base.NONE, nil, nil, D[name])
end
local F = {
    command = text_field("command"), command_name = text_field("command_name"), argument = text_field("argument"),
    available = bool_field("available"), reply = text_field("reply"), reply_name = text_field("reply_name"),
    error = bool_field("error"),
}
local E = {
    error_reply = ProtoExpert.new(spec.name .. ".error_reply", "The reply says an error",
        expert.group.RESPONSE_CODE, expert.severity.WARN),
    unknown_command = ProtoExpert.new(spec.name .. ".unknown_command", "Unknown command",
        expert.group.MALFORMED, expert.severity.WARN),
    unavailable = ProtoExpert.new(spec.name .. ".unavailable", "The software version lacks this command",
        expert.group.PROTOCOL, expert.severity.WARN),
    too_long = ProtoExpert.new(spec.name .. ".too_long", "Line longer than " .. spec.max_line .. " bytes",
        expert.group.MALFORMED, expert.severity.ERROR),
    not_kept = ProtoExpert.new(spec.name .. ".not_kept", spec.not_kept, expert.group.SEQUENCE, expert.severity.ERROR),
    reply_not_kept = ProtoExpert.new(spec.name .. ".reply_not_kept", spec.reply_not_kept,
        expert.group.SEQUENCE, expert.severity.ERROR),
    internal = ProtoExpert.new(spec.name .. ".internal_error", "Dissector error",
        expert.group.MALFORMED, expert.severity.ERROR),
}
proto.fields = {F.command, F.command_name, F.argument, F.available, F.reply, F.reply_name, F.error}
for _, f in ipairs(rt.exchange_field_list) do proto.fields[#proto.fields + 1] = f end
proto.experts = {E.error_reply, E.unknown_command, E.unavailable, E.too_long, E.not_kept, E.reply_not_kept, E.internal}
proto.prefs.version = Pref.string("Software version", "",
    "Controller software version (as 5.11 or 3.15.7) assumed until a PolyscopeVersion reply tells it: \z
    commands it lacks are flagged. Empty: none assumed.")

-- ---- state per conversation, and what the first pass decided per line ----

local conversations, decided = {}, {}

-- A conversation: both ends, and Wireshark's TCP conversation where the tree has it (the
-- innermost tcp.stream), so that a new connection on the same addresses and ports pairs nothing
-- with the last one's commands, as in the native plugin.
local tcp_stream_index = rt.tcp_stream_index

local function conversation_key(pinfo, from_server)
    local server = tostring(from_server and pinfo.src or pinfo.dst) .. ":" ..
        (from_server and pinfo.src_port or pinfo.dst_port)
    local client = tostring(from_server and pinfo.dst or pinfo.src) .. ":" ..
        (from_server and pinfo.dst_port or pinfo.src_port)
    local index = tcp_stream_index()
    return server .. "<>" .. client .. (index and "#" .. tostring(index) or "")
end

local function conversation(key)
    local c = conversations[key]
    if not c then
        c = {pending = pending_queue(spec.pending_kept), greeted = false, version = parse_version(proto.prefs.version),
             skipping = {[true] = false, [false] = false}}
        conversations[key] = c
    end
    return c
end

-- A request awaits its reply: its decision (the command, nil when unknown, and its exchange); false
-- when it is not kept. A command that comes when pending_kept await replies is not kept but counted
-- lost, and so is every command behind a lost one (replies come in order,
-- runtime/lua/common/pending.lua): no reply is paired with another command.
local function keep(c, d)
    if not spec.one_reply_per_request then     -- only the latest request counts (c.latest)
        c.latest = d
        return true
    end
    return push(c.pending, d)
end

-- The request a reply answers (nil: none), and whether it answers one that was not kept.
local function answered(c)
    if not spec.one_reply_per_request then
        return c.latest, false   -- every answering line belongs to the latest request
    end
    local paired, d = pop(c.pending)
    return d, not paired
end

-- A line too long is still a line: a command the server answers, or the reply to one, so that
-- the pairing of the lines after it holds (and its exchange is linked, though not shown).
local function count_too_long(c, requests, pinfo)
    if requests then
        keep(c, {exchange = exchange_request(pinfo)})
    else
        c.greeted = true
        local request = answered(c)
        exchange_reply(request and request.exchange, pinfo)
    end
end

-- A command's line: its name, argument, whether the version has it (nil: version unknown), and its
-- exchange (which the reply paired with it completes).
local function decide_command(c, text, pinfo)
    local index, argument = find_command(text)
    local d = {command = index, argument = argument, exchange = exchange_request(pinfo)}
    d.not_kept = not keep(c, d)
    if index and c.version then d.available = available(index, c.version) end
    return d
end

-- A reply's line: the banner, or the command it answers, what it says and its link to the command.
local function decide_reply(c, text, pinfo)
    if not c.greeted then
        c.greeted = true
        if spec.banner and matches(spec.banner.pieces, text) then return {reply = spec.banner} end
    end
    local request, not_kept = answered(c)
    local command = request and request.command
    if command and command == spec.version_command then
        c.version = version_in(text) or c.version
    end
    return {command = command, reply = classify(command, text), not_kept = not_kept,
            link = exchange_reply(request and request.exchange, pinfo)}
end

-- ---- the tree ----

local function show_command(tree, range, text, d)
    local item = tree:add(proto, range)
    item:add(F.command, range, text)
    if d.command then
        item:add(F.command_name, range, spec.commands[d.command].name):set_generated()
        if d.argument then item:add(F.argument, range, shown(d.argument)) end
        if d.available ~= nil then
            local it = item:add(F.available, range, d.available):set_generated()
            if not d.available then
                it:add_proto_expert_info(E.unavailable, "The software version lacks this command")
            end
        end
    else
        item:add_proto_expert_info(E.unknown_command, "Unknown command")
    end
    if d.not_kept then item:add_proto_expert_info(E.not_kept, spec.not_kept) end
    rt.show_exchange_request(item, range, d.exchange)
    item:append_text(": " .. text)
    return "Command: " .. text
end

local function show_reply(tree, range, text, d)
    local item = tree:add(proto, range)
    item:add(F.reply, range, text)
    if d.command then item:add(F.command_name, range, spec.commands[d.command].name):set_generated() end
    if d.reply then item:add(F.reply_name, range, d.reply.name):set_generated() end
    local says_error = d.reply ~= nil and d.reply.error
    local it = item:add(F.error, range, says_error):set_generated()
    if says_error then it:add_proto_expert_info(E.error_reply, "The reply says an error") end
    if d.not_kept then item:add_proto_expert_info(E.reply_not_kept, spec.reply_not_kept) end
    rt.show_exchange_reply(item, range, d.link)
    item:append_text(": " .. text)
    return "Reply: " .. text
end

-- ---- lines ----

local function dissect(tvb, pinfo, tree)
    local n = tvb:len()
    -- The server sends from its port; the robot is the server but for the driver's sockets.
    local from_server = pinfo.src_port == pinfo.match_uint
    local from_robot = from_server ~= spec.robot_is_client
    local requests = from_robot == spec.requests_from_robot
    local key = conversation_key(pinfo, from_server)
    local c = conversation(key)
    pinfo.cols.protocol = spec.short
    local infos = {}
    local at = 0
    local here = tostring(pinfo.number) .. ":" .. tostring(from_robot) .. ":"
    local first_pass = not pinfo.visited
    local buf = tvb:raw(0, n)
    local skipping = c.skipping[from_robot]
    if first_pass then decided[here .. "skip"] = skipping else skipping = decided[here .. "skip"] end
    while at < n do
        local nl = string.find(buf, "\n", at + 1, true)
        if skipping then
            if not nl then at = n break end
            tree:add(proto, tvb(at, nl - at)):set_text("Rest of a line too long")
            skipping, at = false, nl
        elseif not nl and n - at <= spec.max_line + 1 then
            if pinfo.can_desegment > 0 then
                pinfo.desegment_offset = at
                pinfo.desegment_len = DESEGMENT_ONE_MORE_SEGMENT
                break
            end
            tree:add(proto, tvb(at, n - at)):set_text("Part of a line (reassembly is off)")
            at = n
        else
            local stop = nl and nl - 1 or n
            local len = stop - at
            if nl and len > 0 and string.byte(buf, stop) == 13 then len = len - 1 end
            if not nl or len > spec.max_line then
                local item = tree:add(proto, tvb(at, stop - at))
                item:add_proto_expert_info(E.too_long, "Line longer than " .. spec.max_line .. " bytes")
                infos[#infos + 1] = "Line too long"
                if first_pass then count_too_long(c, requests, pinfo) end
                if not nl then skipping = true end
                at = nl or n
            else
                local text = string.sub(buf, at + 1, at + len)
                local range = len > 0 and tvb(at, len) or tvb(at, 1)
                local slot = here .. at
                local d = decided[slot]
                if first_pass or not d then
                    d = requests and decide_command(c, text, pinfo) or decide_reply(c, text, pinfo)
                    decided[slot] = d
                end
                infos[#infos + 1] = (requests and show_command or show_reply)(tree, range, shown(text), d)
                at = nl
            end
        end
    end
    if first_pass then c.skipping[from_robot] = skipping end
    if #infos > 0 then pinfo.cols.info = table.concat(infos, "; ") end
    return n
end

proto.dissector = rt.guard(proto, dissect, E.internal, spec.name)

function proto.init()
    conversations, decided = {}, {}
end

rt.register_port_preference(proto, spec.name, table.concat(spec.ports, ","))
