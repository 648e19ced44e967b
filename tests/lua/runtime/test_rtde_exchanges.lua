-- runtime/lua/typed_messages/exchanges.lua: each reply linked with the oldest request of its pair
-- still awaiting one, pairs apart, at most max_pending kept per pair; a reply with no request seen
-- (a capture that starts later) links to none; messages in no pair cost nothing.
local S = dofile("stubs.lua")
S.wireshark_globals()
local spec = {
    exchange_fields = { response_in = "rtde.response_in", response_to = "rtde.response_to", time = "rtde.time" },
    exchanges = { requests = { setup_outputs = 1, pause = 2 }, replies = { setup_outputs_reply = 1, pause_reply = 2 },
                  count = 2, max_pending = 2 },
}
local rt = S.load("common/pending.lua", spec)
S.load("common/exchange.lua", spec, rt)
S.load("typed_messages/exchanges.lua", spec, rt)

local state = {}
local function message(name, number)
    local view = {}
    rt.follow_exchange(state, view, name, { number = number, rel_ts = number / 100 })
    return view
end
S.eq(message("data_package", 1).link, nil, "a data package is in no pair")
S.eq(state.exchanges, nil, "and makes no queues")
S.eq(message("pause_reply", 2).link, nil, "a reply with no request seen: no link")
local setup, pause = message("setup_outputs", 3), message("pause", 4)
local pause_reply = message("pause_reply", 5)
S.eq(pause_reply.link.response_to, 4, "a reply answers its own pair's request, not the older setup")
S.eq(tostring(pause_reply.link.time), "0.010000000", "with the time since it")
S.eq(pause.request.response_in, 5, "and the request links to it")
S.eq(setup.request.response_in, nil, "the setup still awaits")
local second, third = message("setup_outputs", 6), message("setup_outputs", 7)
S.eq(third.request, nil, "past max_pending (2): not kept, not linked")
S.eq(message("setup_outputs_reply", 8).link.response_to, 3, "replies in order: the oldest first")
S.eq(message("setup_outputs_reply", 9).link.response_to, 6, "then the next")
S.eq(message("setup_outputs_reply", 10).link, nil, "the reply to the one not kept links to none")
S.eq(second.request.response_in, 9, "each request its own reply")

local item, range = S.tree(), S.tvb("ab")(0, 1)
rt.show_exchange(item, range, setup)
rt.show_exchange(item, range, pause_reply)
rt.show_exchange(item, range, {})
S.eq(#item.children, 3, "a request's response_in, a reply's response_to and time, nothing for the rest")
print("ok")
