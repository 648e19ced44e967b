-- Loaded into the Wireshark GUI beside the dissector (tests/tools/gui.py): counts, as the GUI
-- reads the capture, every frame, the frames its display filter shows, and the frames with a
-- Lua error or a dissector fault, and writes the counts to URWIRE_PROBE_OUT after each one.
-- The listeners are made in init, once the dissector's fields exist.
local out = os.getenv("URWIRE_PROBE_OUT")
local filter = os.getenv("URWIRE_PROBE_FILTER")
local FAULTS = "_ws.lua.error || ur.internal_error || _ws.malformed"

local probe = Proto("urwire_probe", "urwire GUI probe")
local counts = { frames = 0, shown = 0, faults = 0 }
local made = false

local function save()
    local f = io.open(out, "w")
    f:write(string.format("frames=%d shown=%d faults=%d\n", counts.frames, counts.shown, counts.faults))
    f:close()
end

local function counter(key)
    return function()
        counts[key] = counts[key] + 1
        save()
    end
end

function probe.init()
    counts.frames, counts.shown, counts.faults = 0, 0, 0
    if made then return end
    made = true
    Listener.new("frame").packet = counter("frames")
    Listener.new("frame", filter).packet = counter("shown")
    Listener.new("frame", FAULTS).packet = counter("faults")
end
