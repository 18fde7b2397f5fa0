-- SPDX-License-Identifier: MIT
-- rockfall/shapes.lua: rock shapes (ball, three_balls, ngon, fitted, pebbles), checked, and the rock of
-- one draw: its pebbles, size, density, angle and mass.
local Dist = require("rockfall.distributions")
local K = require("rockfall.check")
local fail, check_keys, num, hint = K.fail, K.check_keys, K.num, K.hint
local check_dist, draw = Dist.check_dist, Dist.draw

-- Unit geometries: pebbles {x, y, r} about the origin; `size` names what the shape's scale 1
-- means. The clump's centroid (exact union, engine) is put at the release point.
local SHAPES = {}

-- An's (2006, chapter 6) rock: three equal balls in mutual contact (an equilateral triangle of
-- side 2R), R = 0.04 m. Centred on the triangle's centroid. `thesis_a` is its older name, still
-- accepted.
SHAPES.three_balls = function(spec)
    local R = spec.radius or 0.04
    local h = R * math.sqrt(3) / 3
    return { { -R, -h, R }, { R, -h, R }, { 0, 2 * h, R } }
end
SHAPES.thesis_a = SHAPES.three_balls

SHAPES.ball = function(spec) return { { 0, 0, spec.radius or 0.5 } } end

