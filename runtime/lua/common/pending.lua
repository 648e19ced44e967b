-- Requests awaiting their replies, oldest first, at most `size` kept: how a reply is paired with
-- the request it answers (the RTDE setup exchange, the dashboard server's commands). A request
-- beyond is not kept but counted (`lost`), and so is every later one while a counted one is
-- ahead of it: replies come in the order of the requests, so a kept one behind a lost one would
-- take the lost one's reply.
local spec, rt = ...

local function pending_queue(size)
    return { first = 1, last = 0, lost = 0, size = size }
end

-- Keeps a request v (not nil); false when it is not kept (then counted).
local function pending_push(q, v)
    if q.lost > 0 or q.last - q.first + 1 >= q.size then
        q.lost = q.lost + 1
        return false
    end
    q.last = q.last + 1
    q[q.last] = v
    return true
end

-- The request a reply answers: true and the request, or false for one not kept, or true and nil
-- when no request awaits.
local function pending_pop(q)
    if q.first > q.last then
        if q.lost > 0 then
            q.lost = q.lost - 1
            return false, nil
        end
        return true, nil
    end
    local v = q[q.first]
    q[q.first] = nil
    q.first = q.first + 1
    return true, v
end

rt.pending_queue, rt.pending_push, rt.pending_pop = pending_queue, pending_push, pending_pop
