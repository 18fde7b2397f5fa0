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

--- The engine's servo (m:servo, docs/lua-api.md "Servos") on every record of `recs` that has a
--- `target` stress, one servo per wall (PFC's gain on the wall's own contacts): the stress over
--- the gap between the two walls of rec.span (measured by the engine every step), or over
--- rec.len() when the record has no span; opts = {alpha (0.5), vmax}. Set once; returns {stop =
--- the servos removed, the walls at rest}.
function W.servo(m, recs, opts)
    local servos = {}
    for _, rec in ipairs(recs) do
        if rec.target then
            servos[#servos + 1] = m:servo{ walls = { rec.wall }, dirs = { rec.n }, stress = rec.target,
                                           span = rec.span, length = (not rec.span) and rec.len() or nil,
                                           alpha = opts.alpha or 0.5, vmax = opts.vmax }
        end
    end
    return {
        stop = function()
            for _, sv in ipairs(servos) do sv:remove() end
            for _, rec in ipairs(recs) do rec.wall.vel = { 0, 0 } end
        end,
    }
end

return W
