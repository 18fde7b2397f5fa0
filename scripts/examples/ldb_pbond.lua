-- SPDX-License-Identifier: MIT
--
-- ldb_pbond.lua: the Lac du Bonnet granite parallel-bond example (the micro-properties of
-- Potyondy & Cundall 2004): UCS, E, nu and Brazilian tensile strength over seeds, with their
-- scatter (docs/results/material.md, "Lac du Bonnet"). A Brazilian test that did not split is marked *
-- and left out of sigma_t (M.brazilian's `valid`).
--
--   talus run scripts/examples/ldb_pbond.lua [outdir] [nseeds] [scale] [first_seed] [--rate=R]
--       [--max-steps=N]
--
-- --rate: the loading rate as the axial strain per P-wave crossing (default
-- M.strain_per_crossing, docs/material.md "Loading rate"); --max-steps: each test's step cap
-- (default: the steps that strain the specimen by 2% at the rate).
--
-- Needs the pbond plugin (the bonds are installed by m:bond). scale < 1 shrinks the specimen
-- (0.5: 15.9 x 31.7 mm, ~1000 balls) when time is short: P&C note that the ball size is not a
-- free parameter (it sets the fracture toughness), so a smaller specimen at the same R_min is
-- a different, noisier test, not a faster copy.
local M = require("material")
local args, opt = require("talus_util.options").command_line(arg, { "rate", "max-steps" })
local outdir = args[1] or "out"
local n = tonumber(args[2] or "5")
local scale = tonumber(args[3] or "1")
local first = tonumber(args[4] or "1") - 1 -- seeds first .. first + nseeds - 1
local loading = { strain_per_crossing = opt.rate, max_steps = opt["max-steps"] }
talus.mkdir(outdir)
local mat, genesis, disk = M.lac_du_bonnet()
local res = talus.map(n, function(k)
    local i = first + k
    local pk = genesis(0.0317 * scale, 0.0634 * scale, i)
    local m = {}
    for k, v in pairs(mat) do m[k] = v end
    m.seed = i
    local u = M.compress(M.specimen(pk, m), { post_peak = 0.8, csv = outdir .. "/ldb_ucs_" .. i .. ".csv",
                                              strain_per_crossing = loading.strain_per_crossing,
                                              max_steps = loading.max_steps })
    -- The Brazilian disk is made in a circular vessel (M.genesis_disk, as brazilian.lua and
    -- ldb_brazilian.lua): its rim balls touch its circle, so the curved jaws load it over an
    -- arc. A disk cut from a box packing has a rim as rough as a ball and was loaded at one ball
    -- (at full size seed 1 gave 1.62 MPa beside 20.5 MPa for seed 2, docs/results/material.md). Jaws
    -- with friction 0.5: between smooth ones a disk slid or rolled out sideways.
    local pd = disk(0.98 * 0.0317 * scale, 100 + i)
    local md = {}
    for k, v in pairs(m) do md[k] = v end
    md.platen = { kn = mat.platen.kn, ks = mat.platen.ks, fric = 0.5 }
    local b = M.brazilian(M.specimen(pd, md, { balls = M.disk(pd) }), loading)
    -- tensile is nil for a disk that did not split (M.brazilian): no ratio then
    return { seed = i, balls = #pk.balls, porosity = pk.porosity, ucs = u.ucs, E = u.E, nu = u.nu,
             tensile = b.tensile, peak = b.peak, ratio = b.tensile and u.ucs / b.tensile, stop = u.stop .. "/" .. b.stop,
             deleted = pk.deleted, links = pk.chain_links, steps = u.steps, valid = b.valid,
             reason = b.reason }
end)
-- UCS, E, nu over every seed; sigma_t (and UCS/sigma_t) over the Brazilian tests that split
local function stats(key)
    if key == "tensile" or key == "ratio" then return M.mean_sd(res, key) end
    local all = {}
    for k, r in ipairs(res) do all[k] = { [key] = r[key] } end
    return M.mean_sd(all, key)
end
print("seed balls porosity UCS[MPa] E[GPa]  nu     sigma_t[MPa] UCS/sigma_t  stop(UCS/Brazilian) UCS-steps deleted links")
for _, r in ipairs(res) do
    print(string.format("%4d %5d  %.3f   %7.1f %6.1f  %.3f  %10s    %5s        %-20s %6d %4d %3d", r.seed, r.balls,
        r.porosity, r.ucs / 1e6, r.E / 1e9, r.nu, r.tensile and string.format("%.2f", r.tensile / 1e6)
        or string.format("(%.2f)*", r.peak / 1e6), r.ratio and string.format("%.1f", r.ratio) or "-", r.stop, r.steps,
        r.deleted, r.links))
end
local u, su = stats("ucs"); local e, se = stats("E"); local nu, snu = stats("nu"); local t, st, nt = stats("tensile")
print(string.format("mean +- sd (%d seeds): UCS %.1f +- %.1f MPa, E %.1f +- %.1f GPa, nu %.3f +- %.3f, sigma_t %.2f +- %.2f MPa "
    .. "(%d valid Brazilian tests)", #res, u / 1e6, su / 1e6, e / 1e9, se / 1e9, nu, snu, t / 1e6, st / 1e6, nt))
for _, r in ipairs(res) do
    if not r.valid then
        print(string.format("* seed %d: no tensile strength (left out of sigma_t and UCS/sigma_t): %s", r.seed,
            r.reason))
    end
end
M.write_csv(outdir .. "/ldb_seeds_" .. (first + 1) .. ".csv", res,
    { "seed", "balls", "porosity", "ucs", "E", "nu", "tensile", "peak", "ratio", "valid", "reason" })
