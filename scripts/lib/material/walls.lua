-- SPDX-License-Identifier: MIT
-- material/walls.lua: straight walls as records {wall, n (inward unit normal), ...}, their
-- position and load along the normal, and the engine's servo (w:servo) on a set of them.
local W = {}

--- A straight wall through `a`-`b` whose inward normal is `n`; the record keeps what the servo
--- and the measurements need.
function W.make(m, a, b, n, group, props)
    local o = { points = { a, b }, group = group }
    for k, v in pairs(props or {}) do o[k] = v end
    local w = m:wall(o)
    return { wall = w, n = n }
end

--- Position of a wall along its inward normal (signed distance of its line from the origin).
--- A curved jaw (Brazilian test) is a chain whose first vertex is not its apex: rec.apex is the
--- apex's offset from that vertex along n (constant, the jaw translates rigidly), so the
--- position is the apex's.
function W.pos(rec)
    local p = rec.wall.points[1]
    return p[1] * rec.n[1] + p[2] * rec.n[2] + (rec.apex or 0)
end

--- Compressive force on a wall: the balls push it against its inward normal.
function W.push(rec)
    local f = rec.wall.force
    return -(f[1] * rec.n[1] + f[2] * rec.n[2])
end

--- PFC's wall servo (w:servo, docs/lua-api.md) on every record of `recs` that has a `target`
--- stress, over its loaded length rec.len(); opts = {alpha (0.5), vmax}. Returns {update =
--- re-arm with the lengths now, stop = servo off and the walls at rest}.
function W.servo(recs, opts)
    local function arm()
        for _, rec in ipairs(recs) do
            if rec.target then
                rec.wall:servo{ stress = rec.target, length = rec.len(), alpha = opts.alpha or 0.5,
                                vmax = opts.vmax, on = true }
            end
        end
    end
    arm()
    return {
        stop = function()
            for _, rec in ipairs(recs) do
                if rec.target then rec.wall:servo{ on = false } end
                rec.wall.vel = { 0, 0 }
            end
        end,
        update = arm,
    }
end

return W
