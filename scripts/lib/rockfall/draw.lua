-- SPDX-License-Identifier: MIT
-- rockfall/draw.lua: everything random about one rock: its seeder, shape, size, release state and the
-- profile it meets.
local Rand = require("rockfall.random")
local Dist = require("rockfall.distributions")
local P = require("rockfall.profile")
local Shapes = require("rockfall.shapes")
local rock_seed, stream, STREAMS = Rand.rock_seed, Rand.stream, Rand.STREAMS
local draw = Dist.draw
local refine, roughen, polyline_distance, ground_at = P.refine, P.roughen, P.polyline_distance, P.ground_at
local make_rock = Shapes.make_rock

local function weighted(list, total, weight_of, r)
    local u = r:uniform() * total
    for k, item in ipairs(list) do
        u = u - weight_of(item)
        if u < 0 then return item, k end
    end
    return list[#list], #list
end

--- The profile rock i meets: the nominal one, or roughened with the rock's (or the analysis')
--- roughness stream.
local function rock_profile(an, seed)
    if not an.roughness or an.roughness.amplitude == 0 then return an.nominal, an.segment_material end
    local pts, mats = an.nominal, an.segment_material
    if an.roughness.spacing then
        local out, om = { { pts[1][1], pts[1][2] } }, {}
        for k = 1, #pts - 1 do
            local piece = refine({ pts[k], pts[k + 1] }, an.roughness.spacing)
            for j = 2, #piece do
                out[#out + 1] = piece[j]
                om[#om + 1] = mats[k]
            end
        end
        pts, mats = out, om
    end
    local s = an.roughness.per_rock and seed or rock_seed(an.seed, 0)
    return roughen(pts, an.roughness.amplitude, stream(s, "roughness"):next()), mats
end

--- Everything random about rock i: its seed, seeder, shape, size, release state and profile.
local function sample(an, i)
    local seed = rock_seed(an.seed, i)
    local rs = {}
    for name in pairs(STREAMS) do rs[name] = stream(seed, name) end
    local sd = weighted(an.seeders, an.seeder_weight, function(s) return s.weight end, rs.seeder)
    local spec = weighted(sd.rocks, sd.rock_weight, function(s) return s.weight or 1 end, rs.shape)
    local rock = make_rock(spec, rs)
    local u = rs.position:uniform()
    local x = sd.from[1] + u * (sd.to[1] - sd.from[1])
    local y = sd.from[2] + u * (sd.to[2] - sd.from[2])
    local pts, mats = rock_profile(an, seed)
    -- A rock seeded into or below the slope is lifted until it clears it (RocFall moves it to
    -- the surface): distance to the polyline >= bounding radius + clearance.
    local lifted = false
    for _ = 1, 100 do
        local d = polyline_distance(pts, x, y)
        local below = y < ground_at(pts, x)
        if not below and d >= rock.bound + an.clearance * 0.999 then break end
        lifted = true
        if below then y = ground_at(pts, x) + rock.bound + an.clearance
        else y = y + (rock.bound + an.clearance - d) + 1e-6 end
    end
    return {
        seed = seed, seeder = sd.name, rock = rock, points = pts, materials = mats, lifted = lifted,
        release = { x = x, y = y, vx = draw(sd.vx, rs.vx), vy = draw(sd.vy, rs.vy),
            spin = draw(sd.spin, rs.spin) },
    }
end

return { rock_profile = rock_profile, sample = sample }
