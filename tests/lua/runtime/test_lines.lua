-- runtime/lua/lines/match.lua and runtime/lua/lines/dissect.lua: commands and replies looked up, a
-- conversation's replies paired with its commands, the version learnt, lines reassembled.
local S = dofile("stubs.lua")
S.wireshark_globals()

local spec = {
    name = "ur_dashboard", title = "Dashboard", ports = {29999}, max_line = 32, pending_kept = 4,
    e_series_from = 5000000, polyscope_x_from = 10000000, version_command = 2, version_prefix = "URSoftware ",
    banner = {name = "connected", pieces = {"Connected"}, error = false},
    robot_is_client = false, requests_from_robot = false, one_reply_per_request = true,
    common = {{name = "not_understood", pieces = {"could not understand: '", "'"}, error = true}},
    commands = {
        {name = "load", text = "load", argument = true, since_cb = 1004000, since_e_series = 5000000,
         replies = {{name = "loading", pieces = {"Loading: ", ""}, error = false},
                    {name = "not_found", pieces = {"File not found: ", ""}, error = true}}},
        {name = "polyscope_version", text = "PolyscopeVersion", argument = false, since_cb = 1008000,
         since_e_series = 5000000, replies = {{name = "version", pieces = {"URSoftware ", ""}, error = false}}},
        {name = "safetystatus", text = "safetystatus", argument = false, since_e_series = 5004000,
         since_polyscope_x = 10013000,
         replies = {{name = "status", pieces = {"Safetystatus: ", ""}, error = false}}},
    },
    lookup = {2, 3, 1},
    labels = {command = "Command", command_name = "Command name", argument = "Argument", available = "Available",
              reply = "Reply", reply_name = "Reply meaning", error = "Says an error"},
    not_kept = "command not kept", reply_not_kept = "reply to a command not kept",
    exchange_fields = {response_in = "ur_dashboard.response_in", response_to = "ur_dashboard.response_to",
                       time = "ur_dashboard.time"},
}
local rt = S.load("common/dotted_version.lua", spec)
S.load("lines/match.lua", spec, rt)
S.eq(rt.find_command("load /a.urp"), 1, "a command with its argument")
S.eq(select(2, rt.find_command("load /a.urp")), "/a.urp", "the argument")
S.eq(rt.find_command("loadx"), nil, "a text that only opens like a command")
-- Interpreter mode's shape: a command with no text is any other line, tried last, the whole its argument.
local statements = {commands = {{name = "statement", text = "", argument = true, replies = {}},
                                {name = "abort", text = "abort", argument = false, replies = {}}},
                    lookup = {2, 1}, common = {}}
local any = S.load("common/dotted_version.lua", statements)
S.load("lines/match.lua", statements, any)
S.eq(any.find_command("abort"), 2, "a command's text before any other line")
S.eq(any.find_command("abort()"), 1, "any other line")
S.eq(select(2, any.find_command("abort()")), "abort()", "the whole line its argument")
S.eq(rt.classify(1, "File not found: x").name, "not_found", "a command's reply")
S.eq(rt.classify(nil, "could not understand: 'x'").error, true, "a common reply, with no command")
S.eq(rt.version_in("URSoftware 3.15.7.1 (x)"), 3015007, "the version a reply tells")
S.eq(rt.parse_version(" 5.11.1 "), 5011001, "the version preference")
S.eq(rt.parse_version("3.1234.5"), 3999005, "a minor past 999 stands at 999")
S.eq(rt.parse_version("5.11 beta"), nil, "not a version preference")
S.eq(rt.available(3, 3015007), false, "an e-Series command on a CB3")
S.eq(rt.available(3, 5004000), true, "from its first version")
S.eq(rt.available(3, 10012000), false, "PolyScope X reads its own column")
S.eq(rt.available(3, 10013000), true, "from its first PolyScope X version")

local made
local make_proto = Proto
Proto = function(...) made = make_proto(...); return made end
S.load("common/register.lua", spec, rt)
S.load("common/guard.lua", spec, rt)
S.load("common/tcp_stream.lua", spec, rt)
S.load("common/pending.lua", spec, rt)
S.load("common/exchange.lua", spec, rt)
S.load("lines/dissect.lua", spec, rt)
S.eq(S.ports["tcp.port"], "29999", "the port registered")

-- A conversation: the client's lines go to port 29999, the replies come from it.
-- Frame n is n milliseconds into the capture.
local function pinfo(number, from_robot, visited)
    return {number = number, visited = visited or false, rel_ts = number / 1000, src_port = from_robot and 29999 or 50123,
            dst_port = from_robot and 50123 or 29999, match_uint = 29999, can_desegment = 2,
            src = from_robot and "robot" or "pc", dst = from_robot and "pc" or "robot",
            cols = {info = S.column(), protocol = S.column()}}
