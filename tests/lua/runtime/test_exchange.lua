-- runtime/lua/common/exchange.lua: a request keeps its frame and time, the reply paired with it
-- links both ways, the time rounded to the nanosecond from the difference of two pinfo.rel_ts.
local S = dofile("stubs.lua")
S.wireshark_globals()
local spec = { exchange_fields = { response_in = "x.response_in", response_to = "x.response_to", time = "x.time" } }
local rt = S.load("common/exchange.lua", spec)

local function pinfo(number, rel_ts) return { number = number, rel_ts = rel_ts } end
local request = rt.exchange_request(pinfo(3, 86399.000000001))
S.eq(request.frame, 3, "the request's frame"); S.eq(request.response_in, nil, "no reply yet")
local link = rt.exchange_reply(request, pinfo(7, 86400.25))
S.eq(request.response_in, 7, "the request links to its reply")
S.eq(link.response_to, 3, "the reply to its request")
S.eq(tostring(link.time), "1.249999999", "a day into the capture, still to the nanosecond")
rt.exchange_reply(request, pinfo(9, 86401))
S.eq(request.response_in, 7, "a later reply (a stream of lines) leaves the first")
S.eq(rt.exchange_reply(nil, pinfo(10, 1)), nil, "a reply with no request: no link")
local back = rt.exchange_reply(rt.exchange_request(pinfo(11, 3.5)), pinfo(12, 2.0)).time
S.eq(back.secs, -1, "timestamps that go back: a negative time")
S.eq(back.nsecs, -500000000, "seconds and nanoseconds of one sign, as nstime_delta gives them")

local item, range = S.tree(), S.tvb("ab")(0, 2)
rt.show_exchange_request(item, range, rt.exchange_request(pinfo(13, 0)))
S.eq(#item.children, 0, "a request with no reply seen shows nothing")
rt.show_exchange_request(item, range, request)
rt.show_exchange_reply(item, range, link)
rt.show_exchange_reply(item, range, nil)
S.eq(#item.children, 3, "response_in; response_to and time")
S.eq(item.children[1].f, "x.response_in", "the request's field"); S.eq(item.children[1].value, 7, "its frame")
S.eq(item.children[3].f, "x.time", "the time field"); S.eq(item.children[3].generated, true, "generated")
S.eq(#rt.exchange_field_list, 3, "three fields to register")
print("ok")
