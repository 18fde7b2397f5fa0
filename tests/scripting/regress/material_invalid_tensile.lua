-- SPDX-License-Identifier: MIT
-- A Brazilian test that did not split gives no tensile strength, and its number never reaches a
-- mean, a ratio or a calibration objective (docs/material.md "Brazilian test", "Calibration
-- against several targets"). Before, M.run_seeds's table and CSV filled UCS/sigma_t from disks
-- that were not valid, and M.calibrate picked its best point on sigma_t = 11.4 MPa with every
-- point's disks invalid.
local T = require("testlib")
local M = require("material")
local RS = require("talus_util.response_surface")

-- 1. The seeds' statistics: a row without a valid tensile strength (tensile nil, the peak kept
-- apart) is left out of sigma_t and of UCS/sigma_t.
local rows = {
    { seed = 1, ucs = 200e6, tensile = 10e6, tensile_peak = 10e6, valid = true, ratio = 20 },
    { seed = 2, ucs = 180e6, tensile = nil, tensile_peak = 25e6, valid = false, reason = "no split" },
    { seed = 3, ucs = 190e6, tensile = 9e6, tensile_peak = 9e6, valid = true, ratio = 190 / 9 },
}
local mt, _, nt = M.seeds_stat(rows, "tensile")
T.near(mt, 9.5e6, 1e-9, "sigma_t: the mean of the two valid disks")
T.check(nt == 2, "sigma_t over 2 disks")
local mr, _, nr = M.seeds_stat(rows, "ratio")
T.check(nr == 2 and math.abs(mr - 0.5 * (20 + 190 / 9)) < 1e-12, "UCS/sigma_t over the valid disks only")
local mu, _, nu = M.seeds_stat(rows, "ucs")
T.check(nu == 3 and math.abs(mu - 190e6) < 1e-6, "UCS over every seed")
-- M.mean_sd (the examples' statistics) likewise: neither an invalid row nor a missing value counts
local m2, _, n2 = M.mean_sd({ { tensile = 1 }, { tensile = 100, valid = false }, { valid = true }, { tensile = 3, valid = true } },
    "tensile")
T.check(m2 == 2 and n2 == 2, "M.mean_sd: invalid and missing values left out")

-- 2. A calibration point whose disks did not split: no tensile strength and no ratio, its
-- misfit infinite (calibrate.fit_targets never picks it), and the calibration says so.
local tests = {
    { kind = "ucs", seed = 1, peak = 190e6, E = 50e9, nu = 1.5, E_elastic = 70e9, nu_elastic = 0.25, cpu = 1 },
    { kind = "ucs", seed = 2, peak = 210e6, E = 52e9, nu = 1.6, E_elastic = 71e9, nu_elastic = 0.26, cpu = 1 },
    { kind = "brazilian", seed = 1, tensile = nil, peak = 11.4e6, valid = false, cpu = 1 },
    { kind = "brazilian", seed = 2, tensile = nil, peak = 25.0e6, valid = false, cpu = 1 },
}
local o = M.calibration_outputs(tests)
T.check(o.tensile == nil and o.ratio == nil, "no disk split: the point has no sigma_t and no ratio")
T.check(o.tensile_valid == 0 and o.disks == 2, "tensile_valid 0 of 2 disks")
T.near(o.ucs, 200e6, 1e-6, "UCS still measured")
tests[3] = { kind = "brazilian", seed = 1, tensile = 9e6, peak = 9e6, valid = true, cpu = 1 }
o = M.calibration_outputs(tests)
T.check(o.tensile == 9e6 and o.tensile_valid == 1 and math.abs(o.ratio - 200e6 / 9e6) < 1e-12,
    "one disk split: sigma_t and the ratio from it alone")

-- The response-surface search over points where sigma_t is measured only at some: the best is
-- among them, whatever the others' invalid peaks would have given.
local targets = { { name = "ucs", value = 200e6, tol = 0.11 }, { name = "tensile", value = 9.3e6, tol = 0.14 } }
local calls = 0
local res = RS.fit_targets{
    params = { { name = "a", lo = 0.5, hi = 2, start = 1, spread = 0.3 } }, targets = targets, budget = 4,
    evaluate = function(points)
        local outs = {}
        for i, p in ipairs(points) do
            calls = calls + 1
            -- points with a > 1 "split"; the others report no sigma_t
            local split = p.a > 1
            outs[i] = { ucs = 200e6 * p.a, tensile = split and 9.3e6 * p.a or nil }
        end
        return outs
    end,
}
T.check(res.best and res.best.out.tensile ~= nil, "the best point has a measured sigma_t")
for _, r in ipairs(res.rows) do
    if r.out.tensile == nil then T.check(r.misfit == math.huge, "a point without sigma_t: infinite misfit") end
end
local said = M.calibration_unmeasured(res, targets)
local found = false
for _, line in ipairs(said) do if line:find("target 'tensile' not measured", 1, true) then found = true end end
T.check(found, "the calibration says which points could not measure sigma_t: " .. table.concat(said, "; "))
-- every point without sigma_t: no best point at all, and said so
local none = { rows = { { index = 1, out = { ucs = 2e8 }, misfit = math.huge }, { index = 2, out = { ucs = 1.9e8 },
                                                                                   misfit = math.huge } } }
none.best = none.rows[1]
said = M.calibration_unmeasured(none, targets)
T.check(none.best == nil and said[#said]:find("no point had every target measured", 1, true),
    "no point measured every target: no best point (" .. said[#said] .. ")")

T.done("material_invalid_tensile")
