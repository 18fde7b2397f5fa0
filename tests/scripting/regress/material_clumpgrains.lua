-- SPDX-License-Identifier: MIT
-- Clumped grains (material.genesis option `grains`, docs/material.md "Genesis"): the grouping
-- of touching balls into clumps of up to three (An 2006 appendix B), the clumps M.specimen
-- makes of them, and the bonds it installs between different bodies only.
local T = require("testlib")
local M = require("material")

-- 1. M.group_grains on small graphs. A triangle 1-2-3 plus a ball 4 touching only 3: with
-- kmax = 3 every grouping leaves either {1,2,3} + {4} or a pair with 4 and a pair or single
-- of the rest; in every case each grain is connected and every ball is in exactly one grain.
local function drawn(seed) local u = M.drawer(seed); return u end
local tri = { { 2, 3 }, { 1, 3 }, { 1, 2, 4 }, { 3 } }
for seed = 1, 20 do
    local grains, counts = M.group_grains(tri, 3, drawn(seed))
    local seen, n = {}, 0
    for _, g in ipairs(grains) do
        T.check(#g >= 2 and #g <= 3, "grain size " .. #g)
        for _, i in ipairs(g) do
            T.check(not seen[i], "ball " .. i .. " in two grains (seed " .. seed .. ")"); seen[i] = true
        end
    end
    for k = 1, 3 do n = n + k * counts[k] end
    T.check(n == 4, "counts cover the four balls (seed " .. seed .. ")")
    T.check(counts[2] + counts[3] == #grains, "counts of grains of 2 and 3 = grains returned")
end
-- kmax = 1: no grains; a ball with no neighbour stays single
local g1, c1 = M.group_grains(tri, 1, drawn(1))
T.check(#g1 == 0 and c1[1] == 4, "kmax 1: all single")
-- the same seed gives the same grouping
local a, b = M.group_grains(tri, 3, drawn(7)), M.group_grains(tri, 3, drawn(7))
T.check(#a == #b, "reproducible count")
for i = 1, #a do T.check(table.concat(a[i], ",") == table.concat(b[i], ","), "reproducible grain " .. i) end

-- 2. A small packing with grains (~110 balls, as material_genesis.lua; ~1 s).
local rho = 2600
local pk = M.genesis{ width = 0.01, height = 0.02, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16,
                      kn = 3.2e10, ks = 4.8e9, density = rho, seed = 3, grains = { clump_max = 3 } }
local nb = #pk.balls
T.check(#pk.clumps > 0.2 * nb / 3, "clumps made: " .. #pk.clumps .. " of " .. nb .. " balls")
local owner = {}
local in_clumps = 0
for ci, g in ipairs(pk.clumps) do
    T.check(#g >= 2 and #g <= 3, "clump " .. ci .. " has " .. #g .. " balls")
    -- every member touches another member (for <= 3 balls, with >= #g - 1 touching pairs the
    -- grain is connected): touching = overlapping at sigma0 (centre distance < R1 + R2)
    local pairs_touch = 0
    for x = 1, #g do
        local touches = false
        for y = 1, #g do
            if x ~= y then
                local p, q = pk.balls[g[x]], pk.balls[g[y]]
                if math.sqrt((p[1] - q[1]) ^ 2 + (p[2] - q[2]) ^ 2) < p[3] + q[3] then
                    touches = true
                    if x < y then pairs_touch = pairs_touch + 1 end
                end
            end
        end
        T.check(touches, "clump " .. ci .. ": ball " .. g[x] .. " touches no other member")
    end
    T.check(pairs_touch >= #g - 1, "clump " .. ci .. " connected")
    for _, i in ipairs(g) do
        T.check(not owner[i], "ball " .. i .. " in two clumps"); owner[i] = ci
        in_clumps = in_clumps + 1
    end
end
local gc = pk.grain_counts
T.check(gc[1] + 2 * gc[2] + 3 * gc[3] == nb, "grain counts cover every ball")
T.check(2 * gc[2] + 3 * gc[3] == in_clumps, "grain counts match the clump lists")

-- the packing file keeps the grains
local f = os.tmpname()
M.save_packing(pk, f)
local back = M.load_packing(f)
os.remove(f)
T.check(#back.clumps == #pk.clumps, "round trip clumps")

-- 3. The specimen: clumps of those balls, bonds between different bodies only.
local gap = 1e-3 * pk.rmin
local sp = M.specimen(pk, { model = "cbond", kn = 3.2e10, ks = 4.8e9, fric = 0.5, density = rho,
                            bond = { cb_tenf = 4.6e4, cb_shearf = 4.6e5 }, gap = gap, seed = 3 })
local m = sp.model
T.check(#sp.clumps == #pk.clumps and m:clump_count() == #pk.clumps, "one clump per grain")
T.check(#sp.balls == nb and m:ball_count() == nb - in_clumps, "free balls = singles")
-- Mass mode "sum" (PFC 3.x): the clump's mass is the sum of its pebbles' disk masses rho pi R^2
-- (t = 1 m). Both sides are sums of 2-3 products: 1e-12 relative is a few ulps; the union mode
-- differs by the lens overlaps (up to 1.9e-8 relative on this packing, measured) and a wrong
-- density by O(1).
for ci, c in ipairs(sp.clumps) do
    local peb = c:pebbles()
    T.check(#peb == #pk.clumps[ci], "clump " .. ci .. " pebbles")
    local msum = 0
    for _, p in ipairs(peb) do msum = msum + rho * math.pi * p.radius * p.radius end
    T.check(math.abs(c.mass - msum) <= 1e-12 * msum,
        string.format("clump %d mass %.17g, sum of disks %.17g", ci, c.mass, msum))
end
-- Bonds: none inside a clump, and every pair of different bodies within the gap at install is
-- bonded. The packing's positions stand for those at install (one step from rest moves a ball
-- by ~1e-12 m, against the gap of 5e-7 m), so the count is bracketed by the pairs within
-- 0.999 and 1.001 of the gap.
local bonds, at_pebbles = 0, 0
for c in m:contacts{ model = "cbond" } do
    if c:prop("bonded") == 1 then
        bonds = bonds + 1
        local c1, c2 = c.clump1, c.clump2
        T.check(not (c1 and c2 and c1 == c2), "a bond inside a clump")
        T.check(c.ball2 ~= nil, "a bond at a wall")
        if c1 or c2 then at_pebbles = at_pebbles + 1 end
    end
end
local must, may = 0, 0
for i = 1, nb do
    for j = i + 1, nb do
        if not (owner[i] and owner[i] == owner[j]) then
            local p, q = pk.balls[i], pk.balls[j]
            local d = math.sqrt((p[1] - q[1]) ^ 2 + (p[2] - q[2]) ^ 2) - p[3] - q[3]
            if d <= 0.999 * gap then must = must + 1 end
            if d <= 1.001 * gap then may = may + 1 end
        end
    end
end
T.check(bonds == sp.bonds, "bond count reported " .. sp.bonds .. ", found " .. bonds)
T.check(bonds >= must and bonds <= may, string.format("bonds %d, pairs within the gap %d-%d", bonds, must, may))
T.check(at_pebbles > 0, "bonds at pebbles")

T.fails(function() M.genesis{ width = 0.01, height = 0.02, rmin = 1e-3, rmax = 1e-3, kn = 1, grains = { clumpmax = 3 } } end,
    { "unknown option 'clumpmax'" }, "grains typo")
T.fails(function() M.genesis{ width = 0.01, height = 0.02, rmin = 1e-3, rmax = 1e-3, kn = 1, grains = { clump_max = 0 } } end,
    { "clump_max must be an integer >= 1" }, "bad clump_max")
print(string.format("material_clumpgrains: %d checks, %d balls, grains of 1/2/3: %d/%d/%d, %d bonds (%d at pebbles)",
    T.checks, nb, gc[1], gc[2], gc[3], bonds, at_pebbles))
