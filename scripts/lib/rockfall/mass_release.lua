-- SPDX-License-Identifier: MIT
-- rockfall/mass_release.lua: rocks released together into one model, with rock-rock contact.
local Draw = require("rockfall.draw")
local Model = require("rockfall.model")
local Tr = require("rockfall.tracking")
local K = require("rockfall.check")
local fail, check_keys, need_analysis, check_hook = K.fail, K.check_keys, K.need_analysis, K.check_hook
local sample, rock_profile = Draw.sample, Draw.rock_profile
local new_model, build_slope, place_rock = Model.new_model, Model.build_slope, Model.place_rock
local rock_lines, track_rock = Tr.rock_lines, Tr.track_rock
local ended_at_start, collect_rock = Tr.ended_at_start, Tr.collect_rock

--- Releases n rocks at once into one model (rock-rock contact with analysis.rock_contact);
--- returns one record per rock, as run_rock does. All rocks meet the nominal (or the analysis'
--- single roughened) profile: roughness per rock has no meaning in one model.
local function mass_release(an, opts)
    need_analysis(an)
    opts = opts or {}
    check_keys(opts, { "n", "trajectory", "chunk", "on_model", "on_end" }, "mass_release options")
    check_hook(opts, "on_model", "mass_release options")
    check_hook(opts, "on_end", "mass_release options")
    local n = opts.n or an.n
    if math.type(n) ~= "integer" or n < 1 then fail("mass_release: n must be an integer >= 1 (got %s)", tostring(n)) end
    local samples, rsum = {}, 0
    local pts, mats = an.nominal, an.segment_material
    if an.roughness and an.roughness.amplitude > 0 then
        pts, mats = rock_profile({ nominal = an.nominal, segment_material = an.segment_material,
            roughness = { amplitude = an.roughness.amplitude, spacing = an.roughness.spacing,
                per_rock = false }, seed = an.seed }, 0)
    end
    for i = 1, n do
        local si = sample(an, i)
        si.points, si.materials = pts, mats
        rsum = rsum + si.rock.r_eq
        -- Rocks drawn onto each other would start with huge overlaps: a rock whose bounding
        -- circle meets an earlier one's is lifted above it (deterministic: rocks in index order).
        local moved = true
        while moved do
            moved = false
            for j = 1, i - 1 do
                local sj = samples[j]
                local dx, dy = si.release.x - sj.release.x, si.release.y - sj.release.y
                local need = si.rock.bound + sj.rock.bound + an.clearance
                if dx * dx + dy * dy < need * need then
                    si.release.y = sj.release.y + math.sqrt(need * need - dx * dx) + 1e-6
                    si.lifted, moved = true, true
                end
            end
        end
        samples[i] = si
    end
    -- A tenth of the mean rock size. Here some rock always touches something, so contacts set
    -- the step and a wide margin (run_rock's, which lengthens a lone rock's steps in flight)
    -- buys nothing: it only makes candidate pairs of rocks near each other, and at 100 rocks
    -- those cost five times the contacts (docs/rockfall.md, "Mass release").
    local warnings = {}
    local m = new_model(an, an.margin or 0.1 * rsum / n, warnings)
    local wall_material = build_slope(m, an, pts, mats)
    Tr.add_barriers(m, an, pts)
    local lines = rock_lines(an)
    local left = n
    local function ended(rt)
        left = left - 1
        -- A rock that left, or that a barrier stopped, leaves the model (after the first
        -- sample: once every rock is placed).
        if rt.placed and rt.record.stop ~= "rest" then rt.body:delete() end
    end
    local rocks = {}
    for i = 1, n do
        local body = place_rock(m, samples[i])
        rocks[i] = track_rock(m, an, i, samples[i], body, lines, opts, ended)
    end
    m:energy{ on = true }
    for _, rt in ipairs(rocks) do
        rt.placed = true
        ended_at_start(rt)
    end
    if opts.on_model then
        local bodies = {}
        for i, rt in ipairs(rocks) do bodies[i] = rt.body end
        opts.on_model(m, { rocks = n, bodies = bodies, mass_release = true })
    end
    local chunk = opts.chunk or 50
    while left > 0 do m:cycle(chunk) end
    local recs = {}
    for i, rt in ipairs(rocks) do
        collect_rock(rt, lines, wall_material)
        rt.record.mass_release = true
        recs[i] = rt.record
    end
    if #warnings > 0 then recs.warnings = warnings end
    if opts.on_end then opts.on_end(m, recs) end
    return recs
end

return { mass_release = mass_release }
