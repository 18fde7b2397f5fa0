-- SPDX-License-Identifier: MIT
--
-- ucs.lua: make a bonded specimen (P&C 2004 genesis), crush it between platens, print UCS,
-- E and Poisson's ratio, write the history CSV and a stress-strain plot (docs/material.md).
--
--   talus run scripts/examples/ucs.lua [outdir] [seed] [--rate=R] [--max-steps=N]
--
-- --rate: the loading rate as the axial strain per P-wave crossing of the specimen (default
-- M.strain_per_crossing, docs/material.md "Loading rate"); --max-steps: the test's step cap
-- (default: the steps that strain it by 2% at the rate).
--
-- Material: An (2006) appendix B's contact-bond micro-properties (kn 6.4e10 N/m, ks 9.6e9 N/m,
-- fric 0.5, density 2600, shear/normal bond strength 10) on a 20 x 40 mm specimen of ~470
-- balls (R 0.5-0.83 mm). A contact bond's strength is a force, so the UCS scales as strength /
-- ball size in 2D; the normal strength here, 4.6e4 N, is the one that gives about 40 MPa at this
-- ball size (docs/results/material.md, "Berea sandstone").

local M = require("material")
local args, opt = require("talus_util.options").command_line(arg, { "rate", "max-steps" })
local outdir = args[1] or "out"
local seed = tonumber(args[2] or "1")
talus.mkdir(outdir)

local t0 = os.clock()
local pk = M.genesis{ width = 0.02, height = 0.04, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16,
                      kn = 6.4e10, ks = 9.6e9, density = 2600, seed = seed }
M.save_packing(pk, outdir .. "/ucs_packing.lua") -- reuse: M.load_packing(file)
local t_gen = os.clock() - t0
print(string.format("genesis: %d balls, porosity %.3f, %d floaters moved/grown, %d deleted, %.1f s",
    #pk.balls, pk.porosity, pk.floaters, pk.deleted, t_gen))

t0 = os.clock()
local sp = M.specimen(pk, { model = "cbond", kn = 6.4e10, ks = 9.6e9, fric = 0.5, density = 2600,
                            bond = { cb_tenf = 4.6e4, cb_shearf = 4.6e5 }, seed = seed })
print(string.format("specimen: %d bonds, relaxed in %d steps, %.1f s", sp.bonds, sp.relax_steps,
    os.clock() - t0))

local csv = outdir .. "/ucs_history.csv"
local r = M.compress(sp, { post_peak = 0.8, csv = csv, strain_per_crossing = opt.rate, max_steps = opt["max-steps"] })
print(string.format("UCS %.2f MPa   E %.2f GPa (tangent at 50%% of peak; secant E50 %.2f GPa)   nu %.3f",
    r.ucs / 1e6, r.E / 1e9, r.E50 / 1e9, r.nu))
print(string.format("peak axial strain %.4g, strain rate %.3g 1/s, %d steps, breaks: %d tension, %d shear, %.1f s",
    r.peak_strain, r.rate, r.steps, r.breaks.tension, r.breaks.shear, r.time))
local q = r.quasi_static
print(string.format("quasi-static at the peak: platen stress difference %.2g of the stress, kinetic/stored energy %.2g",
    q.difference_peak, q.kinetic_peak or 0 / 0))

-- the plot, with the project's plot tool (needs python3-matplotlib)
local src = debug.getinfo(1, "S").source:sub(2)
local tool = (src:match("^(.*)/examples/[^/]*$") or "scripts") .. "/plot_history.py"
local png = outdir .. "/ucs_stress_strain.png"
local cmd = string.format("python3 '%s' '%s' -o '%s' --x strain_axial --columns 'stress_axial [Pa]' "
    .. "--stress-unit MPa --xlabel 'axial strain' --ylabel 'axial stress [MPa]' --title 'UCS test (E tangent at 50%% of peak)'", tool, csv, png)
if os.execute(cmd) then print("plot: " .. png) else print("plot: failed (" .. cmd .. ")") end

print(string.format("cracks: %d listed in %s/ucs_history_cracks.csv; crack damage threshold %.2f MPa (%.0f%% of UCS)",
    #r.cracks, outdir, r.crack_damage.stress / 1e6, 100 * r.crack_damage.stress / r.ucs))

-- A picture of the crushed specimen with its force chains and cracks (m:picture, docs/output.md).
local ok_pic, why = pcall(function()
    sp.model:picture{ file = outdir .. "/ucs_specimen.png", size = {600, 1000}, contacts = "force", cracks = true,
                      color = "none",
                      title = string.format("UCS specimen at %d%% post-peak (%d bond breaks)",
                          80, r.breaks.tension + r.breaks.shear) }
end)
print(ok_pic and ("picture: " .. outdir .. "/ucs_specimen.png") or ("picture: failed (" .. tostring(why) .. ")"))
