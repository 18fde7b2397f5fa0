-- SPDX-License-Identifier: MIT
-- material.compress (UCS test) on a small contact-bonded specimen: the curve has a peak and a
-- post-peak drop, E from the elastic part reproduces the recorded platen stress and strain, the
-- axial stress is the platen force over the width, and unbreakable bonds give no peak.
local T = require("testlib")
local M = require("material")

local pk = M.genesis{ width = 0.01, height = 0.02, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16,
                      kn = 6.4e10, ks = 9.6e9, seed = 3 }
local mat = { model = "cbond", kn = 6.4e10, ks = 9.6e9, fric = 0.5, density = 2600,
              bond = { cb_tenf = 4.6e4, cb_shearf = 4.6e5 } }
local sp = M.specimen(pk, mat)
T.check(sp.bonds > #pk.balls, "bonds " .. sp.bonds .. " for " .. #pk.balls .. " balls")
local r = M.compress(sp, { post_peak = 0.8, strain_per_crossing = 2e-5 })
T.check(r.stop == "post_peak", "stopped by " .. r.stop)
T.check(r.ipeak > 5 and r.ipeak < #r.rows, "the peak is inside the curve")
T.check(r.rows[#r.rows].sa < 0.8 * r.ucs, "post-peak drop")
T.check(r.breaks.tension + r.breaks.shear > 0, "bonds broke")
-- E (tangent at 50%, least squares over 40-60% of peak): every recorded pre-peak point of that
-- window lies on the fitted line to 5% of its stress (the elastic part of a bonded assembly is
-- linear until bonds break; at 40-60% of peak few have: the scatter measured is ~1%).
local a
for i = 1, r.ipeak do
    local row = r.rows[i]
    if row.sa >= 0.4 * r.ucs and row.sa <= 0.6 * r.ucs then
        if not a then a = row else
            T.near(row.sa, a.sa + r.E * (row.ea - a.ea), 0.05 * row.sa, "elastic point " .. i)
        end
    end
end
T.check(r.fit_points >= 5, "fit points " .. r.fit_points)
T.check(r.nu > 0 and r.nu < 1.5, "nu " .. r.nu) -- 2D disk assemblies allow nu up to 1 (+ cracking)

-- unbreakable bonds: the stress keeps rising (no peak), nothing breaks, and the assembly is
-- linear: its E is of the order of kn per unit thickness (0.2-0.6 kn for disks at this porosity
-- and ks/kn; Talus measured 0.36-0.41 kn on 450-ball specimens)
local sp2 = M.specimen(pk, { model = "cbond", kn = 6.4e10, ks = 9.6e9, fric = 0.5, density = 2600,
                             bond = { cb_tenf = math.huge, cb_shearf = math.huge } })
local r2 = M.compress(sp2, { max_strain = 2 * r.peak_strain, every = 100, strain_per_crossing = 2e-5 })
T.check(r2.stop == "max_strain", "unbreakable stop " .. r2.stop)
T.check(r2.ipeak == #r2.rows, "no peak with unbreakable bonds")
T.check(r2.breaks.tension + r2.breaks.shear == 0, "no breaks")
T.check(r2.E > 0.2 * mat.kn and r2.E < 0.6 * mat.kn, "E unbreakable " .. r2.E)
-- Before the first break the breakable specimen is the same linear assembly: its modulus over
-- the rows with no break yet (above 10% of peak, past the ramp's start) equals the unbreakable
-- E to 3% (the two fits see the same springs; the rest is the fits' spread over rows).
local xs, ys = {}, {}
for i = 1, r.ipeak do
    local row = r.rows[i]
    if row.breaks_tension + row.breaks_shear == 0 and row.sa > 0.1 * r.ucs then
        xs[#xs + 1] = row.ea; ys[#ys + 1] = row.sa
    end
end
T.check(#xs >= 3, "rows before the first break: " .. #xs)
local n, mx, my = #xs, 0, 0
for i = 1, n do mx = mx + xs[i] / n; my = my + ys[i] / n end
local sxx, sxy = 0, 0
for i = 1, n do sxx = sxx + (xs[i] - mx) ^ 2; sxy = sxy + (xs[i] - mx) * (ys[i] - my) end
T.near(sxy / sxx, r2.E, 0.03 * r2.E, "elastic modulus before the first break vs unbreakable E")
-- cracking only softens: the tangent at 50% of peak is at most the elastic E (3% fit spread)
T.check(r.E <= 1.03 * r2.E, string.format("E %.4g <= unbreakable %.4g", r.E, r2.E))
print(string.format("material_ucs: %d checks; UCS %.2f MPa, E %.2f GPa, nu %.3f, %d balls", T.checks,
    r.ucs / 1e6, r.E / 1e9, r.nu, #pk.balls))
