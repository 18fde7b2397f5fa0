-- SPDX-License-Identifier: MIT
-- material.brazilian on a small bonded disk: sigma_t = 2 F / (pi D t) from the recorded platen
-- force, the disk is the cut asked for, the test has a peak, and the disk is weaker in tension
-- than the same material in compression.
local T = require("testlib")
local M = require("material")

local pk = M.genesis{ width = 0.014, height = 0.014, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16,
                      kn = 6.4e10, ks = 9.6e9, seed = 5 }
local d = 0.0125
local idx = M.disk(pk, d)
-- jaws with friction 0.5, as in scripts/examples/brazilian.lua: a disk held between smooth
-- platens at one ball each may slide or roll out sideways instead of splitting (docs/material.md
-- "Brazilian test"; seen here on the packing of the move/grow genesis: no break in 60 000 steps).
-- The disk gets the default curved jaws; material_brazilian_jaws.lua tests them in detail.
local mat = { model = "cbond", kn = 6.4e10, ks = 9.6e9, fric = 0.5, density = 2600,
              bond = { cb_tenf = 4.6e4, cb_shearf = 4.6e5 }, platen = { fric = 0.5 } }
local sp = M.specimen(pk, mat, { balls = idx })
T.check(sp.model:ball_count() == #idx, "disk balls")
T.check(sp.jaws == "curved", "curved jaws by default")
local r = M.brazilian(sp, { post_peak = 0.7, strain_per_crossing = 2e-5 })
T.check(r.stop == "post_peak", "stopped by " .. r.stop)
-- the disk's extent is the cut diameter less at most one largest ball diameter (balls are kept
-- when wholly inside)
T.check(r.diameter <= d and r.diameter > d - 2 * 0.83e-3, "diameter " .. r.diameter)
-- the formula, t = 1 m: exact (same floating-point expression up to the order of operations)
T.near(r.peak, 2 * r.force / (math.pi * r.diameter), 1e-12, "2F/(pi D)")
T.check(r.tensile == (r.valid and r.peak or nil), "tensile: the peak when valid, else nil")
-- the fracture record: every break listed, fractions in [0, 1]
local f = r.fracture
T.check(f.n == #r.breaks_at and f.n == r.breaks.tension + r.breaks.shear, "breaks listed")
T.check(f.band >= 0 and f.band <= 1 and f.cover >= 0 and f.cover <= 1 and f.pre_peak <= f.n, "fracture fractions")
-- the force is the mean of the two platen forces at the peak row; both platens carry the load
T.check(r.force > 0, "force")
-- contact-bonded disks: tensile strength well below the UCS of the same packing and bonds
-- (P&C and PFC: UCS / sigma_t of bonded-particle models is 3-10; we accept > 1.5)
local sp2 = M.specimen(pk, mat)
local u = M.compress(sp2, { post_peak = 0.8, strain_per_crossing = 2e-5 })
T.check(u.ucs > 1.5 * r.peak, string.format("UCS %.3g vs the disk's peak %.3g", u.ucs, r.peak))
print(string.format("material_brazilian: %d checks; sigma_t %.2f MPa, UCS %.2f MPa, %d balls in the disk",
    T.checks, r.peak / 1e6, u.ucs / 1e6, #idx))
