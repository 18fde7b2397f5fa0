-- SPDX-License-Identifier: MIT
-- Measurement regions (core/src/api/measure.cpp) against closed forms: exact disk-region areas,
-- porosity, coordination number and stress of regular lattices, strain rate of prescribed
-- velocity fields.
local T = require("testlib")
local pi, sqrt = math.pi, math.sqrt

-- 1. Exact areas. One ball in an empty model (porosity = 1 - ball part inside / region area).
do
    local m = talus.model{}
    local r = 0.1
    m:ball{ pos = {0, 0}, radius = r, density = 1000 }
    -- a circle of radius 2r about the ball: 1 - r^2 / (2r)^2
    T.near(m:measure{ circle = {0, 0, 2 * r} }.porosity, 0.75, 1e-14, "disk inside a circle")
    -- the lens of two equal circles a radius apart: (2 pi / 3 - sqrt(3) / 2) r^2
    local lens = (2 * pi / 3 - sqrt(3) / 2) * r * r
    T.near(m:measure{ circle = {r, 0, r} }.solid, lens, 1e-15, "lens area")
    -- boxes: a quarter (centre on a corner), a half (centre on an edge), nothing, everything
    T.near(m:measure{ box = {0, 0, 1, 1} }.solid, pi * r * r / 4, 1e-15, "quarter disk")
    T.near(m:measure{ box = {-1, 0, 1, 1} }.solid, pi * r * r / 2, 1e-15, "half disk")
    T.near(m:measure{ box = {r, -1, 1, 1} }.solid, 0, 1e-15, "disk outside")
    T.near(m:measure{ box = {-1, -1, 1, 1} }.solid, pi * r * r, 1e-15, "disk inside")
    -- a general corner cut, against a midpoint-rule quadrature of the chord lengths (2e5 panels;
    -- the chord's square-root ends make its error O(h^1.5), ~3e-9 of the area here: tol 2e-8)
    local x0, y0 = -0.03, -0.04  -- box [x0, 1] x [y0, 1]: the disk minus its left and lower caps
    local n, sum = 200000, 0
    local h = 2 * r / n
    for k = 1, n do
        local x = -r + (k - 0.5) * h
        if x >= x0 then
            local s = sqrt(r * r - x * x)
            sum = sum + math.max(0, s - math.max(-s, y0)) * h
        end
    end
    T.near(m:measure{ box = {x0, y0, 1, 1} }.solid, sum, 2e-8 * sum, "disk cut at a corner")
    -- a box smaller than the disk, inside it: all solid
    T.near(m:measure{ box = {-0.05, -0.05, 0.05, 0.05} }.porosity, 0, 1e-15, "box inside the disk")
end

-- 2. Lattices of equal balls of radius r at spacing a = 2r - d (slightly overlapping, fixed, so
-- every neighbour pair is a contact with force F = kn d). With a box of whole lattice cells:
-- the solid inside is exact (periodicity), so the porosity is the lattice's, and every ball
-- whose centre is inside has all its neighbours.
--   square:    porosity 1 - pi r^2 / a^2,           coordination 4, stress -F / a (isotropic)
--   hexagonal: porosity 1 - 2 pi r^2 / (sqrt3 a^2), coordination 6, stress -sqrt3 F / a
-- (the stress: each ball adds -sum_k (a/2) F n_k n_k over its neighbours, over its cell's area).
local r, d, KN = 0.05, 1e-4, 1e8
local a = 2 * r - d
local F = KN * d
local function lattice(hex)
    local m = talus.model{}
    m:on_warning(function() end)  -- the lattice is built overlapping on purpose
    m:contact_model("linear", { kn = KN, ks = KN, fric = 0.5 })
    local dy = hex and a * sqrt(3) / 2 or a
    for j = 0, 13 do
        for i = 0, 13 do
            local x = i * a + ((hex and j % 2 == 1) and a / 2 or 0)
            m:ball{ pos = {x, j * dy}, radius = r, density = 1000, fix = true }
        end
    end
    m:timestep{ fixed = 1e-6 }
    m:cycle(1)
    return m, dy
end
do
    local m = lattice(false)
    local c = m:contacts{}()
    T.near(c.normal_force, F, 1e-9 * F, "square: contact force kn d")
    local x0 = 2.25 * a  -- 8 x 8 cells, no centre or contact point on the boundary
    local res = m:measure{ box = {x0, x0, x0 + 8 * a, x0 + 8 * a} }
    T.check(res.balls == 64, "square: 64 centres inside")
    T.near(res.porosity, 1 - pi * r * r / (a * a), 1e-12, "square: porosity")
    T.near(res.coordination, 4, 0, "square: coordination 4")
    T.near(res.stress.xx, -F / a, 1e-9 * F / a, "square: stress xx = -F/a")
    T.near(res.stress.yy, -F / a, 1e-9 * F / a, "square: stress yy = -F/a")
    T.near(res.stress.xy, 0, 1e-9 * F / a, "square: no shear stress")
    T.check(res.contacts == 2 * 64, "square: 2 contacts per cell: " .. res.contacts)
    -- A circle region: the porosity of a lattice is approached, not exact (the circle cuts cells)
    local cr = m:measure{ circle = {6.5 * a, 6.5 * a, 3 * a} }
    T.near(cr.porosity, 1 - pi * r * r / (a * a), 0.02, "square: circle porosity close")
    T.near(cr.coordination, 4, 0, "square: circle coordination 4")
end
do
    local m, dy = lattice(true)
    local x0, y0 = 2.25 * a, 1.5 * dy  -- 8 x 4 periods (a x sqrt3 a, two balls each)
    local res = m:measure{ box = {x0, y0, x0 + 8 * a, y0 + 8 * dy} }
    T.check(res.balls == 64, "hex: 64 centres inside: " .. res.balls)
    T.near(res.porosity, 1 - 2 * pi * r * r / (sqrt(3) * a * a), 1e-12, "hex: porosity")
    T.near(res.coordination, 6, 0, "hex: coordination 6")
    T.near(res.stress.xx, -sqrt(3) * F / a, 1e-9 * F / a, "hex: stress xx = -sqrt3 F/a")
    T.near(res.stress.yy, -sqrt(3) * F / a, 1e-9 * F / a, "hex: stress yy = -sqrt3 F/a")
    T.near(res.stress.xy, 0, 1e-9 * F / a, "hex: no shear stress")
    -- touching equal disks (d -> 0): the closed forms pi/4 and pi/(2 sqrt3) of solid fraction
    print(string.format("measure_region: square porosity %.6f (touching: %.6f), hex %.6f (touching: %.6f)",
        1 - pi * r * r / (a * a), 1 - pi / 4, res.porosity, 1 - pi / (2 * sqrt(3))))
end

-- 3. Strain rate from the best fit of the ball velocities (balls placed irregularly, no contacts).
local function field(L, v0, omega)
    local m = talus.model{}
    local balls = {}
    for k = 1, 40 do
        local x, y = (k * 0.6180339887) % 1, (k * 0.7548776662) % 1
        balls[k] = m:ball{ pos = {x, y}, radius = 0.01, density = 1000 }
    end
    for _, b in ipairs(balls) do
        local p = b.pos
        local dx, dy = p[1] - 0.5, p[2] - 0.5
        b.vel = { v0[1] + L[1] * dx + L[2] * dy - omega * dy, v0[2] + L[3] * dx + L[4] * dy + omega * dx }
    end
    return m:measure{ circle = {0.5, 0.5, 0.45} }
end
do
    -- rigid motion: translation and rotation about an arbitrary centre give no strain rate
    local res = field({0, 0, 0, 0}, {0.3, -0.2}, 2.5)
    T.check(res.balls >= 3, "strain rate: balls in the circle")
    T.near(res.strain_rate.xx, 0, 1e-12, "rigid rotation: xx = 0")
    T.near(res.strain_rate.yy, 0, 1e-12, "rigid rotation: yy = 0")
    T.near(res.strain_rate.xy, 0, 1e-12, "rigid rotation: xy = 0")
    T.near(res.spin, 2.5, 1e-12, "rigid rotation: spin = omega")
    -- a linear field v = v0 + L x: its gradient's symmetric part
    res = field({0.1, 0.4, -0.2, -0.3}, {1, 2}, 0)
    T.near(res.strain_rate.xx, 0.1, 1e-12, "linear field: xx")
    T.near(res.strain_rate.yy, -0.3, 1e-12, "linear field: yy")
    T.near(res.strain_rate.xy, 0.5 * (0.4 - 0.2), 1e-12, "linear field: xy")
    T.near(res.spin, 0.5 * (-0.2 - 0.4), 1e-12, "linear field: spin")
end

-- 4. Input errors.
do
    local m = talus.model{}
    T.fails(function() m:measure{} end, { "measure: give one region" }, "no region")
    T.fails(function() m:measure{ circle = {0, 0} } end, { "takes 3 numbers (got 2)" }, "circle size")
    T.fails(function() m:measure{ circle = {0, 0, -1} } end, { "radius > 0" }, "circle radius")
    T.fails(function() m:measure{ box = {1, 0, 0, 1} } end, { "xmin < xmax" }, "box order")
    T.fails(function() m:measure{ circel = {0, 0, 1} } end, { "unknown option 'circel'" }, "typo")
    local e = m:measure{ circle = {0, 0, 1} }
    T.check(e.balls == 0 and e.porosity == 1 and e.strain_rate.xx ~= e.strain_rate.xx,
        "empty region: porosity 1, no strain rate (NaN)")
end

T.done("measure_region")
