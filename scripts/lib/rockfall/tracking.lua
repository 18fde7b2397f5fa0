-- SPDX-License-Identifier: MIT
-- rockfall/tracking.lua: the engine tracks a rock (m:track) at every step; Lua acts only at events (a
-- barrier crossing, the rock's end) and fills the record from the tracker's lists at the end.
local P = require("rockfall.profile")
local ground_at = P.ground_at

-- The engine tracks a rock (m:track, docs/lua-api.md "Trackers") at every step, in C++: its
-- touches of the slope (impacts), its crossings of the collector and barrier lines, its
-- envelope, its path and its end rules (left, rest, time); the engine's barriers (m:barrier)
-- slow or stop it. Lua acts only at events -- a barrier crossing, the rock's end -- to record
-- them, and fills the record from the tracker's lists at the end; it never looks at the rock
-- and its contacts each step. run_rock tracks its one rock, mass_release
-- every rock of its model, both with these functions.

--- The collector and barrier lines in +x order.
local function rock_lines(an)
    local lines = {}
    for _, c in ipairs(an.collectors) do lines[#lines + 1] = { kind = "collector", name = c.name, x = c.x } end
    for _, b in ipairs(an.barriers) do
        lines[#lines + 1] = { kind = "barrier", name = b.name, x = b.x, energy = b.energy, height = b.height }
    end
    table.sort(lines, function(a, b) return a.x < b.x end)
    return lines
end

--- Whether a rock is fixed (a barrier stopped it; rocks are not fixed otherwise).
local function fixed(body)
    local f = body.fix
    return f == true or (type(f) == "table" and #f > 0)
end

--- The analysis' barriers as engine barriers (m:barrier; docs/rockfall.md, "Barriers"): each a
--- vertical segment from the ground under its x up to its height. The engine catches a rock whose
--- centre crosses the line with its equivalent disk on the segment -- its bottom (centre less
--- r_eq) below the barrier's height, the rule this module's records use -- at every step, in
--- C++, and books what it takes as the energy item `barrier`, so the balance check stays on.
local function add_barriers(m, an, pts)
    for _, b in ipairs(an.barriers) do
        local g = ground_at(pts, b.x)
        m:barrier{ name = b.name, from = { b.x, g }, to = { b.x, g + b.height }, energy = b.energy }
    end
end

--- Starts the engine's tracker of rock i (body `body`, draw `s`) and returns its Lua side:
--- the record it fills and what the events need. `ended(rt)`, if given, is called once when it
--- ends.
local function track_rock(m, an, i, s, body, lines, opts, ended)
    local rk, pts = s.rock, s.points
    local rt = {
        body = body, mass = body.mass, inertia = body.inertia, r_eq = rk.r_eq, pts = pts,
        crossed = {}, done = false,
        record = {
            rock = i, seed = s.seed, seeder = s.seeder, shape = rk.shape, mass = body.mass,
            volume = rk.volume, r_eq = rk.r_eq, density = rk.density, scale = rk.scale,
            angle = rk.angle, lifted = s.lifted or nil,
            release = { x = s.release.x, y = s.release.y, vx = s.release.vx, vy = s.release.vy,
                spin = s.release.spin },
            crossings = {}, barrier = {}, impacts = {}, env_height = {}, env_ke = {},
            path = opts.trajectory and {} or nil,
        },
    }
    local ke_rest = an.rest_ke
    if not ke_rest then
        -- Speed v for the centroid and v / r_eq at the rim: 1/2 m v^2 + 1/2 I (v / r_eq)^2.
        local v = an.rest_speed
        ke_rest = 0.5 * body.mass * v * v + 0.5 * body.inertia * (v / rk.r_eq) ^ 2
    end
    -- Vertical lines reaching far beyond the profile (a rock below it has left; one 10 km
    -- above it does not exist), crossed toward +x: from below to above.
    local y_lo, y_hi = math.huge, -math.huge
    for _, p in ipairs(pts) do y_lo, y_hi = math.min(y_lo, p[2]), math.max(y_hi, p[2]) end
    local tl = {}
    for k, line in ipairs(lines) do
        tl[k] = { from = { line.x, y_lo - 1e4 }, to = { line.x, y_hi + 1e4 }, event = line.kind == "barrier" }
    end
    local env = an.envelope
    local function finish(stop, time, x, y)
        if rt.done then return end
        rt.done = true
        local r = rt.record
        r.stop, r.t_end, r.end_x, r.end_y = stop, time, x, y
        if ended then ended(rt) end
    end
    rt.finish = finish
    local function on_event(tr, ev)
        if rt.done then return end
        if ev.kind == "end" then
            local st = tr:status()
            local stop = ({ exit = "left", rest = "rest", time = "time" })[ev.state] or ev.state
            finish(stop, st.t, st.pos[1], st.pos[2])
            return
        end
        -- A barrier line, crossed for the first time: the capacity rule (docs/rockfall.md).
        if rt.crossed[ev.line] then return end
        rt.crossed[ev.line] = true
        local line, c, r = lines[ev.line], ev.crossing, rt.record
        local ux, uy, yc, tc = c.vel[1], c.vel[2], c.pos[2], c.t
        local kt, kr = c.ke_trans, c.ke_rot
        local ke = kt + kr
        local hit = {
            name = line.name, t = tc, x = line.x, y = yc, height = yc - ground_at(pts, line.x) - rk.r_eq,
            energy = ke, angle = math.deg(math.atan(-uy, ux)), ke_trans = kt, ke_rot = kr,
        }
        r.barrier[#r.barrier + 1] = hit
        -- The engine's barrier (add_barriers) has acted in this step, before this event: it
        -- took E_cap from a faster rock (velocity and spin scaled by sqrt((ke - E_cap) / ke)) or
        -- stopped and fixed a slower one, and booked what it took as the energy item `barrier`.
        if hit.height >= line.height then
            hit.stopped, hit.over = false, true -- flies over: recorded as passed, energy unchanged
        elseif not fixed(body) then
            hit.stopped, hit.energy_after = false, ke - line.energy
            r.barrier_absorbed = (r.barrier_absorbed or 0) + line.energy
        else
            hit.stopped = true
            tr:stop()
            finish("barrier", tc, line.x, yc)
        end
    end
    rt.tracker = m:track(body, {
        impacts = { with = "walls", min_speed = an.impact_min_vn },
        lines = tl,
        rest = { energy = ke_rest, time = an.rest_time },
        region = { lo = { pts[1][1], an.y_min - 2 * rk.r_eq - 1 }, hi = { pts[#pts][1], math.huge } },
        end_time = an.t_max,
        envelope = { ground = pts, x0 = env.x0, dx = env.dx, bins = env.nbins },
        path = opts.trajectory and an.path_every or nil,
        on_event = on_event,
    })
    return rt
end

--- A rock whose tracker ended at its first sample (when it was made: no event then) ends here.
local function ended_at_start(rt)
    local st = rt.tracker:status()
    if st.state ~= "tracking" then
        local stop = ({ exit = "left", rest = "rest", time = "time" })[st.state] or st.state
        rt.finish(stop, st.t, st.pos[1], st.pos[2])
    end
end

--- Fills rock rt's record from its tracker's records (after the run).
local function collect_rock(rt, lines, wall_material)
    local tr, r = rt.tracker, rt.record
    local first = {}
    for _, c in ipairs(tr:crossings()) do
        local line = lines[c.line]
        if line.kind == "collector" and not first[c.line] then
            first[c.line] = true
            local ux, uy = c.vel[1], c.vel[2]
            r.crossings[#r.crossings + 1] = {
                line = line.name, t = c.t, x = line.x, y = c.pos[2],
                height = c.pos[2] - ground_at(rt.pts, line.x) - rt.r_eq, vx = ux, vy = uy,
                v = math.sqrt(ux * ux + uy * uy), spin = c.spin, ke_trans = c.ke_trans,
                ke_rot = c.ke_rot, ke = c.ke_trans + c.ke_rot,
            }
        end
    end
    local function ke(v, w)
        return 0.5 * rt.mass * (v[1] * v[1] + v[2] * v[2]) + 0.5 * rt.inertia * w * w
    end
    for _, im in ipairs(tr:impacts()) do
        local nx, ny = im.normal[1], im.normal[2]
        local vx, vy = im.vel[1], im.vel[2]
        local rec = { t = im.t, x = im.pos[1], y = im.pos[2], vn_in = vx * nx + vy * ny,
            vt_in = vx * ny - vy * nx, material = wall_material[im.wall.id] }
        if im.t_end then
            -- Closed at the first sample without a touch, or at the rock's last sample (then
            -- it lasted until the rock ended: at a barrier, the crossing's time).
            local ox, oy = im.vel_end[1], im.vel_end[2]
            local vn, vt = ox * nx + oy * ny, ox * ny - oy * nx
            rec.vn_out, rec.vt_out = vn, vt
            rec.rn = rec.vn_in ~= 0 and math.abs(vn / rec.vn_in) or 0
            rec.rt = rec.vt_in ~= 0 and vt / rec.vt_in or 0
            rec.energy_lost = ke(im.vel, im.spin) - ke(im.vel_end, im.spin_end)
            rec.duration = (im.ended and im.t_end or r.t_end) - im.t
            if not im.ended then rec.ended = false end
        end
        r.impacts[#r.impacts + 1] = rec
    end
    local env = tr:envelope()
    for k, h in pairs(env.height) do r.env_height[k] = h - rt.r_eq end
    for k, e in pairs(env.energy) do r.env_ke[k] = e end
    if r.path then
        for _, p in ipairs(tr:path()) do r.path[#r.path + 1] = p end
        r.path[#r.path + 1] = { r.t_end, r.end_x, r.end_y }
    end
end

return { rock_lines = rock_lines, add_barriers = add_barriers, track_rock = track_rock, ended_at_start = ended_at_start, collect_rock = collect_rock }
