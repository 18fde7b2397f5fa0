-- SPDX-License-Identifier: MIT
--
-- rockfall: the rockfall workflow. Slope profiles split into material zones,
-- optional roughness, rock shapes (balls and clumps), point and line seeders with random
-- distributions, collectors, barriers, per-rock impacts and trajectories, end rules, mass
-- release and a Monte Carlo driver. docs/rockfall.md is the user's page; this header is the map, and
-- the parts are one file each in this folder:
--   check.lua          input checks; errors named by the entry point, at the user's line
--   random.lua         each rock's random streams (splitmix64, talus_util.random)
--   distributions.lua  quantities as numbers or distributions, drawn truncated
--   profile.lua        profiles: CSV, checks, material zones, roughness, ground height
--   shapes.lua         rock shapes and the rock of one draw
--   analysis.lua       rockfall.analysis{}: every option checked; rockfall.describe
--   draw.lua           everything random about one rock (rockfall.sample)
--   model.lua          a rock's model: slope walls by material, the rock body
--   tracking.lua       the engine's tracker of a rock, its events and its record
--   run.lua            rockfall.run_rock: one rock alone
--   mass_release.lua   rockfall.mass_release: rocks together
--   output.lua         the per-rock CSV files, rockfall.summary
--   monte_carlo.lua    rockfall.monte_carlo: all rocks on all cores, n of them or until named
--                      statistics are known to a stated precision
--   precision.lua      the statistics monte_carlo can be asked for, checked and estimated
--   report.lua         what a Monte Carlo writes and says: CSVs, statistics, precision, notes
--   stats/             the Monte Carlo statistics (rockfall.stats, also require("rockfall_stats"))
--
--   local rockfall = require("rockfall")
--   local an = rockfall.analysis{ profile = {...}, materials = {...}, zones = {...},
--                                 seeders = {...}, collectors = {...}, barriers = {...}, seed = 1 }
--   local rec = rockfall.run_rock(an, 1)                  -- one independent rock
--   local recs = rockfall.monte_carlo(an, { n = 300, outdir = "out" })
--   local recs = rockfall.mass_release(an, { n = 50 })     -- rocks together, rock-rock contact
--
-- Units SI (m, kg, s, J, rad, rad/s); 2D bodies of unit thickness, so a rock's "volume" is its
-- area [m^2] and its mass density x area. Profiles run toward +x: rocks travel to larger x.
--
-- Every random draw of rock i comes from generators seeded by (analysis seed, i, purpose), so a
-- rock does not depend on how many rocks the analysis has, on their order, or on how they are
-- shared among workers (talus.map).

local K = require("rockfall.check")
local Rand = require("rockfall.random")
local Dist = require("rockfall.distributions")
local P = require("rockfall.profile")
local Shapes = require("rockfall.shapes")
local An = require("rockfall.analysis")
local Draw = require("rockfall.draw")
local Run = require("rockfall.run")
local Mass = require("rockfall.mass_release")
local Out = require("rockfall.output")
local Mc = require("rockfall.monte_carlo")
local api = K.api

return {
    version = Mc.VERSION,
    -- random numbers and distributions
    rng = api("rng", Rand.rng), rock_seed = Rand.rock_seed, stream = api("stream", Rand.stream),
    bounds = Dist.bounds, draw = api("draw", Dist.draw),
    -- profiles and shapes
    ground = P.ground_at, read_csv = api("read_csv", P.read_csv), roughen = api("roughen", P.roughen),
    union_area = Shapes.union_area, shapes = Shapes.SHAPES,
    -- the analysis and its rocks
    analysis = api("analysis", An.analysis), describe = An.describe, dp_nratio = An.dp_nratio,
    sample = api("sample", function(an, i)
        K.need_analysis(an)
        return Draw.sample(an, i)
    end),
    run_rock = api("run_rock", Run.run_rock), mass_release = api("mass_release", Mass.mass_release),
    monte_carlo = api("monte_carlo", Mc.monte_carlo),
    -- output
    write_csv = api("write_csv", Out.write_csv), summary = Out.summary,
    stats = require("rockfall.stats"),
}
