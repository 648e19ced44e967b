-- runtime/lua/common/pending.lua: requests awaiting replies, paired in order, the ones beyond the
-- limit counted, and every one behind a counted one counted too.
local S = dofile("stubs.lua")
local rt = S.load("common/pending.lua")
local push, pop = rt.pending_push, rt.pending_pop


local q = rt.pending_queue(2)
S.eq(select("#", pop(q)), 2, "two answers"); S.eq((pop(q)), true, "a reply to nothing: paired with nothing")
S.eq(select(2, pop(q)), nil, "and no request")
S.eq(push(q, "a"), true, "the first kept"); S.eq(push(q, false), true, "a request kept as false")
S.eq(push(q, "c"), false, "past the limit: counted")
local paired, v = pop(q)
S.eq(paired, true, "the first reply"); S.eq(v, "a", "to the oldest request")
S.eq(push(q, "d"), false, "room again, but a counted request is ahead: counted too")
paired, v = pop(q)
S.eq(paired, true, "the second reply"); S.eq(v, false, "to the request kept as false")
paired, v = pop(q)
S.eq(paired, false, "the third reply: to a counted request"); S.eq(v, nil, "none to give")
paired = pop(q)
S.eq(paired, false, "the fourth: to the other counted one")
paired, v = pop(q)
S.eq(paired, true, "then nothing awaits"); S.eq(v, nil, "and nothing is given")
S.eq(push(q, "e"), true, "kept again once the counted ones are answered")
S.eq(select(2, pop(q)), "e", "and paired")
S.eq(q[1], nil, "answered requests are let go")
print("ok")
