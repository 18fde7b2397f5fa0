-- SPDX-License-Identifier: MIT
-- rockfall/model.lua: a rock's model: the engine model, the slope's walls by material, the rock body.

--- A rock's model; the engine's warnings (from the first call on) go into `warnings`, which
--- the record carries, instead of one line on stderr per rock. The analysis' timestep settings,
--- else `timestep` (nil: the engine's).
local function new_model(an, margin, warnings, timestep)
    local m = talus.model{ gravity = an.gravity, mass = "disk" }
    m:on_warning(function(text) warnings[#warnings + 1] = text end)
    m:contact_model(an.rock_contact.model, an.rock_contact.props)
    if an.timestep or timestep then m:timestep(an.timestep or timestep) end
    m:broadphase{ margin = margin }
    return m
end

--- Walls: one per run of consecutive segments of one material, grouped by the material name.
local function build_slope(m, an, pts, mats)
    for name, mat in pairs(an.materials) do
        m:contact_model(mat.model or "linear", mat.props or {}, { groups = { "rock", name } })
    end
    local wall_material = {}
    local k = 1
    while k <= #mats do
        local j = k
        while j < #mats and mats[j + 1] == mats[k] do j = j + 1 end
        local wp = {}
        for v = k, j + 1 do wp[#wp + 1] = pts[v] end
        local w = m:wall{ points = wp, group = mats[k] }
        wall_material[w.id] = mats[k]
        k = j + 1
    end
    return wall_material
end

--- Creates the rock body (a ball, or a clump of its pebbles) in model m.
local function place_rock(m, s)
    local rk, rel = s.rock, s.release
    if rk.ball then
        return m:ball{ pos = { rel.x, rel.y }, radius = rk.pebbles[1][3] * rk.scale, density = rk.density,
            vel = { rel.vx, rel.vy }, spin = rel.spin, group = "rock" }
    end
    return m:clump{ pebbles = rk.pebbles, pos = { rel.x, rel.y }, angle = rk.angle, scale = rk.scale,
        density = rk.density, vel = { rel.vx, rel.vy }, spin = rel.spin, group = "rock" }
end

return { new_model = new_model, build_slope = build_slope, place_rock = place_rock }
