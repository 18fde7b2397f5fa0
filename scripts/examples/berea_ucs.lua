-- SPDX-License-Identifier: MIT
--
-- berea_ucs.lua: An (2006) appendix B (Berea sandstone, contact bonds) reproduced over seeds:
-- kn 6.4e10 N/m, ks 9.6e9 N/m, fric 0.5, density 2600, contact-bond strengths normal : shear =
-- 1e9 : 1e10 N. Thesis result: UCS 39.6 MPa, E 16.1 GPa (targets 40 MPa, 16 GPa, nu 0.28).
--
--   talus run scripts/examples/berea_ucs.lua [outdir] [nseeds] [ball|contact] [balls|clumps|clumpgen] [elastic]
--
-- "ball" (default): kn, ks are the balls' stiffnesses, as PFC2D 3.x reads them (the contact gets
-- the two balls' springs in series, kn/2 and ks/2 for equal balls; docs/lua-api.md, "inherited
-- ... springs in series"); docs/results/material.md says why this is An's (2006) reading. "contact":
-- the same numbers as the contacts' stiffnesses (twice as stiff), for comparison.
--
-- "clumps": the grains are rigid clumps of up to three touching balls, grouped at random after
-- genesis (M.genesis grains option, docs/material.md), as An's (2006) specimen; "balls"
-- (default): single balls. "clumpgen": the grains are generated AS clumps (M.clump_genesis: rigid
-- templates of 1, 2 or 3 touching balls, a third of the grains each, placed at random and
-- compacted as clumps; docs/material.md); "clumpgen:p1,p2,p3" with grain shares p1 : p2 : p3.
-- "elastic": unbreakable bonds, loaded to an axial strain of 2e-3 (the
-- thesis's first calibration step, "match E with infinite strengths"): E and nu of the bonded
-- assembly before any crack.
--
-- An (2006) does not give its ball size; we use balls of R 0.5-0.83
-- mm. In 2D with unit thickness a bond strength F is a
-- stress times a length, so at fixed kn, ks and packing UCS scales exactly as F / R and E does
-- not depend on R. The script therefore runs a normal strength of 4.6e4 N at this ball size and
-- reports UCS * R_mean / F_n, from which An's (2006) values follow for any ball size.
local M = require("material")
local outdir = arg[1] or "out"
local n = tonumber(arg[2] or "5")
talus.mkdir(outdir)
local Fn = 4.6e4
local mode = arg[3] or "ball"
local grains = arg[4] or "balls"
-- "clumps" = clumps of up to 3 balls (An's 2006); "clumpsK" = up to K (a sensitivity check)
-- "clumpgen:p1,p2,p3": the same with grain shares p1 : p2 : p3 (grains of 1, 2, 3 balls)
local clumpgen = grains == "clumpgen" or grains:match("^clumpgen:") ~= nil
local shares
if grains:match("^clumpgen:") then
    shares = {}
    for v in grains:sub(10):gmatch("[^,]+") do
        local x = tonumber(v)
        if not x then error("berea_ucs: 4th argument: clumpgen:p1,p2,p3 needs numbers (got '" .. v .. "')") end
        shares[#shares + 1] = x
    end
end
local clump_max = grains == "clumps" and 3 or tonumber(grains:match("^clumps(%d)$") or "")
if grains ~= "balls" and not clump_max and not clumpgen then
    error("berea_ucs: 4th argument: balls, clumps, clumpsK (up to K balls) clumpgen or clumpgen:p1,p2,p3 (got " .. grains .. ")")
end
local elastic = arg[5] == "elastic"
if arg[5] and not elastic then error("berea_ucs: 5th argument: elastic or nothing (got " .. arg[5] .. ")") end
local tag = mode .. ((clump_max or clumpgen) and "_" .. grains:gsub("[:,]", "_") or "") .. (elastic and "_elastic" or "")
local kn, ks = 6.4e10, 9.6e9
if mode == "ball" then kn, ks = kn / 2, ks / 2 end
local res = talus.map(n, function(i)
    local g = { width = 0.02, height = 0.04, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16,
                kn = kn, ks = ks, density = 2600, seed = i,
                grains = clump_max and { clump_max = math.tointeger(clump_max) } or nil }
    g.shares = shares
    local pk = clumpgen and M.clump_genesis(g) or M.genesis(g)
    local sp = M.specimen(pk, { model = "cbond", kn = kn, ks = ks, fric = 0.5, density = 2600,
                                bond = elastic and { cb_tenf = math.huge, cb_shearf = math.huge }
                                    or { cb_tenf = Fn, cb_shearf = 10 * Fn }, seed = i })
    local r = M.compress(sp, { post_peak = 0.8, max_strain = elastic and 2e-3 or nil,
                               csv = outdir .. "/berea_" .. tag .. "_" .. i .. ".csv" })
    local rm = 0
    for _, b in ipairs(pk.balls) do rm = rm + b[3] / #pk.balls end
    local gc = pk.grain_counts or { #pk.balls }
    gc = { gc[1] or 0, gc[2] or 0, gc[3] or 0 }
    return { seed = i, balls = #pk.balls, porosity = pk.porosity, ucs = r.ucs, E = r.E, E50 = r.E50,
             nu = r.nu, rmean = rm, k = r.ucs * rm / Fn, tension = r.breaks.tension,
             shear = r.breaks.shear, f1 = gc[1] / #pk.balls, f2 = 2 * gc[2] / #pk.balls,
             f3 = 3 * gc[3] / #pk.balls, bonds = r.bonds }
end)
-- A seed that failed is left out of the table and the statistics, and said so (M.finished).
res = M.finished(res, n)
local function stats(key) return M.mean_sd(res, key) end
print("seed balls porosity  UCS[MPa]  E[GPa]  E50[GPa]  nu     UCS*R/Fn  breaks(t/s)  bonds  balls in grains of 1/2/3")
for _, r in ipairs(res) do
    print(string.format("%4d %5d  %.3f   %7.2f  %6.2f  %6.2f  %.3f  %.4f   %d/%d  %5d  %.3f/%.3f/%.3f", r.seed,
        r.balls, r.porosity, r.ucs / 1e6, r.E / 1e9, r.E50 / 1e9, r.nu, r.k, r.tension, r.shear, r.bonds,
        r.f1, r.f2, r.f3))
end
local u, su = stats("ucs"); local e, se = stats("E"); local nu, snu = stats("nu"); local k, sk = stats("k")
print(string.format("mean +- sd: UCS %.2f +- %.2f MPa, E %.2f +- %.2f GPa, nu %.3f +- %.3f, UCS*R/Fn %.4f +- %.4f",
    u / 1e6, su / 1e6, e / 1e9, se / 1e9, nu, snu, k, sk))
if elastic then
    print("elastic: unbreakable bonds; 'UCS' is the stress at the 2e-3 axial strain stop, E and nu its tangent over 40-60% of it")
else
    print(string.format("with An's (2006) Fn = 1e9 N, UCS = 40 MPa needs R_mean = %.2f m", k * 1e9 / 40e6))
end
print("stiffness reading: " .. mode .. string.format(" (contact kn %.3g N/m, ks %.3g N/m); grains: ", kn, ks) .. grains)
M.write_csv(outdir .. "/berea_seeds_" .. tag .. ".csv", res, { "seed", "balls", "porosity", "ucs", "E", "E50", "nu", "k",
    "tension", "shear", "bonds", "f1", "f2", "f3" })
