-- SPDX-License-Identifier: MIT
--
-- ucs_5000.lua: timing of the UCS workflow on a ~5000-ball bonded specimen, per phase
-- (docs/results/benchmarks-history.md "UCS"). One process, one core.
--
--   talus run scripts/bench/ucs_5000.lua [outdir] [width] [height] [floater_passes] [v (verbose genesis)]
--
-- R 0.5-0.83 mm, about 470 balls per 20 x 40 mm: width 0.065 m, height 0.13 m gives ~5000
-- balls (the defaults, 32.5 x 65 mm, ~1200 balls, are a quicker check).
local M = require("material")
local outdir = arg[1] or "out"
talus.mkdir(outdir)
local W, H = tonumber(arg[2] or "0.0325"), tonumber(arg[3] or "0.065")
local c0 = os.clock()
local pk = M.genesis{ width = W, height = H, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16,
                      kn = 6.4e10, ks = 9.6e9, density = 2600, seed = 1,
                      floater_passes = tonumber(arg[4]), -- default 3 move/grow passes; 0: rattlers deleted only
                      verbose = arg[5] == "v" }
local c1 = os.clock()
local sp = M.specimen(pk, { model = "cbond", kn = 6.4e10, ks = 9.6e9, fric = 0.5, density = 2600,
                            bond = { cb_tenf = 4.6e4, cb_shearf = 4.6e5 } })
local c2 = os.clock()
-- max_steps well above the ~40 000 steps to 80% post-peak at this size (M.compress's default
-- of 30 000 ended the test before the peak: 29 550 steps to the peak at 1.3 1/s)
local r = M.compress(sp, { post_peak = 0.8, max_steps = 200000, csv = outdir .. "/ucs_5000.csv" })
local c3 = os.clock()
print(string.format("balls %d bonds %d porosity %.3f; floaters moved/grown %d, deleted %d, chain links kept %d; wall stresses %.3g %.3g %.3g %.3g Pa",
    #pk.balls, sp.bonds, pk.porosity, pk.floaters, pk.deleted, pk.chain_links, pk.stress[1], pk.stress[2], pk.stress[3], pk.stress[4]))
print(string.format("genesis %.1f s (place %.2f, expand %.1f, stress %.1f, floaters %.1f; %d steps)",
    c1 - c0, pk.timing.place, pk.timing.expand, pk.timing.stress, pk.timing.floaters, pk.steps))
print(string.format("bond+relax %.1f s (%d relax steps)", c2 - c1, sp.relax_steps))
print(string.format("test %.1f s (%d steps, stop: %s)", c3 - c2, r.steps, r.stop))
print(string.format("total %.1f s; UCS %.2f MPa E %.2f GPa nu %.3f", c3 - c0, r.ucs / 1e6, r.E / 1e9, r.nu))
print("genesis engine profile:\n" .. pk.profile)
print("bond + relax + test engine profile:\n" .. sp.model:profile())
