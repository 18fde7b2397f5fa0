-- SPDX-License-Identifier: MIT
-- material.genesis_disk: a disk specimen made in a circular vessel (a regular polygon of
-- segment walls, shrunk radially by one servo) instead of cut from a box packing. Physics
-- checks on a small disk (~200 balls): every ball inside the circle, the porosity, the
-- isotropic stress (vessel pressure, and the whole disk's mean stress measured by m:measure,
-- equal to it by equilibrium), no overlap once the vessel is gone and the disk relaxed, and
-- that M.disk / M.specimen take the packing as a disk between the curved jaws.
local T = require("testlib")
local M = require("material")

local rmin, rmax, kn = 0.4e-3, 0.66e-3, 6.4e10
local D0, n0, sigma0 = 0.017, 0.16, 1e5
local pk = M.genesis_disk{ diameter = D0, rmin = rmin, rmax = rmax, porosity = n0, kn = kn, ks = 9.6e9,
                           stress = sigma0, seed = 3 }
local v = pk.vessel
local R = 0.5 * v.diameter
local N = v.segments
T.check(#pk.balls > 150, "balls: " .. #pk.balls)

-- 1. the vessel is a circle to within 1e-2 rmin: its flats lie at most R (1 - cos(pi/N))
-- inside the circumcircle (and a ball wedged in a corner sticks out of the circle of radius
-- a - r by the same to leading order)
T.check(R * (1 - math.cos(math.pi / N)) <= 1e-2 * rmin, string.format("%d segments: flat depth %.3g m <= 1e-2 rmin", N,
    R * (1 - math.cos(math.pi / N))))
T.near(v.apothem, R * math.cos(math.pi / N), 1e-12, "apothem = R cos(pi/N)")
-- the vessel shrank only by the servo's last adjustment (the stress came from radius scaling)
T.check(math.abs(v.diameter - D0) < 1e-3 * D0, "final diameter within 1e-3 of the asked one")

-- 2. every centre within D/2 - r of the centre (the polygon is inscribed in the circle). A
-- ball may press into a flat by its overlap at sigma0: F/kn with F at most ~10 mean contact
-- forces, the mean ~ sigma0 2 rmean (per unit thickness): 10 * 1e5 * 1.06e-3 / 6.4e10 = 1.7e-8
-- m = 4e-5 rmin; tolerance 1e-4 r
local c = v.center
local worst = -math.huge
for _, p in ipairs(pk.balls) do
    local out = math.sqrt((p[1] - c[1]) ^ 2 + (p[2] - c[2]) ^ 2) - (R - p[3])
    worst = math.max(worst, out / p[3])
end
T.check(worst <= 1e-4, string.format("every centre within D/2 - r (worst excess %.3g r)", worst))

-- 3. porosity. The radii are drawn for (1 - n0) of the vessel's area; the frictionless
-- packing then relaxes to sigma0 (the radii shrink, ~1%), and the rattlers (~4% of the balls)
-- are deleted, so the final porosity lies above n0: the box genesis gives 0.175-0.21 for
-- n0 = 0.16 on 20 x 40 mm boxes of ~460 balls (docs/material.md), and a disk of diameter D has
-- the same perimeter per area (4/D) as a box of side D, hence the same wall layer; this disk
-- has half as many balls, so a little more scatter (seeds 1-6 of it: 0.187-0.216).
-- Tolerance: n0 to n0 + 0.07. The packing's figure is the balls' area over the polygon's.
local solid = 0
for _, p in ipairs(pk.balls) do solid = solid + math.pi * p[3] ^ 2 end
local poly = N * v.apothem ^ 2 * math.tan(math.pi / N)
T.near(pk.porosity, 1 - solid / poly, 1e-12, "porosity = 1 - balls' area / polygon area")
T.check(pk.porosity >= n0 and pk.porosity <= n0 + 0.07, string.format("porosity %.4f in [%.2f, %.2f]", pk.porosity,
    n0, n0 + 0.07))
-- the interior (m:measure, circle of 0.8 R) is no looser than the whole, and denser by at most
-- the wall layer's share: a row of balls against a flat leaves (2 - pi/2) r^2 of pore per 2r of
-- wall, an excess porosity of ~0.43 r / R over the disk (0.027 here), so the two differ by at
-- most 0.04 (seeds 1-6: 0.002-0.024)
T.check(pk.porosity_inner <= pk.porosity + 0.01 and pk.porosity_inner >= pk.porosity - 0.04,
    string.format("inner porosity %.4f (whole %.4f)", pk.porosity_inner, pk.porosity))

-- 4. stress. The servo stops with the vessel pressure within its tolerance (10%) of sigma0,
-- and asks a ratio <= 1e-3 but may end at its step cap (as M.genesis's): a frictionless
-- packing at sigma0 is marginal and keeps rearranging somewhere (seed 2: balls moving at
-- 1 cm/s after 45 000 steps). Seeds 1-6 of this disk end at 7e-4 to 1.9e-3, seed 2 at 1e-2
-- (caught in such a rearrangement). Asked here (seed 3, 1.8e-3): <= 5e-3, unbalanced forces
-- below 0.5% of the mean contact force; the stress identity below checks the balance too. The whole disk's mean stress (m:measure over the circumcircle, rescaled from
-- the circle's area to the polygon's) equals the pressure in equilibrium: the mean of
-- (sxx + syy)/2 over the disk is sum_i F_i a / (2 A) = sum F / L for flats at distance a, A =
-- L a / 2 (the virial theorem); the unbalanced forces (ratio 1e-3 of the mean contact force)
-- perturb it far below 1e-2.
T.check(math.abs(pk.stress.vessel - sigma0) <= 0.1 * sigma0, string.format("vessel pressure %.4g Pa", pk.stress.vessel))
T.check(pk.ratio <= 5e-3, "ratio " .. pk.ratio)
T.near(pk.stress.measured, pk.stress.vessel, 1e-2, "mean stress of the disk = vessel pressure")
-- the interior carries the stress too (within 25%: a ~100-ball circle, its own force-chain noise)
T.check(math.abs(pk.stress.inner - sigma0) <= 0.25 * sigma0, string.format("inner mean stress %.4g Pa", pk.stress.inner))

-- 5. the vessel removed (a model of the balls alone, frictionless as in genesis) and the disk
-- relaxed: the packing releases sigma0, about 1e-6 of a radius of elastic strain, and comes to
-- rest with no overlap left. At sigma0 the largest overlap is ~1e-5 r (below); once relaxed,
-- what remains is the overlap of forces of the order of the unbalanced ones (ratio 1e-5 of the
-- initial mean contact force): tolerance 1e-2 of the largest overlap at sigma0
local function build()
    local m = M.new_model(0.7)
    m:contact_model("linear", { kn = kn, ks = 9.6e9, fric = 0 })
    for _, p in ipairs(pk.balls) do m:ball{ pos = { p[1], p[2] }, radius = p[3], density = 2600 } end
    m:cycle(1)
    return m
end
local function max_overlap(m)
    local o = 0
    for ct in m:contacts{} do
        if ct.overlap > 0 then o = math.max(o, ct.overlap / math.min(ct.ball1.radius, ct.ball2.radius)) end
    end
    return o
end
local m = build()
local o0 = max_overlap(m)
T.check(o0 > 0 and o0 < 1e-4, string.format("largest overlap at sigma0 %.3g r", o0))
local mean0 = m:unbalanced().mean_contact
M.solve_ratio(m, 1e-5, 20000, 100)
local o1 = max_overlap(m)
print(string.format("overlap at sigma0 %.3g r, relaxed %.3g r; porosity %.4f (inner %.4f); pressure %.5g Pa, " ..
    "mean stress %.5g Pa (inner %.5g Pa)", o0, o1, pk.porosity, pk.porosity_inner, pk.stress.vessel,
    pk.stress.measured, pk.stress.inner))
T.check(o1 <= 1e-2 * o0, string.format("largest overlap after the vessel went %.3g r (at sigma0 %.3g r)", o1, o0))
-- it stays a disk. The release itself is ~1e-6 strain (1e-8 m here), but an unloaded
-- frictionless packing is unjammed (floppy), so balls may creep while the last forces decay
-- (4e-7 m measured); what must not happen is a rearrangement by a fraction of a radius:
-- tolerance 1e-2 rmin
local moved = 0
local k = 0
for b in m:balls() do
    k = k + 1
    local p = pk.balls[k]
    moved = math.max(moved, math.sqrt((b.pos[1] - p[1]) ^ 2 + (b.pos[2] - p[2]) ^ 2))
end
T.check(moved < 1e-2 * rmin, string.format("largest displacement on release %.3g m", moved))
T.check(mean0 > 0, "contacts carried force at sigma0")

-- 6. M.disk takes the whole packing as the disk (centre and diameter of the vessel), and
-- M.specimen gives it the curved jaws
local idx = M.disk(pk)
T.check(#idx == #pk.balls and idx.cut == v.diameter and idx.center[1] == c[1] and idx.center[2] == c[2],
    "M.disk of a vessel packing: all balls, the vessel's centre and diameter")
local sp = M.specimen(pk, { model = "cbond", kn = kn, ks = 9.6e9, fric = 0.5, density = 2600,
                            bond = { cb_tenf = 1e15, cb_shearf = 1e15 } }, { balls = idx })
T.check(sp.jaws == "curved" and sp.bonds > #pk.balls, "specimen between curved jaws, bonded")
-- the jaws meet the disk's circle: both first contacts within a ball's angular width (2 rmax /
-- R = 9 degrees) of the loaded diameter, where a cut disk's were up to 20 degrees off
print(string.format("first jaw contacts %.2f / %.2f degrees", sp.disk.first_contact[1], sp.disk.first_contact[2]))
for _, a in ipairs(sp.disk.first_contact) do
    T.check(math.abs(a) <= math.deg(2 * rmax / R), string.format("first jaw contact %.1f degrees off the diameter", a))
end

T.fails(function() M.genesis_disk{ diameter = D0, rmin = rmin, rmax = rmax, kn = kn, wall = 1 } end,
    { "unknown option 'wall'" }, "unknown option")
T.fails(function() M.genesis_disk{ diameter = 4 * rmax, rmin = rmin, rmax = rmax, kn = kn } end,
    { "must exceed 8 rmax" }, "too small a vessel")
T.fails(function() M.genesis_disk{ diameter = D0, rmin = rmin, rmax = rmax, kn = kn, segments = 4 } end,
    { "segments must be an integer >= 8" }, "too few segments")
T.fails(function() M.genesis_disk{ rmin = rmin, rmax = rmax, kn = kn } end, { "'diameter' is required" }, "no diameter")
T.done("material_disk_vessel")
