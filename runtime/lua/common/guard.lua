-- The error guard every dissector runs behind: a Lua error while dissecting never reaches the
-- user as a Lua error, but shows as an expert info on the packet, and the packet's bytes count
-- as dissected.
local spec, rt = ...

-- A dissector function for proto that runs dissect(tvb, pinfo, tree) behind pcall; an error
-- becomes the expert `internal`, its text after `label` ("urwire: ...").
local function guard(proto, dissect, internal, label)
    return function(tvb, pinfo, tree)
        local ok, result = pcall(dissect, tvb, pinfo, tree)
        if ok then return result end
        tree:add(proto, tvb()):add_proto_expert_info(internal, label .. ": " .. tostring(result))
        return tvb:len()
    end
end

rt.guard = guard
