-- SPDX-License-Identifier: MIT
--
-- talus_util: the small common library the shipped libraries (rockfall, material, calibrate)
-- share, one concern a file in this folder:
--   errors.lua    errors raised at the line of the user's script that called a library
--   options.lua   option tables checked with the engine's did-you-mean; merged copies
--   random.lua    seeded generators (splitmix64; xorshift64* for the material packings)
--   csv.lua       the CSV writer: one cell format, every write checked
--   interp.lua    piecewise-linear interpolation with an explicit rule outside the points
--   stats.lua     quantiles with distribution-free intervals, Wilson's interval, summaries
--   optimize.lua  root finder, Nelder-Mead, two-level designs, least squares
--   response_surface.lua  several parameters fitted to several targets (a design, then
--                 power-law surfaces in a trust region)
--   sequential.lua  a Monte Carlo run until named statistics are known to a stated precision
--                 (looks fixed in advance, intervals corrected for stopping on them)
--
--   local U = require("talus_util")
--   local ok, err = U.csv.write("out/a.csv", { "x", "y" }, { { 1, 0.5 } })
return {
    errors = require("talus_util.errors"),
    options = require("talus_util.options"),
    random = require("talus_util.random"),
    csv = require("talus_util.csv"),
    interp = require("talus_util.interp"),
    stats = require("talus_util.stats"),
    optimize = require("talus_util.optimize"),
    response_surface = require("talus_util.response_surface"),
    sequential = require("talus_util.sequential"),
}
