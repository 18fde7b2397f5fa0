-- SPDX-License-Identifier: MIT
-- Grains generated AS clumps (material.clump_genesis, docs/material.md "An (2006) appendix B"):
-- the physics of the packing it returns on a small specimen. Rigid grains (pebble distances
-- are the templates' after placement, expansion, scaling and servo), no overlap between
-- different grains beyond what the isotropic stress itself makes, each wall's stress within the
-- servo tolerance of the target and equal to the force its pebble overlaps make (F = kn d), and
-- the specimen M.specimen builds from it: one clump per grain, bonds only between grains.
local T = require("testlib")
local M = require("material")

local kn, sigma0, tol = 3.2e10, 1e5, 0.1
local rmin, rmax = 0.5e-3, 0.83e-3
local W, H = 0.01, 0.02
-- ~110 pebbles, ~55 grains (about 1 s)
local pk = M.clump_genesis{ width = W, height = H, rmin = rmin, rmax = rmax, porosity = 0.16,
                            kn = kn, ks = 0.15 * kn, density = 2600, seed = 2, stress = sigma0,
                            tolerance = tol }
local nb = #pk.balls
T.check(nb > 80, "pebbles: " .. nb)

-- 1. Grain bookkeeping: every pebble in exactly one grain; the counts cover the pebbles.
local owner = {}
for ci, g in ipairs(pk.clumps) do
    T.check(#g == 2 or #g == 3, "grain " .. ci .. " has " .. #g .. " pebbles")
    for _, i in ipairs(g) do
        T.check(not owner[i], "pebble " .. i .. " in two grains"); owner[i] = ci
    end
end
local c = pk.grain_counts
T.check(c[1] + 2 * c[2] + 3 * c[3] == nb, "grain counts cover the pebbles")
T.check(c[2] + c[3] == #pk.clumps, "grains of 2 and 3 = pk.clumps")
-- default shares 1/3 each: about a third of the grains of each size (56 grains: a share is
-- binomial, sd sqrt(56 * 2/9) = 3.5 grains around 18.7; 8 is three sd below)
for k = 1, 3 do T.check(c[k] >= 8, "grains of " .. k .. ": " .. c[k]) end

-- 2. Rigid grains: the templates are tangent pebbles (pair: distance r1 + r2; triple: every
-- pair tangent), scaled as a whole. After thousands of steps of rigid motion and re-scalings
-- the distances must still be r_i + r_j: the pebbles are placed from fixed offsets every step,
-- so only round-off enters (positions ~1e-2 m, doubles ~2e-18 m): 1e-12 of a radius is 1e5 x
-- that, and a grain that deformed by its contact overlaps (~4e-9 m = 6e-6 R, below) would
-- fail by far.
local function dist(p, q) return math.sqrt((p[1] - q[1]) ^ 2 + (p[2] - q[2]) ^ 2) end
for ci, g in ipairs(pk.clumps) do
    for x = 1, #g do
        for y = x + 1, #g do
            local p, q = pk.balls[g[x]], pk.balls[g[y]]
            T.near(dist(p, q) / (p[3] + q[3]), 1, 1e-12, "grain " .. ci .. ": pebbles " .. x .. "," .. y .. " tangent")
        end
    end
end
-- all grains share one scale: the radii lie in [rmin, rmax] x scale
for i, p in ipairs(pk.balls) do
    T.check(p[3] >= pk.rmin * (1 - 1e-12) and p[3] <= pk.rmax * (1 + 1e-12), "pebble " .. i .. " radius")
end

-- 3. Overlaps between different grains (and with the walls) are what the stress makes: a
-- contact carries about sigma0 x 2 R (the stress over a grain's width, unit thickness), i.e. an
-- overlap of sigma0 2 R / kn = 4.2e-9 m at R = 0.67 mm; force chains carry a few times the mean
-- (an exponential tail), so 20 x that bounds them (measured: largest 1.9e-8 m, bound 8.0e-8 m).
-- Placement or scaling that let grains overlap makes overlaps of 1e-6 m and more.
local rbar = 0.5 * (pk.rmin + pk.rmax)
local dmax = 20 * sigma0 * 2 * rbar / kn
local worst = 0
for i = 1, nb do
    for j = i + 1, nb do
        if not (owner[i] and owner[i] == owner[j]) then
            local p, q = pk.balls[i], pk.balls[j]
            worst = math.max(worst, p[3] + q[3] - dist(p, q))
        end
    end
end
local box = pk.box
local wall_f = { 0, 0, 0, 0 } -- kn x overlap summed per wall: left, right, bottom, top
for _, p in ipairs(pk.balls) do
    local d = { p[3] - (p[1] - box[1]), p[3] - (box[3] - p[1]), p[3] - (p[2] - box[2]), p[3] - (box[4] - p[2]) }
    for k = 1, 4 do
        if d[k] > 0 then wall_f[k] = wall_f[k] + kn * d[k] end
        worst = math.max(worst, d[k])
    end
end
T.check(worst > 0 and worst < dmax, string.format("largest overlap %.3g m (bound %.3g m)", worst, dmax))

-- 4. Isotropic stress: each wall within the servo tolerance of the target, and equal to the
-- force of its pebbles' overlaps (linear contact F = kn d) over its length. A cycle moves the
-- bodies and then computes the forces (PFC's order), so the wall force read at the end belongs
-- to the very positions written to the packing: the two agree to the round-off of the sum
-- (measured: <= 1.1e-16 relative), checked to 1e-9. A packing written from another state than
-- the one whose stress is reported, or a wall force not made by these overlaps, fails.
-- Rigid grains interlock, so even frictionless they can hold a deviatoric stress that the
-- walls' servo only makes flow (M.clump_genesis warns then; pk.isotropic false): the servo
-- holds the mean of the four walls within the tolerance, and the walls' ratio at the grains'
-- yield (measured on seeds 1-6 of this specimen: up to 1.30 for this seed, 1.59 over all).
local len = { box[4] - box[2], box[4] - box[2], box[3] - box[1], box[3] - box[1] }
local mean, smax, smin = 0, 0, math.huge
for k = 1, 4 do
    mean = mean + 0.25 * pk.stress[k]
    smax, smin = math.max(smax, pk.stress[k]), math.min(smin, pk.stress[k])
    T.near(wall_f[k] / len[k] / pk.stress[k], 1, 1e-9, "wall " .. k .. " stress from its overlaps")
end
T.check(math.abs(mean - sigma0) <= tol * sigma0,
    string.format("mean wall stress %.5g Pa within %g of %g", mean, tol, sigma0))
T.check(smax / smin < 1.6, string.format("wall stresses %.5g to %.5g Pa", smin, smax))
local iso = true
for k = 1, 4 do iso = iso and math.abs(pk.stress[k] - sigma0) <= tol * sigma0 end
T.check(pk.isotropic == iso, "pk.isotropic says whether every wall is within the tolerance")
T.near(pk.porosity, 1 - (function()
    local a = 0
    for _, p in ipairs(pk.balls) do a = a + math.pi * p[3] ^ 2 end
    return a
end)() / ((box[3] - box[1]) * (box[4] - box[2])), 1e-12, "porosity of the pebbles (tangent: union = sum)")

-- 5. The specimen: one clump per grain of 2 or 3, bonds only between different bodies, and
-- the grains still rigid after the bonded relaxation.
local sp = M.specimen(pk, { model = "cbond", kn = kn, ks = 0.15 * kn, fric = 0.5, density = 2600,
                            bond = { cb_tenf = 4.6e4, cb_shearf = 4.6e5 }, seed = 2 })
local m = sp.model
T.check(#sp.clumps == #pk.clumps and m:clump_count() == #pk.clumps, "one clump per grain")
local bonds = 0
for ct in m:contacts{} do
    if ct.ball2 then
        local c1, c2 = ct.clump1, ct.clump2
        T.check(not (c1 and c2 and c1 == c2), "no contact inside a grain")
        if ct:prop("bonded") == 1 then bonds = bonds + 1 end
    end
end
-- A jammed packing of grains holds with at least 3 contacts per grain on average in 2D (the
-- isostatic count with friction: 3 degrees of freedom per grain against 2 force components per
-- contact, each contact shared by two grains: Z = 3);
-- the grain-grain bonds alone (no wall contacts) give 3.96 per grain here; a specimen that
-- bonded only some of its contacts would fall below.
local ngrains = c[1] + c[2] + c[3]
T.check(bonds == sp.bonds and 2 * bonds / ngrains >= 3, "bonds between grains: " .. bonds ..
    " (specimen " .. sp.bonds .. ", grains " .. ngrains .. ")")
for ci, cl in ipairs(sp.clumps) do
    local pb = cl:pebbles()
    for x = 1, #pb do
        for y = x + 1, #pb do
            local p, q = pb[x], pb[y]
            T.near(dist(p.pos, q.pos) / (p.radius + q.radius), 1, 1e-12, "specimen clump " .. ci .. " rigid")
        end
    end
end

-- 6. Shares: grains of three only (every pebble in a triple) and of one only (no clumps).
local p3 = M.clump_genesis{ width = W, height = H, rmin = rmin, rmax = rmax, kn = kn, ks = 0.15 * kn,
                            seed = 4, shares = { 0, 0, 1 } }
T.check(p3.grain_counts[1] == 0 and p3.grain_counts[2] == 0 and 3 * p3.grain_counts[3] == #p3.balls
    and #p3.clumps == p3.grain_counts[3], "shares {0, 0, 1}: triples only")
local p1 = M.clump_genesis{ width = W, height = H, rmin = rmin, rmax = rmax, kn = kn, ks = 0.15 * kn,
                            seed = 4, shares = { 1 } }
T.check(#p1.clumps == 0 and p1.grain_counts[1] == #p1.balls, "shares {1}: single balls")

-- 7. Bad input names the option.
T.fails(function() M.clump_genesis{ width = W, height = H, rmin = rmin, rmax = rmax, kn = kn, shares = { 1, -1 } } end,
    { "clump_genesis", "shares[2]" }, "negative share")
T.fails(function() M.clump_genesis{ width = W, height = H, rmin = rmin, rmax = rmax, kn = kn, shares = { 0, 0, 0 } } end,
    { "clump_genesis", "sum to 0" }, "zero shares")
T.fails(function() M.clump_genesis{ width = W, height = H, rmin = rmin, rmax = rmax, kn = kn, grains = {} } end,
    { "clump_genesis", "unknown option 'grains'" }, "unknown option")
T.fails(function() M.clump_genesis{ width = 1e-3, height = H, rmin = rmin, rmax = rmax, kn = kn } end,
    { "clump_genesis", "does not fit" }, "grain larger than the box")
T.done("material_clump_genesis")
