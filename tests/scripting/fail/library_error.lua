-- SPDX-License-Identifier: MIT
-- An engine function's error met inside a library (talus.map inside rockfall.monte_carlo) is
-- reported at this script's line, named by the library's entry point.
local rockfall = require("rockfall")
local an = rockfall.analysis{ profile = { { 0, 5 }, { 5, 0 }, { 20, 0 } },
    seeders = { { kind = "point", at = { 0.5, 5.6 }, rock = { shape = "ball", radius = 0.2 } } } }
rockfall.monte_carlo(an, { n = 1, jobs = 0 })
print("not reached")
