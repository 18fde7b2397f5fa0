-- SPDX-License-Identifier: MIT
--
-- brazilian.lua: Brazilian (diametral compression) test on a bonded disk made by P&C's
-- genesis in a circular vessel (default) or cut from a box packing; sigma_t = 2 F / (pi D t),
-- t = 1 m (ISRM 1978; docs/material.md).
--
--   talus run scripts/examples/brazilian.lua [outdir] [seed] [jaws] [disk] [--rate=R] [--max-steps=N]
--
-- jaws = curved (default: the ISRM jaws of radius 1.5 R, M.make_jaws) or flat (platens).
-- disk = vessel (default: M.genesis_disk, a 29.4 mm vessel) or cut (M.disk: the balls of a
-- 30 x 30 mm box packing inside the 29.4 mm circle, the disk of before).
-- Same micro-properties as scripts/examples/ucs.lua (An 2006 appendix B contact bonds,
-- strength scaled to the ball size). --rate: the axial strain per P-wave crossing (default
-- M.strain_per_crossing); --max-steps: the test's step cap (default: 2% strain at the rate).
local M = require("material")
local args, opt = require("talus_util.options").command_line(arg, { "rate", "max-steps" })
local outdir = args[1] or "out"
local seed = tonumber(args[2] or "1")
local jaws = args[3] or "curved"
local disk = args[4] or "vessel"
if disk ~= "vessel" and disk ~= "cut" then error("brazilian.lua: disk = '" .. disk .. "' (known: vessel, cut)") end
talus.mkdir(outdir)
local pk
if disk == "vessel" then
    pk = M.genesis_disk{ diameter = 0.98 * 0.03, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16,
                         kn = 6.4e10, ks = 9.6e9, density = 2600, seed = seed }
else
    pk = M.genesis{ width = 0.03, height = 0.03, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16,
                    kn = 6.4e10, ks = 9.6e9, density = 2600, seed = seed }
end
local sp = M.specimen(pk, { model = "cbond", kn = 6.4e10, ks = 9.6e9, fric = 0.5, density = 2600,
                            bond = { cb_tenf = 4.6e4, cb_shearf = 4.6e5 }, seed = seed,
                            -- jaw/platen friction: with smooth flat platens the disk, held at two
                            -- single balls, slid out sideways after the first break under a platen
                            platen = { fric = 0.5 } },
                      { balls = M.disk(pk), jaws = jaws })
local csv = outdir .. "/brazilian_history.csv"
-- the test stops at the split (docs/material.md "Brazilian test")
local r = M.brazilian(sp, { csv = csv, strain_per_crossing = opt.rate, max_steps = opt["max-steps"] })
print(string.format("disk (%s) D = %.2f mm, %d balls, %d bonds, %s jaws", disk == "vessel" and "made in a vessel" or "cut",
    r.diameter * 1e3, r.balls, sp.bonds, r.jaws))
print(string.format("peak force %.4g N per m of thickness -> 2F/(pi D t) = %.3f MPa (stopped: %s)",
    r.force, r.peak / 1e6, r.stop))
print(string.format("%d steps, breaks: %d tension, %d shear", r.steps, r.breaks.tension, r.breaks.shear))
local f = r.fracture
print(string.format("fracture: %d breaks, %.0f%% within 0.1 D of the loaded diameter, crack along %.0f%% of it, " ..
    "%.1f degrees off it: %s", f.n, 100 * f.band, 100 * f.cover, f.angle or 0 / 0,
    f.split and "split" or (f.crush and "crushed at a jaw" or "not a split")))
print(r.valid and "valid: the disk split along the loaded diameter"
    or ("NOT VALID, the number above is not a tensile strength: " .. r.reason))
-- the disk and its cracks (m:picture, docs/output.md); the crack list is in the CSV beside the
-- history
local ok_pic, why = pcall(function()
    sp.model:picture{ file = outdir .. "/brazilian_disk.png", size = { 700, 744 }, color = "none", cracks = true,
                      title = string.format("Brazilian disk (%s), %s jaws: %d cracks", disk, r.jaws, #r.cracks) }
end)
print(ok_pic and ("picture: " .. outdir .. "/brazilian_disk.png, cracks: " .. outdir .. "/brazilian_history_cracks.csv")
    or ("picture: failed (" .. tostring(why) .. ")"))
