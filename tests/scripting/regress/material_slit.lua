-- SPDX-License-Identifier: MIT
-- Slit interfaces of a flat-jointed specimen (M.specimen's mat.slit, Potyondy 2012): the
-- fraction drawn, each slit interface unbonded and open by its gap, the draw reproducible, and
-- a specimen of slit interfaces only has no bonds to hold it: a small fraction of the bonded
-- specimen's strength in uniaxial compression.
local T = require("testlib")
local M = require("material")

local pk = M.genesis{ width = 0.01, height = 0.02, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16, kn = 6.4e10,
                      ks = 6.4e10 / 2.5, seed = 3 }
local function mat(fraction, gap)
    return { model = "fjoint", kn = 6.4e10, ks = 6.4e10 / 2.5, fric = 0.5, density = 2600, seed = 7,
             bond = { fj_emod = 6.4e10, fj_kratio = 2.5, fj_nr = 2, fj_fric = 0.6,
                      fj_ten = { mean = 2e7, sd = 2e6 }, fj_coh = { mean = 1e8, sd = 1e7 } },
             slit = fraction and { fraction = fraction, gap = gap } or nil }
end
local GAP = 1e-7
local sp = M.specimen(pk, mat(0.3, GAP))
local n = sp.bonds
-- binomial: the count within 4 standard deviations of 0.3 n
local sd = math.sqrt(n * 0.3 * 0.7)
print(string.format("material_slit: %d interfaces, %d slit (expected %.1f +- %.1f)", n, sp.slits, 0.3 * n, sd))
T.check(math.abs(sp.slits - 0.3 * n) <= 4 * sd, "slit fraction")
local slit, bonded, set = 0, 0, {}
for c in sp.model:contacts{ model = "fjoint" } do
    if c:prop("fj_mtype") == 2 then
        slit = slit + 1
        set[#set + 1] = c.ball1.id .. "-" .. (c.ball2 and c.ball2.id or "w")
        T.check(c:prop("fj_nbond") == 0 and c:prop("bonded") == 0, "a slit interface has no bonded element")
        T.check(c:prop("fj_gap0") == GAP, "installation gap")
        -- force-free at its gap: after the relaxation, open by the gap less what the specimen's
        -- settling closed (the balls move by ~1e-10 m under the bonded network's zero stress)
        T.near(c:prop("fj_gap"), GAP, 0.05, "open by its gap (relative)")
        T.check(c:prop("fj_fn") == 0, "no force on an open slit")
    elseif c:prop("fj_nbond") == 2 then
        bonded = bonded + 1
    end
end
T.check(slit == sp.slits, "every slit counted")
T.check(bonded == n - slit, "the rest bonded")
-- the same seed draws the same interfaces
local sp2 = M.specimen(pk, mat(0.3, GAP))
local set2 = {}
for c in sp2.model:contacts{ model = "fjoint" } do
    if c:prop("fj_mtype") == 2 then set2[#set2 + 1] = c.ball1.id .. "-" .. (c.ball2 and c.ball2.id or "w") end
end
T.check(table.concat(set, ",") == table.concat(set2, ","), "reproducible draw")

-- all slit (no gap) against all bonded, in uniaxial compression
local bonded_r = M.compress(M.specimen(pk, mat(nil)), { post_peak = 0.8, strain_per_crossing = 2e-5 })
local slit_sp = M.specimen(pk, mat(1, 0))
T.check(slit_sp.slits == slit_sp.bonds, "fraction 1: every interface slit")
local slit_r = M.compress(slit_sp, { post_peak = 0.8, max_strain = 4 * bonded_r.peak_strain, strain_per_crossing = 2e-5 })
print(string.format("material_slit: UCS bonded %.1f MPa, all slit %.2f MPa (%s)", bonded_r.ucs / 1e6, slit_r.ucs / 1e6,
    slit_r.stop))
T.check(slit_r.ucs < 0.2 * bonded_r.ucs, "no bonds, no strength")

T.fails(function() M.specimen(pk, { model = "pbond", kn = 1e10, fric = 0.5, bond = { pb_ten = 1e7, pb_coh = 1e7 },
                                     slit = { fraction = 0.1 } }) end, { "mat.slit is for a flat joint" }, "not a flat joint")
T.fails(function() M.specimen(pk, mat(1.5, 0)) end, { "mat.slit.fraction must be in [0, 1]" }, "fraction > 1")
print(string.format("material_slit: %d checks", T.checks))
