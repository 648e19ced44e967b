-- What the dissector adds around the spec's layouts: its own fields (raw and extra bytes, the
-- software version a message was read with, URScript text) and its expert infos. Registers
-- them, after every field of the spec, with the protocol. Runs once, at load time.
local spec, rt = ...
local ur = spec.proto

local X = {
    raw = ProtoField.bytes("ur.raw", "Raw", base.NONE,
        "Bytes kept whole: a type the spec does not lay out, or a part that could not be read."),
    extra = ProtoField.bytes("ur.extra", "Extra bytes", base.NONE,
        "Bytes after the known layout of a package or message."),
    skipped = ProtoField.bytes("ur.skipped", "Skipped bytes", base.NONE,
        "Bytes skipped while looking for the next plausible message header."),
    version = ProtoField.string("ur.software_version", "Software version", base.ASCII,
        "The software version this message is read with (its layouts, enum names and value types): \z
        the stream's Version message, else the ur.version preference, else what the layout sizes \z
        show (\"3.2 to 3.4 (from layout sizes)\"), else the default."),
    assumed = ProtoField.bool("ur.version_assumed", "Version assumed", base.NONE, nil, nil,
        "True when no Version message was seen on this stream: the version comes from the \z
        ur.version preference, the layout sizes or the default."),
    unknown_package = ProtoField.none("ur.unknown_package", "Unknown package",
        "A sub-package type the spec does not lay out, kept raw."),
    urscript = ProtoField.string("ur.urscript", "URScript", base.UNICODE,
        "Bytes from the client to the robot: URScript program text."),
}

local E = {
    bad_length = ProtoExpert.new("ur.bad_length", "Message length out of range (resynchronising)",
        expert.group.MALFORMED, expert.severity.ERROR),
    bad_type = ProtoExpert.new("ur.bad_type", "Unknown message type (resynchronising)",
        expert.group.MALFORMED, expert.severity.ERROR),
    malformed = ProtoExpert.new("ur.malformed", "Package or message too short or malformed",
        expert.group.MALFORMED, expert.severity.ERROR),
    extra = ProtoExpert.new("ur.extra_bytes", "Bytes after the known layout",
        expert.group.PROTOCOL, expert.severity.WARN),
    unknown = ProtoExpert.new("ur.unknown", "Type not laid out by the spec, kept raw",
        expert.group.UNDECODED, expert.severity.NOTE),
    assumed = ProtoExpert.new("ur.assumed_version", "Software version assumed (no Version message seen)",
        expert.group.ASSUMPTION, expert.severity.NOTE),
    version_range = ProtoExpert.new("ur.version_out_of_range",
        "Version message number out of range: set aside, the stream is read as major.minor",
        expert.group.PROTOCOL, expert.severity.WARN),
    by_length = ProtoExpert.new("ur.layout_by_length", "Layout chosen by its length, not by the software version",
        expert.group.ASSUMPTION, expert.severity.NOTE),
    items_hidden = ProtoExpert.new("ur.items_hidden", "More tree items than a message shows",
        expert.group.UNDECODED, expert.severity.NOTE),
    internal = ProtoExpert.new("ur.internal_error", "urwire dissector error",
        expert.group.MALFORMED, expert.severity.ERROR),
}

-- The spec's fields in the order they are declared, then the dissector's own.
local fields = {}
for i, f in ipairs(spec.fields) do fields[i] = f end
for _, f in ipairs({ X.raw, X.extra, X.skipped, X.version, X.assumed, X.unknown_package, X.urscript }) do
    fields[#fields + 1] = f
end
ur.fields = fields
ur.experts = { E.bad_length, E.bad_type, E.malformed, E.extra, E.unknown, E.assumed, E.version_range, E.by_length,
               E.items_hidden, E.internal }

rt.X, rt.E = X, E