end
local function dissect(number, from_robot, raw, visited)
    local tree, p = S.tree(), pinfo(number, from_robot, visited)
    made.dissector(S.tvb(raw), p, tree)
    local dump = S.dump(tree)
    assert(not dump:find("internal_error", 1, true), dump)
    return dump, p
end

local out = dissect(1, true, "Connected\n")
assert(out:find("ur_dashboard.reply_name @0+9 = connected", 1, true), out)
out = dissect(2, false, "PolyscopeVersion\nsafetystatus\nload a\nfoo\n")
assert(out:find("ur_dashboard.command_name @30+6 = load", 1, true), out)
assert(out:find("ur_dashboard.argument @30+6 = a", 1, true), out)
assert(out:find("!ur_dashboard.unknown_command", 1, true), out)
out = dissect(3, true, "URSoftware 3.15.7.1 (x)\nSafetystatus: NORMAL\nFile not found: a\ncould not understand: 'foo'\n")
assert(out:find("ur_dashboard.command_name @0+23 = polyscope_version", 1, true), out)
assert(out:find("ur_dashboard.reply_name @45+17 = not_found", 1, true), out)
assert(out:find("!ur_dashboard.error_reply", 1, true), out)
out = dissect(4, false, "safetystatus\n")
assert(out:find("ur_dashboard.available @0+12 = false", 1, true), out)
assert(out:find("!ur_dashboard.unavailable", 1, true), out)

-- A line cut by the segment asks for one more; one too long is flagged and skipped.
local _, p = dissect(5, false, "lo")
S.eq(p.desegment_offset, 0, "a line not whole yet waits")
S.eq(p.desegment_len, DESEGMENT_ONE_MORE_SEGMENT, "for one more segment")
out = dissect(6, false, string.rep("x", 40))
assert(out:find("!ur_dashboard.too_long", 1, true), out)
out = dissect(7, false, "xx\nload b\n")
assert(out:find("Rest of a line too long", 1, true), out)
assert(out:find("ur_dashboard.command_name @3+6 = load", 1, true), out)

-- Pairing in a new TCP conversation: pending_kept (4) commands await replies; the fifth is not
-- kept, nor the sixth behind it, and their replies are paired with no command.
local function count(text, what)
    local n = 0
    for _ in text:gmatch(what) do n = n + 1 end
    return n
end
S.fields["tcp.stream"] = { value = 1 }
dissect(8, true, "Connected\n")
out = dissect(9, false, "load a\nload b\nload c\nload d\nload e\n")
S.eq(count(out, "!ur_dashboard%.not_kept: command not kept"), 1, "the fifth command is not kept")
out = dissect(10, false, "load f\n")
S.eq(count(out, "!ur_dashboard%.not_kept"), 1, "nor one behind it")
out = dissect(11, true, "Loading: a\nLoading: b\nLoading: c\nLoading: d\nLoading: e\nLoading: f\n")
S.eq(count(out, "command_name @%d+%+%d+ = load"), 4, "four replies paired with their commands")
S.eq(count(out, "!ur_dashboard%.reply_not_kept: reply to a command not kept"), 2, "two paired with none")
S.eq(count(out, "ur_dashboard%.response_to @%d+%+%d+ = 9\n"), 4, "each linked with its command's frame")
S.eq(count(out, "ur_dashboard%.time @%d+%+%d+ = 0%.002000000"), 4, "and the time since it")
S.eq(count(out, "response_to"), 4, "a reply to a command not kept links to none")
out = dissect(9, false, "load a\nload b\nload c\nload d\nload e\n", true)
S.eq(count(out, "ur_dashboard%.response_in @%d+%+%d+ = 11"), 4, "a later pass: each kept command links to its reply")
S.eq(count(out, "response_in"), 4, "the one not kept to none")
out = dissect(12, false, "load g\n")
S.eq(count(out, "not_kept"), 0, "every lost one answered: kept again")
out = dissect(13, true, "Loading: g\n")
S.eq(count(out, "command_name @0%+10 = load"), 1, "and paired")

-- The script sender's rule: only the latest request counts, every reply belongs to it.
spec.one_reply_per_request = false
S.fields["tcp.stream"] = { value = 2 }
dissect(14, true, "Connected\n")
out = dissect(15, true, "Loading: x\n")
S.eq(count(out, "command_name"), 0, "no request yet: paired with none")
S.eq(count(out, "not_kept"), 0, "and none lost")
dissect(16, false, "load a\nPolyscopeVersion\n")
out = dissect(17, true, "URSoftware 5.11\nURSoftware 5.12\n")
S.eq(count(out, "command_name @%d+%+%d+ = polyscope_version"), 2, "both replies to the latest request")
S.eq(count(out, "response_to @%d+%+%d+ = 16"), 2, "both linked with its frame")
out = dissect(16, false, "load a\nPolyscopeVersion\n", true)
S.eq(count(out, "response_in @%d+%+%d+ = 17"), 1, "the latest request links to its first answering line")
print("ok")
