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
local r = M.compress(sp, { post_peak = 0.8 })
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
-- the secant modulus at 50% is close to the tangent (no seating in a bonded specimen): 10%
T.near(r.E50, r.E, 0.1 * r.E, "E50 vs E")
-- 2D linear assembly: E is of the order of kn per unit thickness (0.2-0.6 kn for disks at this
-- porosity and ks/kn, Talus measured 0.36-0.41); nu of a 2D disk assembly lies in (0, 1)
T.check(r.E > 0.2 * mat.kn and r.E < 0.6 * mat.kn, "E " .. r.E)
T.check(r.nu > 0 and r.nu < 1, "nu " .. r.nu)

-- unbreakable bonds: the stress keeps rising (no peak before 0.4% strain), and E agrees with
-- the breakable run's elastic E (same springs) to 3%
local sp2 = M.specimen(pk, { model = "cbond", kn = 6.4e10, ks = 9.6e9, fric = 0.5, density = 2600,
                             bond = { cb_tenf = math.huge, cb_shearf = math.huge } })
local r2 = M.compress(sp2, { max_strain = 2 * r.peak_strain, every = 100 })
T.check(r2.stop == "max_strain", "unbreakable stop " .. r2.stop)
T.check(r2.ipeak == #r2.rows, "no peak with unbreakable bonds")
T.check(r2.breaks.tension + r2.breaks.shear == 0, "no breaks")
T.near(r2.E, r.E, 0.03 * r.E, "E unbreakable vs breakable")
print(string.format("material_ucs: %d checks; UCS %.2f MPa, E %.2f GPa, nu %.3f, %d balls", T.checks,
    r.ucs / 1e6, r.E / 1e9, r.nu, #pk.balls))
