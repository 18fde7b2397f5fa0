-- SPDX-License-Identifier: MIT
--
-- calibrate_ucs.lua: An's (2006) calibration procedure for a contact-bonded rock (appendix B),
-- automated with a root finder over full UCS tests:
--   1. unbreakable bonds: the ratio ks/kn for the target Poisson's ratio (root of nu - target),
--      then kn for the target E (E is proportional to kn at a fixed ratio in a linear
--      assembly, so one scaling, checked by a test);
--   2. bond strengths (normal, with shear = `shear_ratio` x normal) for the target UCS (root).
-- Every evaluation is the mean over `nseeds` specimens, run in parallel by talus.map (all cores,
-- MPI ranks under mpirun). The specimens are made once (genesis) and reused as packings.
--
--   talus run scripts/examples/calibrate_ucs.lua [outdir] [nseeds]     (a few minutes)
--
-- Targets: Berea sandstone (An 2006 app. B): E 16 GPa, nu 0.28, UCS 40 MPa, density 2600.
local M = require("material")
local C = require("calibrate")
local outdir = arg[1] or "out"
local nseeds = tonumber(arg[2] or "3")
talus.mkdir(outdir)
local target = { E = 16e9, nu = 0.28, ucs = 40e6 }
local shear_ratio = 10 -- thesis: shear 1e10 N / normal 1e9 N
local geo = { width = 0.02, height = 0.04, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16,
              density = 2600 }

local wall0 = os.time()
local packings = talus.map(nseeds, function(i)
    local o = { seed = i, kn = 6.4e10, ks = 9.6e9 }
    for k, v in pairs(geo) do o[k] = v end
    return M.genesis(o)
end, { on_error = "raise" }) -- every specimen is needed: a failed genesis stops the calibration
print(string.format("%d packings: %s balls", nseeds, table.concat((function()
    local t = {}; for i, p in ipairs(packings) do t[i] = #p.balls end; return t end)(), ", ")))

-- one set of micro-properties over all packings (parallel); mean E, nu, UCS
local log = {}
local function run(props, unbreakable)
    local res = talus.map(nseeds, function(i)
        local mat = { model = "cbond", kn = props.kn, ks = props.kn * props.ratio, fric = 0.5,
                      density = 2600, seed = i,
                      bond = unbreakable and { cb_tenf = math.huge, cb_shearf = math.huge }
                          or { cb_tenf = props.tenf, cb_shearf = shear_ratio * props.tenf } }
        local sp = M.specimen(packings[i], mat, { energy = false })
        -- unbreakable: no peak; load to 0.2% strain and fit the elastic part (40-60% of the
        -- largest stress)
        local r = M.compress(sp, unbreakable and { max_strain = 2e-3, every = 100 }
                                  or { post_peak = 0.8 })
        return { E = r.E, nu = r.nu, ucs = r.ucs }
    end, { on_error = "raise" }) -- a mean over fewer seeds would move the calibration silently
    local mean = { E = 0, nu = 0, ucs = 0 }
    for _, r in ipairs(res) do
        for k in pairs(mean) do mean[k] = mean[k] + r[k] / #res end
    end
    local row = { kn = props.kn, ratio = props.ratio, tenf = math.huge, E = mean.E, nu = mean.nu }
    if not unbreakable then row.tenf, row.ucs = props.tenf, mean.ucs end -- no peak otherwise
    log[#log + 1] = row
    print(string.format("  kn %.4g  ks/kn %.4f  tenf %s  ->  E %.3f GPa  nu %.4f  %s",
        row.kn, row.ratio, unbreakable and "inf" or string.format("%.4g N", props.tenf),
        mean.E / 1e9, mean.nu, unbreakable and "" or string.format("UCS %.3f MPa", mean.ucs / 1e6)))
    return mean
end

-- step 1a: ks/kn for nu (nu falls as ks/kn rises)
local kn = 6.4e10
print("step 1a: ks/kn for nu = " .. target.nu .. " (unbreakable bonds)")
local ratio = C.root(function(x)
    return run({ kn = kn, ratio = x }, true).nu - target.nu
end, 0.15, 1.0, { xtol = 2e-3, ftol = 0.005 })
-- step 1b: kn for E
print("step 1b: kn for E = " .. target.E / 1e9 .. " GPa")
local e1 = run({ kn = kn, ratio = ratio }, true).E
kn = kn * target.E / e1
local e2 = run({ kn = kn, ratio = ratio }, true)
-- step 2: strength for UCS (UCS ~ tenf: bracket around the linear estimate)
print("step 2: normal bond strength for UCS = " .. target.ucs / 1e6 .. " MPa")
local u1 = run({ kn = kn, ratio = ratio, tenf = 4.6e4 }, false).ucs
local est = 4.6e4 * target.ucs / u1
local tenf = C.root(function(x)
    return run({ kn = kn, ratio = ratio, tenf = x }, false).ucs - target.ucs
end, 0.7 * est, 1.4 * est, { xtol = 1e-3 * est, ftol = 0.005 * target.ucs })
local final = run({ kn = kn, ratio = ratio, tenf = tenf }, false)
print(string.format("\nresult (mean of %d specimens): kn %.4g N/m, ks %.4g N/m (ks/kn %.4f), cb_tenf %.4g N, "
    .. "cb_shearf %.4g N", nseeds, kn, kn * ratio, ratio, tenf, shear_ratio * tenf))
print(string.format("  E %.3f GPa (target %.1f)  nu %.4f (target %.2f; unbreakable run %.4f)  UCS %.3f MPa (target %.1f)",
    final.E / 1e9, target.E / 1e9, final.nu, target.nu, e2.nu, final.ucs / 1e6, target.ucs / 1e6))
print(string.format("  %d full tests, %d s of wall time", #log * nseeds, os.time() - wall0))
C.write_csv(outdir .. "/calibrate_ucs.csv", log, { "kn", "ratio", "tenf", "E", "nu", "ucs" })