-- Rounded n-gon of circumradius `radius`: n corner pebbles of radius corner x radius on a
-- circle, a centre pebble reaching the edges' midpoints (the apothem of the corner disks' hull)
-- and `edge_pebbles` more corner-size pebbles evenly along each edge (a ring approximating the
-- polygon with rounded corners).
SHAPES.ngon = function(spec)
    local n, R = spec.n or 6, spec.radius or 0.5
    local rc = (spec.corner or 0.3) * R
    local rr = R - rc
    local peb = {}
    local corners = {}
    for k = 0, n - 1 do
        local a = 2 * math.pi * k / n + math.pi / 2
        corners[#corners + 1] = { rr * math.cos(a), rr * math.sin(a) }
        peb[#peb + 1] = { corners[#corners][1], corners[#corners][2], rc }
    end
    local e = spec.edge_pebbles or 0
    for k = 1, n do
        local a, b = corners[k], corners[k % n + 1]
        for j = 1, e do
            local s = j / (e + 1)
            peb[#peb + 1] = { a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2]), rc }
        end
    end
    peb[#peb + 1] = { 0, 0, rr * math.cos(math.pi / n) + rc }
    return peb
end

-- A rock fitted to L1 x L2 (L1 >= L2): overlapping balls of radius L2/2 along the long axis,
-- the end balls touching the rock's ends, spaced at most L2/4 apart so that the waist between
-- two balls stays above 0.97 L2 (cos(asin(1/4)) = 0.968).
SHAPES.fitted = function(spec)
    local L1, L2 = spec.L1, spec.L2
    local r = L2 / 2
    local span = L1 - L2
    local m = math.max(1, math.ceil(span / (L2 / 4) - 1e-9))
    local peb = {}
    for j = 0, m do
        peb[#peb + 1] = { -span / 2 + span * j / m, 0, r }
    end
    if span <= 0 then peb = { { 0, 0, r } } end
    return peb
end

SHAPES.pebbles = function(spec) return spec.pebbles end

local ROCK_KEYS = {
    "shape", "name", "weight", "radius", "n", "corner", "edge_pebbles", "L1", "L2", "pebbles",
    "scale", "mass", "volume", "density", "angle",
}

local function check_rock(spec, where)
    check_keys(spec, ROCK_KEYS, where)
    local shape = spec.shape or "ball"
    if not SHAPES[shape] then
        fail("%s: unknown shape '%s'%s (known: ball, three_balls, ngon, fitted, pebbles)", where, tostring(shape),
            hint(shape, { "ball", "three_balls", "ngon", "fitted", "pebbles" }))
    end
    if spec.radius ~= nil then num(spec.radius, where .. ".radius", 1e-9) end
    if shape == "ngon" then
        if spec.n ~= nil and (math.type(spec.n) ~= "integer" or spec.n < 3) then
            fail("%s.n must be an integer >= 3 (got %s)", where, tostring(spec.n))
        end
        if spec.corner ~= nil then num(spec.corner, where .. ".corner", 0.01, 1) end
        if spec.edge_pebbles ~= nil and (math.type(spec.edge_pebbles) ~= "integer" or spec.edge_pebbles < 0) then
            fail("%s.edge_pebbles must be an integer >= 0", where)
        end
    elseif shape == "fitted" then
        num(spec.L1, where .. ".L1", 1e-9)
        num(spec.L2, where .. ".L2", 1e-9)
        if spec.L2 > spec.L1 then fail("%s: L2 (%g) must not exceed L1 (%g)", where, spec.L2, spec.L1) end
    elseif shape == "pebbles" then
        if type(spec.pebbles) ~= "table" or #spec.pebbles < 1 then
            fail("%s.pebbles must be a list of {x, y, r}", where)
        end
        for k, p in ipairs(spec.pebbles) do
            if type(p) ~= "table" or type(p[1]) ~= "number" or type(p[2]) ~= "number"
                or type(p[3]) ~= "number" or p[3] <= 0 then
                fail("%s.pebbles[%d] must be {x, y, r} with r > 0", where, k)
            end
        end
    end
    if spec.mass ~= nil and spec.volume ~= nil then
        fail("%s: give mass or volume, not both", where)
    end
    if spec.scale ~= nil and (spec.mass ~= nil or spec.volume ~= nil) and shape ~= "fitted" then
        fail("%s: give scale, or mass or volume (which set the scale), not both", where)
    end
    if spec.scale ~= nil then check_dist(spec.scale, where .. ".scale", 1e-9) end
    if spec.mass ~= nil then check_dist(spec.mass, where .. ".mass", 1e-12) end
    if spec.volume ~= nil then check_dist(spec.volume, where .. ".volume", 1e-12) end
    if spec.density ~= nil then check_dist(spec.density, where .. ".density", 1e-9) end
    if spec.angle ~= nil then check_dist(spec.angle, where .. ".angle") end
    if spec.weight ~= nil then num(spec.weight, where .. ".weight", 0) end
    return spec
end

--- Exact area [m^2] of a union of disks: Green's theorem on the free arcs (as the engine does,
--- docs/physics/clumps.md); used to size a rock before the model exists.
local function union_area(peb)
    local area = 0
    for i, p in ipairs(peb) do
        local covered, inside = {}, false
        for j, q in ipairs(peb) do
            if j ~= i then
                local dx, dy = q[1] - p[1], q[2] - p[2]
                local d = math.sqrt(dx * dx + dy * dy)
                local tol = 1e-12 * (p[3] + q[3])
                if d + p[3] <= q[3] + tol and (d > tol or q[3] > p[3] + tol or j < i) then
                    inside = true
                    break
                end
                if d < p[3] + q[3] and d + q[3] > p[3] + tol then
                    local ca = (d * d + p[3] * p[3] - q[3] * q[3]) / (2 * d * p[3])
                    local al = math.acos(math.max(-1, math.min(1, ca)))
                    local phi = math.atan(dy, dx)
                    local a, b = phi - al, phi + al
                    if a < -math.pi then
                        covered[#covered + 1] = { a + 2 * math.pi, math.pi }
                        covered[#covered + 1] = { -math.pi, b }
                    elseif b > math.pi then
                        covered[#covered + 1] = { a, math.pi }
                        covered[#covered + 1] = { -math.pi, b - 2 * math.pi }
                    else
                        covered[#covered + 1] = { a, b }
                    end
                end
            end
        end
        if not inside then
            table.sort(covered, function(u, v) return u[1] < v[1] end)
            local free, cur = {}, -math.pi
            for _, c in ipairs(covered) do
                if c[1] > cur then free[#free + 1] = { cur, c[1] } end
                cur = math.max(cur, c[2])
            end
            if cur < math.pi then free[#free + 1] = { cur, math.pi } end
            -- Area = 1/2 closed integral of (x dy - y dx) over arcs t0..t1 of circle (cx, cy, r):
            -- 1/2 [ r^2 (t1 - t0) + r cx (sin t1 - sin t0) - r cy (cos t1 - cos t0) ].
            local r, cx, cy = p[3], p[1], p[2]
            for _, f in ipairs(free) do
                area = area + 0.5 * (r * r * (f[2] - f[1]) + r * cx * (math.sin(f[2]) - math.sin(f[1]))
                    - r * cy * (math.cos(f[2]) - math.cos(f[1])))
            end
        end
    end
    return area
end

--- The rock of one draw: pebbles (unit geometry), scale, density, angle, area, mass, r_eq.
local function make_rock(spec, rs)
    local geom = SHAPES[spec.shape or "ball"](spec)
    local area1 = union_area(geom)
    local density = draw(spec.density or 2600, rs.density)
    local scale = 1
    local size_r = rs.size
    if spec.shape == "fitted" then
        -- Dimensions given: a mass sets the density, a volume the size.
        if spec.mass ~= nil then density = draw(spec.mass, size_r) / area1 end
        if spec.volume ~= nil then scale = math.sqrt(draw(spec.volume, size_r) / area1) end
        if spec.scale ~= nil then scale = scale * draw(spec.scale, size_r) end
    elseif spec.mass ~= nil then
        scale = math.sqrt(draw(spec.mass, size_r) / (density * area1))
    elseif spec.volume ~= nil then
        scale = math.sqrt(draw(spec.volume, size_r) / area1)
    elseif spec.scale ~= nil then
        scale = draw(spec.scale, size_r)
    end
    local area = area1 * scale * scale
    local bound = 0
    for _, p in ipairs(geom) do
        bound = math.max(bound, math.sqrt(p[1] * p[1] + p[2] * p[2]) + p[3])
    end
    local angle = 0
    if #geom > 1 then
        angle = draw(spec.angle or { dist = "uniform", min = 0, max = 2 * math.pi }, rs.angle)
    elseif spec.angle ~= nil then
        angle = draw(spec.angle, rs.angle)
    end
    return {
        shape = spec.name or spec.shape or "ball", pebbles = geom, scale = scale, density = density,
        angle = angle, volume = area, mass = density * area, r_eq = math.sqrt(area / math.pi),
        bound = bound * scale, ball = (#geom == 1 and geom[1][1] == 0 and geom[1][2] == 0),
    }
end

return { SHAPES = SHAPES, check_rock = check_rock, union_area = union_area, make_rock = make_rock }
