-- SPDX-License-Identifier: MIT
--
-- calibrated_seeds.lua: the scatter over seeds of a contact-bonded material calibrated by
-- calibrate_ucs.lua (docs/material.md, "Calibration"). calibrate_ucs.lua reports means over its
-- packings; this runs the same tests seed by seed, on those packings and on held-out ones, and
-- prints each seed and the mean and standard deviation.
--
--   talus run scripts/examples/calibrated_seeds.lua [nseeds] [kn] [ks/kn] [cb_tenf]
--
-- Defaults: 5 seeds and the result of calibrate_ucs.lua on 28 November 2026 (seeds 1-3 were
-- its packings): kn 2.7944536958046806e10 N/m, ks/kn 0.39120044758147399, cb_tenf
-- 39548.02903991934 N (shear strength 10 times the normal one, as calibrate_ucs.lua). Each seed
-- runs twice, as calibrate_ucs.lua's steps do: unbreakable bonds to an axial strain of 2e-3
-- (E0, nu0), then breakable bonds to 80% post-peak (UCS, E, nu).
local M = require("material")
local n = tonumber(arg[1] or "5")
local kn = tonumber(arg[2] or "27944536958.046806")
local ratio = tonumber(arg[3] or "0.39120044758147399")
local tenf = tonumber(arg[4] or "39548.02903991934")
if not (n and n >= 2 and kn and kn > 0 and ratio and ratio > 0 and tenf and tenf > 0) then
    error("calibrated_seeds.lua: arguments nseeds (>= 2), kn, ks/kn and cb_tenf (> 0) must be numbers")
end

local rows = talus.map(n, function(i)
    -- the packings of calibrate_ucs.lua (its genesis stiffness, not the calibrated one)
    local pk = M.genesis{ width = 0.02, height = 0.04, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16,
                          density = 2600, seed = i, kn = 6.4e10, ks = 9.6e9 }
    local out = { seed = i, balls = #pk.balls, porosity = pk.porosity }
    for _, unbreakable in ipairs({ true, false }) do
        local mat = { model = "cbond", kn = kn, ks = kn * ratio, fric = 0.5, density = 2600, seed = i,
                      bond = unbreakable and { cb_tenf = math.huge, cb_shearf = math.huge }
                          or { cb_tenf = tenf, cb_shearf = 10 * tenf } }
        local sp = M.specimen(pk, mat, { energy = false })
        local r = M.compress(sp, unbreakable and { max_strain = 2e-3, every = 100 } or { post_peak = 0.8 })
        if unbreakable then
            out.E0, out.nu0 = r.E, r.nu
        else
            out.E, out.nu, out.ucs, out.stop = r.E, r.nu, r.ucs, r.stop
        end
    end
    return out
end)

-- A seed that failed is left out of the table and the statistics, and said so (M.finished).
rows = M.finished(rows, n)

print(string.format("kn %.6g N/m, ks/kn %.6g, cb_tenf %.6g N, cb_shearf %.6g N", kn, ratio, tenf, 10 * tenf))
print("seed balls porosity  E0[GPa] nu0    UCS[MPa] E[GPa] nu     stop")
for _, r in ipairs(rows) do
    print(string.format("%4d %5d %.3f    %6.2f  %.3f  %7.2f  %6.2f  %.3f  %s", r.seed, r.balls, r.porosity,
        r.E0 / 1e9, r.nu0, r.ucs / 1e6, r.E / 1e9, r.nu, r.stop))
end
local line = "mean +- sd:"
for _, k in ipairs({ { "E0", 1e-9, "GPa" }, { "nu0", 1, "" }, { "ucs", 1e-6, "MPa" }, { "E", 1e-9, "GPa" },
                     { "nu", 1, "" } }) do
    local sum = 0
    for _, r in ipairs(rows) do sum = sum + r[k[1]] * k[2] end
    local mean, var = sum / #rows, 0
    for _, r in ipairs(rows) do var = var + (r[k[1]] * k[2] - mean) ^ 2 end
    line = line .. string.format("  %s %.3f +- %.3f%s", k[1], mean, math.sqrt(var / (#rows - 1)),
                                 k[3] ~= "" and " " .. k[3] or "")
end
print(line)
