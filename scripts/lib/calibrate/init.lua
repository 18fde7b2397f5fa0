-- SPDX-License-Identifier: MIT
--
-- calibrate: fit contact-model parameters to a target restitution against impact velocity
-- (An 2006, chapter 6 and appendix C; docs/rockfall-calibration.md).
--
--   local C = require("calibrate")
--   local rn = C.rocfall()                               -- Rn(v) = 0.53 / (1 + (v/9.144)^2)
--   local rig = C.impact_rig{ model = "power", props = { kn = 6.4e10, transition = 3500 },
--                             radius = 0.04 }
--   local rows = C.fit_param{ rig = rig, param = "exponent", lo = 1, hi = 400,
--                             target = rn, velocities = {1, 2, 3} }
--   C.print_table(rows, { "v", "target", "value", "e" })
--
-- The parts, one file each in this folder (the optimisers are talus_util's optimize.lua and
-- response_surface.lua, shared with material.calibrate):
--   C.root(f, a, b, opts)        bracketing root finder (Illinois regula falsi), own code
--   C.target(t)                  a function e(v) from a function or a table {{v, e}, ...}
--   C.rocfall(rn, vref)          RocFall's velocity-scaled restitution (Pfeiffer & Bowen 1989)
--   C.impact_rig{...}            e(params, v) from one impact on talus.impact{}
--   C.clump_drop_rig{...}        e(params, v) of a clump dropped onto a horizontal wall
--   C.fit_param{...}             one parameter per impact velocity (root of e - target)
--   C.fit_lsq{...}               several parameters over a table (least squares, Nelder-Mead)
--   C.fit_linear_dp_nratio{...}  linear's damping ratio for a restitution (rig and closed form)
--   C.follow{...}                what a fixed parameter set gives over a table (auto exp modes)
--   C.runout_rig{...}, C.fit_runout{...}  a property (rrlinear's rr_fric, ...) from a run-out
--   C.fit_apparent_rn{...}       a slope material fitted to a target apparent Rn, on the
--                                analysis' own rocks and slope (apparent.lua)
--   C.nelder_mead(f, x0, step, opts)  the simplex minimiser fit_lsq uses
--   C.design(p)                  a two-level fractional factorial design with a centre point
--   C.fit_targets{...}           several parameters to several targets at once: a design, then
--                                power-law response surfaces in a trust region (expensive,
--                                noisy evaluations such as laboratory tests on a DEM specimen)
--   C.print_table(rows, cols), C.write_csv(file, rows, cols [, number_format])


local Opt = require("talus_util.optimize")
local RS = require("talus_util.response_surface")
local T = require("calibrate.targets")
local Rigs = require("calibrate.rigs")
local Fits = require("calibrate.fits")
local Out = require("calibrate.output")
local App = require("calibrate.apparent")

return {
    -- optimisers
    root = Opt.root, nelder_mead = Opt.nelder_mead, design = Opt.design, lsq = Opt.lsq,
    fit_targets = RS.fit_targets,
    -- targets and rigs
    rocfall = T.rocfall, target = T.target,
    impact_rig = Rigs.impact_rig, triangle_pebbles = Rigs.triangle_pebbles,
    clump_drop_rig = Rigs.clump_drop_rig, runout_rig = Rigs.runout_rig,
    -- fits
    fit_param = Fits.fit_param, fit_lsq = Fits.fit_lsq, linear_beta = Fits.linear_beta,
    linear_e = Fits.linear_e, fit_linear_dp_nratio = Fits.fit_linear_dp_nratio, follow = Fits.follow,
    fit_runout = Fits.fit_runout, fit_apparent_rn = App.fit_apparent_rn, apparent_rn = App.apparent_rn,
    -- output
    print_table = Out.print_table, write_csv = Out.write_csv,
}
