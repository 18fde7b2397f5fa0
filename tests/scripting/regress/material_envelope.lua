-- SPDX-License-Identifier: MIT
-- M.envelope on a small parallel-bonded specimen (the Lac du Bonnet material of M.lac_du_bonnet
-- at a quarter of its size, ~250 balls): a UCS test and two biaxial tests whose side walls the
-- servo holds at the confinement; the peak rises with the confinement, the Mohr-Coulomb fit has
-- a positive friction angle and cohesion, Hoek-Brown a positive m_i; E does not depend on the
-- confinement (the bonds carry the load elastically); the thresholds are ordered.
local T = require("testlib")
local M = require("material")

local mat, genesis = M.lac_du_bonnet()
local confs = { 0, 10e6, 20e6 }
local r = M.envelope{ packing = function(seed) return genesis(0.0317 / 4, 0.0634 / 4, seed) end, material = mat,
                      confinements = confs, seeds = { 1 }, jobs = 1, test = { strain_per_crossing = 2e-5 } }
T.check(r.failed == nil, "no test failed")
T.check(#r.tests == 3, "three tests")
for i, t in ipairs(r.tests) do
    print(string.format("sigma3 %4.1f MPa: sigma1 %6.1f MPa, E %.1f GPa, nu %.3f, crack initiation %.1f MPa (%.2f), " ..
        "damage %.1f MPa (%.2f), %d cracks, %d steps, lateral %.3f MPa", t.confinement / 1e6, t.peak / 1e6, t.E / 1e9,
        t.nu, t.ci / 1e6, t.ci_ratio, t.cd / 1e6, t.cd_ratio, t.cracks, t.steps, (t.lateral or 0) / 1e6))
    T.check(t.confinement == confs[i], "test order")
    T.check(t.stop == "post_peak", "stopped by " .. t.stop)
    if i > 1 then
        T.check(t.peak > r.tests[i - 1].peak, "sigma1 rises with sigma3")
        -- the servo holds the side walls at the confinement: their mean stress up to the peak
        -- within 2% (the servo's gain corrects a 1% error in ~100 steps, the test lasts 20 000)
        T.near(t.lateral, t.confinement, 0.02 * t.confinement, "lateral stress held")
    else
        T.check(t.lateral == nil, "no side walls in the UCS test")
    end
    -- the same bonded assembly: E within 5% whatever the confinement
    T.near(t.E, r.tests[1].E, 0.05 * r.tests[1].E, "E at sigma3 " .. t.confinement)
    T.check(t.ci > 0 and t.ci <= t.cd and t.cd <= t.peak, "0 < crack initiation <= damage <= peak")
    T.near(t.deviator, t.peak - t.confinement, 0, "deviator")
end
local s = r.seeds[1]
print(string.format("c %.1f MPa, phi %.1f deg, m_i %.2f (sigma_ci %.1f MPa), rms %.2f MPa", s.c / 1e6, s.phi, s.m_i,
    s.sigma_ci / 1e6, s.rms / 1e6))
T.check(s.phi > 0 and s.phi < 60, "phi " .. s.phi)
T.check(s.c > 0, "cohesion")
T.check(s.m_i > 0, "m_i")
T.near(s.sigma_ci, r.tests[1].peak, 0, "sigma_ci = the UCS test's peak")
-- the fit is that of the three points
local mc = M.mohr_coulomb({ { 0, r.tests[1].peak }, { 10e6, r.tests[2].peak }, { 20e6, r.tests[3].peak } })
T.near(s.phi, mc.phi, 1e-12, "phi of the points")
T.check(r.phi.mean == s.phi and r.phi.sd == 0 and r.phi.n == 1, "one seed: its values, sd 0")
T.fails(function() M.envelope{ packing = genesis, material = mat, confinements = { -1 } } end,
    { "confinements[1] must be a stress >= 0" }, "negative confinement")
T.fails(function() M.envelope{ packing = genesis, material = mat, confinement = { 0 } } end,
    { "unknown option 'confinement'" }, "typo")
print(string.format("material_envelope: %d checks", T.checks))
