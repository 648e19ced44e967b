-- Request/response tracking, as Wireshark's request/response protocols show it (dns.response_in,
-- dns.response_to, dns.time). On the first pass a request keeps its frame and time; the reply the
-- dissector pairs with it links both ways: the request gets the frame of its first reply, the reply
-- the request's frame and the time between. Which reply answers which request is the dissector's
-- (in order: runtime/lua/common/pending.lua); these are only the links, kept with the first pass's
-- decisions so that later passes (tshark -2, the GUI) show a request's reply too. The fields are the
-- generated spec.exchange_fields (codegen/exchanges.py): response_in, response_to, time.
local spec, rt = ...
local F = spec.exchange_fields
local BILLION = 1000000000

-- A time difference in seconds as an NSTime, rounded to the nanosecond. The seconds are a
-- difference of pinfo.rel_ts (from the capture's first frame, a double): exact to the nanosecond for
-- captures shorter than about ten days, where Wireshark's own absolute time as a double is not.
local function ns_time(seconds)
    local total = math.floor(seconds * BILLION + 0.5)
    local whole = total >= 0 and math.floor(total / BILLION) or -math.floor(-total / BILLION)
    return NSTime.new(whole, total - whole * BILLION)
end

-- A request as this frame holds it: its frame, its time, later the frame of its reply.
local function exchange_request(pinfo)
    return { frame = pinfo.number, at = pinfo.rel_ts, response_in = nil }
end

-- A reply's link to the request it answers (nil: none, as in a capture that starts after the
-- request), and the request's link to its first reply.
local function exchange_reply(request, pinfo)
    if not request then return nil end
    if not request.response_in then request.response_in = pinfo.number end
    return { response_to = request.frame, time = ns_time(pinfo.rel_ts - request.at) }
end

-- The generated items: a request's reply, once one is seen; a reply's request and the time since.
local function show_request(item, range, request)
    if request and request.response_in then item:add(F.response_in, range, request.response_in):set_generated() end
end

local function show_reply(item, range, link)
    if not link then return end
    item:add(F.response_to, range, link.response_to):set_generated()
    item:add(F.time, range, link.time):set_generated()
end

rt.exchange_request, rt.exchange_reply = exchange_request, exchange_reply
rt.show_exchange_request, rt.show_exchange_reply = show_request, show_reply
rt.exchange_field_list = { F.response_in, F.response_to, F.time }
