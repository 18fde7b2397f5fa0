-- SPDX-License-Identifier: MIT
-- material/equilibrium.lua: a model set up for quasi-static work, and relaxation to PFC's
-- unbalanced-force ratio (mean unbalanced force over balls / mean contact force, m:unbalanced).
local E = {}

--- A model for quasi-static work: the stability rule alone sets the step (the resolution rule
--- is for impacts, docs/models/cbond.md "Time-step contract"), PFC local damping (Potyondy &
--- Cundall 2004: 0.7) and the impact guards off (no impacts are resolved here). The engine's
--- warnings are printed: a routine that overlaps bodies on purpose switches that warning off
--- itself (m:placement_warning(false)) and says so.
function E.new_model(damp)
    local m = talus.model{}
    m:timestep{ resolution = 0 }
    m:damping{ damp = damp or 0.7 }
    m:guard{ energy = "off", resolution = "off" }
    return m
end

function E.unbalanced_ratio(m) return m:unbalanced().ratio end

--- Cycles until the ratio is below `ratio` (or max_steps). Returns steps taken, final ratio.
--- Without `chunk`: m:solve{ratio}, judged after every step. With `chunk` the ratio is judged
--- every `chunk` steps (m:cycle, then m:unbalanced()): the per-step pass over balls and pairs
--- is ~25% of a genesis step at 5000 balls (docs/lua-api.md), and a relaxation may overrun by
--- < chunk steps.
function E.solve_ratio(m, ratio, max_steps, chunk)
    local s0 = m:step()
    if not chunk then
        m:solve{ ratio = ratio, max_steps = max_steps }
        return m:step() - s0, m:unbalanced().ratio
    end
    local r = math.huge
    while m:step() - s0 < max_steps do
        m:cycle(math.min(chunk, max_steps - (m:step() - s0)))
        local u = m:unbalanced()
        r = u.ratio
        -- no contact carries a force (early expansion: the balls drift apart): nothing to
        -- settle, and the ratio is undefined (math.huge)
        if u.contacts == 0 then break end
        if r <= ratio then break end
    end
    return m:step() - s0, r
end

return E
