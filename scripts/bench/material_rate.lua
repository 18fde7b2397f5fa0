-- SPDX-License-Identifier: MIT
--
-- material_rate.lua: what makes the flat-jointed Lac du Bonnet's UCS depend on the loading rate
-- (docs/results/material.md, "The loading rate"). A UCS test whose platens this script moves
-- itself (constant speed after a linear ramp), with a row every `every` steps that records what
-- a quasi-static test must keep small: the platen stress difference (top - bottom over their
-- mean), the kinetic over the stored (strain + bond) energy, PFC's mechanical ratio (mean
-- unbalanced force over mean contact force) and the bond breaks. With `hold_at` the platens stop
-- at that axial strain and the specimen is left to relax for `hold_steps` steps: how far the
-- stress falls, and how long that takes, is the part of the stress the loading rate added.
--
--   talus run scripts/bench/material_rate.lua OUTDIR [scale] [seed] [rate] [damp] [hold_at] [hold_steps]
--
--   rate      axial strain per P-wave crossing of the specimen (2e-5: the rate before this study)
--   damp      PFC local damping (0.7)
--   hold_at   axial strain at which the platens stop (default: never)
-- The packing is made once and kept in OUTDIR/pk_<scale>_<seed>.lua. Writes
-- OUTDIR/rate_<scale>_<seed>_<rate>_<damp>[_hold<strain>].csv and prints one RESULT line: the
-- UCS, the peak strain, the steps, and over the rows above half the peak the largest and mean
-- platen difference, kinetic/stored energy and ratio, and the breaks per P-wave crossing over
-- the tenth of the test before the peak.
--
--   talus run scripts/bench/material_rate.lua OUTDIR seeds [scale] [rate] [nseeds] [material] [hold]
--
-- The work-precision check of the default rate: M.run_seeds (a UCS and a Brazilian test per seed,
-- the examples' code) on seeds 1..nseeds at `rate` (default M.strain_per_crossing) and at half of
-- it, on the same packings (kept in OUTDIR/ck_*); `hold` loads with the platens' equilibrium
-- hold (M.hold's settings). Prints per seed the UCS at both rates, E, the
-- quasi-static measure and the Brazilian outcome, then one RESULT line: the change of the mean
-- UCS when the rate halves, how many disks gave a valid sigma_t at each rate, and the CPU (the
-- tests' own clocks, which a loaded machine stretches less than the wall clock).
local M = require("material")
if arg[2] == "seeds" then
    local outdir, scale = arg[1], tonumber(arg[3] or "0.5")
    local rate, n, kind = tonumber(arg[4] or tostring(M.strain_per_crossing)), tonumber(arg[5] or "5"), arg[6] or "fjoint"
    local hold = arg[7] == "hold" or nil
    talus.mkdir(outdir)
    local mat, genesis, disk = M.lac_du_bonnet(kind, M.ldb_calibrated[kind])
    local seeds = {}
    for i = 1, n do seeds[i] = i end
    local runs = {}
    for k, r in ipairs { rate, 0.5 * rate } do
        runs[k] = M.run_seeds{ material = mat, genesis = genesis, disk = disk, seeds = seeds, scale = scale,
                               strain_per_crossing = r, hold = hold,
                               checkpoint = string.format("%s/ck_%g", outdir, r),
                               key = string.format("%s scale %g", kind, scale) }
    end
    local function stat(res, key)
        local m, sd, k = M.seeds_stat(res.rows, key)
        return { mean = m, sd = sd, n = k }
    end
    local function valid(res)
        local v = 0
        for _, row in ipairs(res.rows) do v = v + ((row.valid and row.tensile) and 1 or 0) end
        return v
    end
    print(string.format("%s, scale %g, rates %g and %g per P-wave crossing", kind, scale, rate, 0.5 * rate))
    print("seed  UCS(r)  UCS(r/2) [MPa]  change   E(r) [GPa]  dF/F(r)   ratio(r)  held(r)  sigma_t(r)  sigma_t(r/2) [MPa]")
    for i, a in ipairs(runs[1].rows) do
        local b = runs[2].rows[i]
        local function t(row) return row.valid and row.tensile and string.format("%.2f", row.tensile / 1e6)
            or "- (" .. tostring(row.reason) .. ")" end
        print(string.format("%4d  %6.1f  %6.1f          %+6.2f%%  %6.1f      %.1e   %.1e   %7d  %s   %s", a.seed,
            a.ucs / 1e6, b.ucs / 1e6, 100 * (b.ucs / a.ucs - 1), (a.E_elastic or 0) / 1e9, a.qs_difference or 0,
            a.qs_ratio or 0 / 0, a.held or 0, t(a), t(b)))
    end
    local ua, ub = stat(runs[1], "ucs"), stat(runs[2], "ucs")
    local ta, tb = stat(runs[1], "tensile"), stat(runs[2], "tensile")
    print(string.format("RESULT %s scale %g rate %g: mean UCS %.2f +- %.2f MPa, at half the rate %.2f +- %.2f MPa "
        .. "(change %+.2f%%); valid sigma_t %d of %d (%.2f +- %.2f MPa), at half the rate %d of %d (%.2f +- %.2f MPa); "
        .. "CPU %.0f s and %.0f s", kind, scale, rate, ua.mean / 1e6, (ua.sd or 0) / 1e6, ub.mean / 1e6, (ub.sd or 0) / 1e6,
        100 * (ub.mean / ua.mean - 1), valid(runs[1]), n, (ta.mean or 0) / 1e6, (ta.sd or 0) / 1e6, valid(runs[2]), n,
        (tb.mean or 0) / 1e6, (tb.sd or 0) / 1e6, runs[1].cpu, runs[2].cpu))
    return
end
local Wl = require("material.walls")
local E = require("material.equilibrium")

local outdir = arg[1] or "out"
local scale = tonumber(arg[2] or "0.5")
local seed = tonumber(arg[3] or "1")
local per_crossing = tonumber(arg[4] or "2e-5")
local damp = tonumber(arg[5] or "0.7")
local hold_at = tonumber(arg[6] or "1")
local hold_steps = tonumber(arg[7] or "40000")
local ramp, every = 2000, 50
talus.mkdir(outdir)

local mat, genesis = M.lac_du_bonnet("fjoint", M.ldb_calibrated.fjoint)
mat.seed, mat.damp = seed, damp
local file = string.format("%s/pk_%g_%d.lua", outdir, scale, seed)
local pk
local f = io.open(file)
if f then
    f:close()
    pk = M.load_packing(file)
else
    pk = genesis(0.0317 * scale, 0.0634 * scale, seed)
    M.save_packing(pk, file)
end
local sp = M.specimen(pk, mat)
local m = sp.model
local h0 = -Wl.pos(sp.top) - Wl.pos(sp.bottom)
local crossing = h0 / math.sqrt(mat.kn / mat.density)
local v = 0.5 * per_crossing / crossing * h0
local stepper = E.held_stepper(m, 1000)
local breaks = 0
m:on_event("bond_break", function() breaks = breaks + 1 end)

local name = string.format("%s/rate_%g_%d_%g_%g%s.csv", outdir, scale, seed, per_crossing, damp,
    hold_at < 1 and string.format("_hold%g", hold_at) or "")
local out = assert(io.open(name, "w"))
out:write("step,time,strain_axial,stress_axial,platen_top,platen_bottom,platen_difference,kinetic_over_stored,"
    .. "ratio,breaks\n")
local rows, peak, ipeak, held = {}, -math.huge, 0, 0
local s0, t0, c0 = m:step(), m:time(), os.clock()
while true do
    local k = m:step() - s0
    local go = (rows[#rows] and rows[#rows].ea >= hold_at) and 0 or 1
    if go == 0 then held = held + every end
    local fr = math.min(1, (k + 0.5 * every) / ramp) * go
    sp.top.wall.vel, sp.bottom.wall.vel = { 0, -v * fr }, { 0, v * fr }
    stepper.cycle(every)
    local h = -Wl.pos(sp.top) - Wl.pos(sp.bottom)
    local ft, fb = Wl.push(sp.top), Wl.push(sp.bottom)
    local e = m:energies()
    local r = { step = m:step() - s0, time = m:time() - t0, ea = (h0 - h) / h0, sa = 0.5 * (ft + fb) / sp.width,
                dF = (ft - fb) / math.max(1e-300, 0.5 * (ft + fb)), ek = e.kinetic / (e.strain + e.bond),
                ratio = m:unbalanced().ratio, breaks = breaks }
    rows[#rows + 1] = r
    out:write(string.format("%d,%.6g,%.6g,%.6g,%.6g,%.6g,%.4g,%.4g,%.4g,%d\n", r.step, r.time, r.ea, r.sa, ft, fb, r.dF,
        r.ek, r.ratio, breaks))
    if r.sa > peak then peak, ipeak = r.sa, #rows end
    if breaks > 0 and r.sa < 0.8 * peak and r.ea > rows[ipeak].ea then break end
    if r.step > 2000000 or held >= hold_steps then break end
end
out:close()
local n, dmax, dsum, kmax, ksum, qmax, qsum = 0, 0, 0, 0, 0, 0, 0
for i = 1, ipeak do
    local r = rows[i]
    if r.sa >= 0.5 * peak then
        n = n + 1
        dmax, dsum = math.max(dmax, math.abs(r.dF)), dsum + math.abs(r.dF)
        kmax, ksum = math.max(kmax, r.ek), ksum + r.ek
        qmax, qsum = math.max(qmax, r.ratio), qsum + r.ratio
    end
end
local p = rows[ipeak]
local i0 = math.max(1, ipeak - math.max(1, ipeak // 10))
local cracking = (p.breaks - rows[i0].breaks) / ((p.time - rows[i0].time) / crossing)
print(string.format("RESULT scale %g seed %d rate %g damp %g: UCS %.2f MPa at strain %.4g, %d steps (peak at %d), "
    .. "%.0f steps per crossing; above half the peak: platen difference max %.3g mean %.3g, kinetic/stored max %.3g "
    .. "mean %.3g, ratio max %.3g mean %.3g; breaks per crossing before the peak %.1f; CPU %.1f s",
    scale, seed, per_crossing, damp, peak / 1e6, p.ea, rows[#rows].step, p.step, crossing / m:dt(), dmax, dsum / n,
    kmax, ksum / n, qmax, qsum / n, cracking, os.clock() - c0))
