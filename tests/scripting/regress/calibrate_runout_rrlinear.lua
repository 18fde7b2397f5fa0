-- Rolling friction from a run-out (docs/rockfall-calibration.md): the fit of rrlinear's rr_fric
-- from the run-out of a disk rolling on a bench recovers the value that made it. The run-out of
-- a disk under the rolling moment rr_fric R Fn is d = (1 + I/(m R^2)) v0^2 / (2 rr_fric g)
-- (docs/models/rrlinear.md); the elastic start-up of the rolling spring shifts it by ~4e-6
-- relative there, so 1e-3 leaves the fit's bracketing tolerance room and still fails if the
-- fit or the plugin's limit is off by a few per mille.
local T = require("testlib")
local C = require("calibrate")
local v0, g, rr = 2, 9.81, 0.3
local d = 1.5 * v0 * v0 / (2 * rr * g) -- disk: (1 + 1/2) v0^2 / (2 rr_fric g)
local val = C.fit_runout{ model = "rrlinear", prop = "rr_fric", measured = d, lo = 0.01, hi = 2,
    props = { kn = 1e8, ks = 5e7, fric = 0.6 }, rock = "ball", v0 = v0, radius = 0.1 }
T.near(val, rr, 1e-3 * rr, "rr_fric from run-out")
T.done("calibrate_runout_rrlinear")
