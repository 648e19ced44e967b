-- RTDE's request/response links (runtime/lua/common/exchange.lua keeps the links themselves): a
-- reply answers the oldest request of its pair still awaiting one (the spec's exchanges.pairs), at
-- most spec.exchanges.max_pending kept per pair and conversation (runtime/lua/common/pending.lua:
-- one beyond is not linked, nor its reply). Data packages and text messages are in no pair and
-- cost nothing here.
local spec, rt = ...
local X = spec.exchanges
local push, pop = rt.pending_push, rt.pending_pop

local function queues()
    local q = {}
    for i = 1, X.count do q[i] = rt.pending_queue(X.max_pending) end
    return q
end

-- On the first pass: what a message is to its pair, kept in the message's view for later passes.
-- `state` is the conversation's (its queues are made with its first request or reply).
function rt.follow_exchange(state, view, name, pinfo)
    local pair = X.requests[name]
    if pair then
        state.exchanges = state.exchanges or queues()
        local request = rt.exchange_request(pinfo)
        if push(state.exchanges[pair], request) then view.request = request end
        return
    end
    pair = X.replies[name]
    if pair then
        state.exchanges = state.exchanges or queues()
        local _, request = pop(state.exchanges[pair])
        view.link = rt.exchange_reply(request, pinfo)
    end
end

-- The message's generated items: a request's reply, a reply's request and the time since.
function rt.show_exchange(item, range, view)
    rt.show_exchange_request(item, range, view.request)
    rt.show_exchange_reply(item, range, view.link)
end
