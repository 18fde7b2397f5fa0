-- SPDX-License-Identifier: MIT
-- The Monte Carlo that interrupt_test.py stops with Ctrl-C and then resumes: disks released onto
-- a 30 degree slope that roll on along a flat (no rolling resistance) until the time cap, so
-- that every rock takes the same few tens of milliseconds and a batch takes seconds.
--   talus run interrupt_scene.lua OUTDIR N [fresh]
-- "fresh" runs every rock (resume = false): the uninterrupted reference.
local rockfall = require("rockfall")
local outdir, n, fresh = arg[1], math.tointeger(tonumber(arg[2])), arg[3] == "fresh"
local an = rockfall.analysis{
    profile = { { 0, 10 }, { 17.32, 0 }, { 200, 0 } },
    materials = { slope = { model = "linear",
        props = { kn = 1e9, ks = 5e8, fric = 0.5, dp_nratio = rockfall.dp_nratio(0.4) } } },
    seeders = { { kind = "line", from = { 0.5, 11 }, to = { 1.5, 11 },
                  vx = { dist = "uniform", min = 0.5, max = 2 },
                  rock = { shape = "ball", radius = 0.3 } } },
    collectors = { { name = "toe", x = 20 } },
    barriers = { { name = "fence", x = 40, energy = 5e3, height = 2 } },
    seed = 31, t_max = 3,
}
local records = rockfall.monte_carlo(an, { n = n, outdir = outdir, jobs = 2, impacts = true,
    resume = not fresh, quiet = true })
print(string.format("interrupt_scene: %d rocks written", #records))
