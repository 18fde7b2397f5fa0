-- SPDX-License-Identifier: MIT
-- calibrate.fit_runout: a contact property from a measured run-out distance. The rolling-friction
-- model `rrlinear` (property rr_fric) is another helper's plugin; this test checks the generic
-- function with what exists: `linear`'s friction `fric` from the run-out of a sliding block (two
-- touching pebbles on a bench, which cannot roll): d = v0^2 / (2 g mu) on a flat bench.
local T = require("testlib")
local C = require("calibrate")

local v0, g, mu = 2, 9.81, 0.4
local measured = v0 * v0 / (2 * g * mu)      -- 0.5097 m
local value, info = C.fit_runout{ model = "linear", prop = "fric", measured = measured,
    lo = 0.05, hi = 2, props = { kn = 1e8, ks = 5e7 }, rock = "pair", v0 = v0, radius = 0.1 }
-- The sliding decelerates at mu g exactly (Coulomb, rigid-body closed form, docs/models/linear.md
-- incline tests to 2e-12); the run-out differs from v0^2/(2 mu g) by the spring's start-up and
-- the stop test (speed <= 1e-4 v0: distance missed < 1e-8 d): a 0.5 % bound on mu is generous.
T.near(value, mu, 5e-3 * mu, "fric from run-out")
T.near(info.distance, measured, 1e-3 * measured, "run-out reached")

-- an unknown model is refused by name
T.fails(function() C.fit_runout{ model = "no_such_model", prop = "x", measured = 1, lo = 0.1, hi = 1 } end,
    { "calibrate.fit_runout", "no_such_model" }, "unknown model")

T.done("calibrate_runout")
