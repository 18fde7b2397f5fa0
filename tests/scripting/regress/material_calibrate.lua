-- SPDX-License-Identifier: MIT
-- M.calibrate end to end on a tiny contact-bonded specimen (~110 balls, one seed): targets made
-- by a run at a known point (kn, cb_tenf) are met again from a start off by 1.6x and 0.6x,
-- from a design of three points; the CSV has a row per point; a second run on the same
-- checkpoint takes every test from it and gives the same rows, bit for bit.
local T = require("testlib")
local M = require("material")
local outdir = arg[1] or "."

local function packing(seed)
    return M.genesis{ width = 0.01, height = 0.02, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16, kn = 6.4e10,
                      ks = 9.6e9, seed = 2 + seed }
end
local function material(p, seed)
    return { model = "cbond", kn = p.kn, ks = p.kn / 6.67, fric = 0.5, density = 2600, seed = seed,
             bond = { cb_tenf = p.cb_tenf, cb_shearf = 10 * p.cb_tenf } }
end
-- the targets: what the known point gives on the same packing
local truth = { kn = 5e10, cb_tenf = 4e4 }
local sp = M.specimen(packing(1), material(truth, 1))
local r0 = M.compress(sp, { post_peak = 0.8, strain_per_crossing = 2e-5 })
print(string.format("truth: UCS %.2f MPa, E %.2f GPa", r0.ucs / 1e6, r0.E / 1e9))

local dir = outdir .. "/material_calibrate"
os.execute("rm -rf '" .. dir .. "'")
local spec = {
    material = material, packing = packing, seeds = { 1 }, quiet = true, jobs = 1,
    params = { { name = "kn", lo = 1e10, hi = 2e11, start = 8e10 }, { name = "cb_tenf", lo = 1e4, hi = 2e5, start = 2.4e4 } },
    targets = { { name = "E", value = r0.E, tol = 0.03 }, { name = "ucs", value = r0.ucs, tol = 0.05 } },
    design = { { 0, 0 }, { 1, 0 }, { 0, 1 } }, budget = 6,
    checkpoint = dir .. "/ckpt", key = "tiny cbond v1", csv = dir .. "/calib.csv",
    tests = { ucs = { strain_per_crossing = 2e-5 } },
}
local r = M.calibrate(spec)
for _, row in ipairs(r.rows) do
    print(string.format("point %d %-6s kn %.4g cb_tenf %.4g: E %.2f GPa, UCS %.2f MPa, misfit %.3g", row.index, row.phase,
        row.params.kn, row.params.cb_tenf, row.out.E / 1e9, row.out.ucs / 1e6, row.misfit))
end
print(string.format("stop %s after %d points (%d tests each), %.1f s CPU", r.stop, r.evaluations, r.tests_per_point, r.cpu))
T.check(r.rows[1].phase == "design" and r.rows[3].phase == "design" and r.rows[4].phase == "step", "design then steps")
T.check(r.stop == "targets", "stopped by " .. r.stop)
T.check(math.abs(r.best.out.E / r0.E - 1) <= 0.03, "E met")
T.check(math.abs(r.best.out.ucs / r0.ucs - 1) <= 0.05, "UCS met")
-- E of a bonded assembly is proportional to the contact stiffness: kn found to the tolerance of E
T.check(math.abs(r.best.params.kn / truth.kn - 1) <= 0.05, "kn " .. r.best.params.kn)
-- the start is far: the design alone does not meet the targets
T.check(not r.rows[1].met and not r.rows[2].met and not r.rows[3].met, "the design points miss")
T.check(r.tests_per_point == 1 and r.cpu > 0, "one UCS test per point, CPU counted")

-- the CSV: a header and one row per point, and the targets beside it
local lines = {}
for line in io.lines(spec.csv) do lines[#lines + 1] = line end
T.check(#lines == 1 + r.evaluations, "csv rows " .. #lines)
T.check(lines[1]:find("^index,batch,phase,kn,cb_tenf,E,E_sd,nu,nu_sd,ucs,ucs_sd") ~= nil, "csv header " .. lines[1])
local nt = 0
for _ in io.lines(dir .. "/calib_targets.csv") do nt = nt + 1 end
T.check(nt == 3, "targets csv")

-- resumption: the same run again takes every test from the checkpoint
local again = M.calibrate(spec)
T.check(#again.rows == #r.rows, "same points")
for i, row in ipairs(r.rows) do
    T.check(again.rows[i].params.kn == row.params.kn and again.rows[i].params.cb_tenf == row.params.cb_tenf, "point " .. i)
    T.check(again.rows[i].out.ucs == row.out.ucs and again.rows[i].out.E == row.out.E, "outputs " .. i)
end
T.fails(function() M.calibrate{ material = material, packing = packing, params = spec.params,
                                 targets = { { name = "UCS", value = 1 } } } end, { "targets[1] is 'UCS' (known: E, nu, ucs" },
    "unknown target")
T.fails(function() M.calibrate{ material = material, packing = packing, params = spec.params,
                                 targets = { { name = "tensile", value = 1 } } } end, { "needs 'disk'" }, "no disk")
os.execute("rm -rf '" .. dir .. "'")
print(string.format("material_calibrate: %d checks", T.checks))
