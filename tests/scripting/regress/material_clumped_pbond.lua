-- SPDX-License-Identifier: MIT
-- Clumped grains with parallel bonds (Cho et al. 2007; M.lac_du_bonnet("clumped")) end to end on
-- a small specimen (a quarter of the Lac du Bonnet size, ~250 balls in ~90 grains): parallel
-- bonds between grains only, never inside one; a UCS test with a peak and a post-peak drop, stiffer
-- than the same packing with its grains' balls bonded to each other instead (a rigid grain has no
-- compliant contact inside it); a biaxial test whose peak rises with the confinement (phi > 0); a Brazilian test
-- on a disk of grains made in a circular vessel (M.clump_genesis_disk, half size) that breaks
-- bonds and gives a tensile strength far below the UCS; the disk's grains touch their circle.
local T = require("testlib")
local M = require("material")

local mat, genesis, disk = M.lac_du_bonnet("clumped")
local W, H = 0.0317 / 4, 0.0634 / 4
local pk = genesis(W, H, 1)
T.check(#pk.clumps > 0.2 * #pk.balls / 3, "grains of 2-3 balls: " .. #pk.clumps)
mat.seed = 1
local sp = M.specimen(pk, mat)
local inside, between, at_pebbles = 0, 0, 0
for c in sp.model:contacts{ model = "pbond" } do
    if c:prop("pb_state") == 3 then
        local c1, c2 = c.clump1, c.clump2
        if c1 and c2 and c1 == c2 then inside = inside + 1 else between = between + 1 end
        if c1 or c2 then at_pebbles = at_pebbles + 1 end
    end
end
T.check(inside == 0, "no bond inside a grain")
T.check(between == sp.bonds, "every bond between two bodies: " .. between .. " of " .. sp.bonds)
T.check(at_pebbles > 0.5 * between, "most bonds hold a grain: " .. at_pebbles)

local u = M.compress(sp, { post_peak = 0.8, strain_per_crossing = 2e-5 })
T.check(u.stop == "post_peak" and u.rows[#u.rows].sa < 0.8 * u.ucs, "UCS test: peak and post-peak drop")
T.check(u.breaks.tension + u.breaks.shear > 0, "bonds broke")
-- the same packing with its grains' balls left free (M.specimen's clumps = false) and bonded to
-- each other too: the contacts inside the grains become compliant, the assembly softer
local ub = M.compress(M.specimen(pk, mat, { clumps = false }), { post_peak = 0.8, strain_per_crossing = 2e-5 })
print(string.format("clumped: %d balls in %d grains, %d bonds: UCS %.1f MPa, E %.1f GPa, nu %.3f; grains unclumped: " ..
    "UCS %.1f MPa, E %.1f GPa", #pk.balls, #pk.clumps, sp.bonds, u.ucs / 1e6, u.E / 1e9, u.nu, ub.ucs / 1e6, ub.E / 1e9))
T.check(u.E > 1.1 * ub.E, "rigid grains stiffen the assembly")

local sb = M.specimen(pk, mat, { sides = true })
local b = M.compress(sb, { post_peak = 0.8, confinement = 10e6, strain_per_crossing = 2e-5 })
local mc = M.mohr_coulomb({ { 0, u.ucs }, { 10e6, b.ucs } })
print(string.format("biaxial at 10 MPa: %.1f MPa; phi %.1f deg", b.ucs / 1e6, mc.phi))
T.check(b.ucs > u.ucs and mc.phi > 0, "the peak rises with the confinement")

local pd = disk(0.98 * 0.0317 / 2, 101)
local md = {}
for k, v in pairs(mat) do md[k] = v end
md.platen = { kn = mat.platen.kn, ks = mat.platen.ks, fric = 0.5 }
T.check(pd.vessel and #pd.clumps > 0, "a vessel disk of grains")
-- its rim: the outermost pebble edges within a tenth of rmin of the circle of the final vessel
local c, R = pd.vessel.center, 0.5 * pd.vessel.diameter
local reach = 0
for _, p in ipairs(pd.balls) do reach = math.max(reach, math.sqrt((p[1] - c[1]) ^ 2 + (p[2] - c[2]) ^ 2) + p[3]) end
T.check(reach <= R * (1 + 1e-6) and reach >= R - 0.1 * pd.rmin, string.format("rim at %.6g of %.6g m", reach, R))
local br = M.brazilian(M.specimen(pd, md, { balls = M.disk(pd) }), { post_peak = 0.5, strain_per_crossing = 2e-5 })
print(string.format("Brazilian (%d balls): peak %.2f MPa, %d breaks, valid %s %s", br.balls, br.peak / 1e6,
    br.fracture.n, tostring(br.valid), br.reason or ""))
T.check((br.stop == "post_peak" or br.stop == "split") and br.fracture.n > 0, "the disk failed, bonds broke")
T.check(br.peak > 0 and br.peak < 0.5 * u.ucs, "the disk's peak well below the UCS")
T.fails(function() M.clump_genesis_disk{ diameter = 0.01, rmin = 1e-3, rmax = 1e-3, kn = 1, width = 1 } end,
    { "unknown option 'width'" }, "a box option")
T.fails(function() M.clump_genesis_disk{ diameter = 0.005, rmin = 1e-3, rmax = 1e-3, kn = 1 } end,
    { "must exceed 12 rmax" }, "too small a disk")
print(string.format("material_clumped_pbond: %d checks", T.checks))
