-- SPDX-License-Identifier: MIT
--
-- calibrate_granite.lua: a Lac du Bonnet granite fitted to the laboratory's E, nu, UCS and
-- Brazilian tensile strength at once (and its friction angle with `phi`), by M.calibrate
-- (docs/material.md, "Calibration against several targets"): a design of experiments, then
-- power-law response surfaces in a trust region, each point tested on the same packings.
--
--   talus run scripts/examples/calibrate_granite.lua [outdir] [material] [scale] [nseeds] [budget] [phi] [start] [moduli]
--       [--rate=R] [--max-steps=N]
--
--   material  fjoint (default; flat joints, Potyondy 2012), pbond (parallel bonds, Potyondy &
--             Cundall 2004) or clumped (grains of 1-3 balls with parallel bonds, Cho et al. 2007)
--   scale     specimen size factor (0.5: 15.9 x 31.7 mm, ~1 000 balls; the default)
--   nseeds    packings per point (2), seeds 1..nseeds (disks 101..)
--   budget    points at most (15); each point is nseeds x (UCS + Brazilian) tests, plus a biaxial
--             test per seed with `phi`
--   phi       `phi` adds the friction angle (59 deg, tolerance 10%) to the targets; `-` not
--   start     the first point: `default` (M.lac_du_bonnet's values) or a Lua table of
--             parameters, e.g. "{fj_ten = 3e7}"
--   moduli    which E and nu meet the laboratory's: `elastic` (the slopes over 10-30% of the
--             peak, M.compress's E_elastic and nu_elastic; the default for fjoint, whose cracks
--             start at a third of the peak and open the lateral strain by half of it) or `50`
--             (the tangents at 40-60% of the peak; the default for pbond and clumped, which crack
--             above half the peak)
--   --rate    the tests' loading rate, the axial strain per P-wave crossing (default
--             M.strain_per_crossing); --max-steps: each test's step cap (default: 2% strain)
--
-- A point whose Brazilian disks did not split has no sigma_t (nor UCS/sigma_t): its misfit is
-- infinite, the table marks it (disks split 0/n) and the plot too; the calibration says which
-- targets it could not measure.
--
-- Laboratory (Potyondy & Cundall 2004; Martin & Chandler 1994): E 69 +- 5.8 GPa, nu 0.26 +- 0.04,
-- UCS 200 +- 22 MPa, sigma_t 9.3 +- 1.3 MPa; each target's tolerance is that scatter. Runs every
-- test through talus.map (all cores; under mpirun, all ranks), keeps each finished test in
-- OUTDIR/ckpt_<material>_<scale>: run the same command again after an interruption and it goes
-- on from there. Writes OUTDIR/calibrate_<material>.csv (one row per point), a plot of the fit
-- (OUTDIR/calibrate_<material>.png, scripts/plot_calibration.py), and prints the table and the
-- best parameters.
local M = require("material")
local args, opt = require("talus_util.options").command_line(arg, { "rate", "max-steps" })
local outdir = args[1] or "out"
local kind = args[2] or "fjoint"
local scale = tonumber(args[3] or "0.5")
local nseeds = tonumber(args[4] or "2")
local budget = tonumber(args[5] or "15")
local with_phi = args[6] == "phi"
local start = {}
if args[7] and args[7] ~= "default" then
    start = assert(load("return " .. args[7]))()
end
local moduli = args[8] or (kind == "fjoint" and "elastic" or "50")
if moduli ~= "elastic" and moduli ~= "50" then error("calibrate_granite.lua: moduli '" .. moduli .. "' (known: elastic, 50)") end
local E_name, nu_name = "E", "nu"
if moduli == "elastic" then E_name, nu_name = "E_elastic", "nu_elastic" end
talus.mkdir(outdir)

-- the searched parameters (log space), from M.lac_du_bonnet's values unless `start` gives others
local d = M.ldb_defaults[kind]
if not d then error("calibrate_granite.lua: material '" .. kind .. "' (known: fjoint, pbond, clumped)") end
local function from(name) return start[name] or d[name] end
local params
if kind == "fjoint" then
    -- the slit fraction lowers the tensile strength most; near 0.5 the bonded interfaces stop
    -- forming a connected network and the strength falls away, hence its narrow design spread;
    -- the friction of unbonded elements (slits, broken elements) acts in compression only
    params = {
        { name = "fj_emod", lo = 20e9, hi = 400e9, start = from("fj_emod") },
        { name = "fj_kratio", lo = 0.7, hi = 5, start = from("fj_kratio") },
        { name = "fj_ten", lo = 3e6, hi = 300e6, start = from("fj_ten") },
        { name = "fj_coh", lo = 20e6, hi = 3000e6, start = from("fj_coh") },
        { name = "slit", lo = 0.05, hi = 0.5, start = from("slit"), spread = 0.2 },
        { name = "fj_fric", lo = 0.3, hi = 2, start = from("fj_fric") },
    }
else
    params = {
        { name = "emod", lo = 10e9, hi = 300e9, start = from("emod") },
        { name = "kratio", lo = 0.7, hi = 5, start = from("kratio") },
        { name = "pb_ten", lo = 5e6, hi = 1000e6, start = from("pb_ten") },
        { name = "pb_coh", lo = 5e6, hi = 3000e6, start = from("pb_coh") },
    }
end
-- the others stay at their values (start may set them)
local fixed = {}
for k, v in pairs(d) do
    local searched = false
    for _, p in ipairs(params) do searched = searched or p.name == k end
    if not searched then fixed[k] = start[k] or v end
end
local targets = {
    { name = E_name, value = 69e9, tol = 5.8 / 69 },
    { name = nu_name, value = 0.26, tol = 0.04 / 0.26 },
    { name = "ucs", value = 200e6, tol = 22 / 200 },
    { name = "tensile", value = 9.3e6, tol = 1.3 / 9.3 },
}
if with_phi then targets[#targets + 1] = { name = "phi", value = 59, tol = 0.1 } end
local seeds = {}
for i = 1, nseeds do seeds[i] = i end
local W, H, D = 0.0317 * scale, 0.0634 * scale, 0.98 * 0.0317 * scale
local _, genesis, disk = M.lac_du_bonnet(kind)
local fixed_text = {}
for k, v in pairs(fixed) do fixed_text[#fixed_text + 1] = k .. "=" .. string.format("%.17g", v) end
table.sort(fixed_text)
local csv = string.format("%s/calibrate_%s.csv", outdir, kind)
local t0 = os.clock()
local r = M.calibrate{
    material = function(p, seed)
        local mat = M.lac_du_bonnet(kind, p)
        mat.seed = seed
        return mat
    end,
    packing = function(seed) return genesis(W, H, seed) end,
    disk = function(seed) return disk(D, 100 + seed) end,
    params = params, fixed = fixed, targets = targets, seeds = seeds, budget = budget,
    checkpoint = string.format("%s/ckpt_%s_%g", outdir, kind, scale),
    key = string.format("ldb %s scale %g fixed %s moduli %s rate %s v3", kind, scale, table.concat(fixed_text, ","),
        moduli, tostring(opt.rate or M.strain_per_crossing)),
    csv = csv,
    tests = { ucs = { strain_per_crossing = opt.rate, max_steps = opt["max-steps"] },
              brazilian = { strain_per_crossing = opt.rate, max_steps = opt["max-steps"] } },
}
if talus.rank() == 0 then
    local C = require("calibrate")
    local rows = {}
    for _, row in ipairs(r.rows) do
        local t = { point = row.index, phase = row.phase, misfit = row.misfit }
        for k, v in pairs(row.params) do t[k] = v end
        local o = row.out or {}
        t.E = o.E and o.E / 1e9; t.nu = o.nu; t.ucs = o.ucs and o.ucs / 1e6; t.tensile = o.tensile and o.tensile / 1e6
        t.E_el = o.E_elastic and o.E_elastic / 1e9; t.nu_el = o.nu_elastic
        t.ratio = o.ratio; t.phi = o.phi
        -- a point whose disks did not split has no sigma_t (marked, never a number)
        if o.disks then t.disks = string.format("%d/%d", o.tensile_valid, o.disks) end
        rows[#rows + 1] = t
    end
    local cols = { "point", "phase" }
    for _, p in ipairs(params) do cols[#cols + 1] = p.name end
    for _, c in ipairs({ { "E", "E [GPa]" }, { "nu", "nu" }, { "E_el", "E elastic [GPa]" }, { "nu_el", "nu elastic" },
                         { "ucs", "UCS [MPa]" }, { "tensile", "sigma_t [MPa]" },
                         { "disks", "disks split" }, { "ratio", "UCS/sigma_t" }, { "phi", "phi [deg]" },
                         { "misfit", "misfit" } }) do
        cols[#cols + 1] = c
    end
    C.print_table(rows, cols)
    for _, u in ipairs(r.unmeasured) do print("NOT MEASURED: " .. u) end
    local b = r.best
    if b then
        local parts = {}
        for _, p in ipairs(params) do parts[#parts + 1] = string.format("%s = %.4g", p.name, b.params[p.name]) end
        print(string.format("best: point %d (%s), misfit %.4g%s; stopped by %s after %d points (%d tests each)", b.index,
            table.concat(parts, ", "), b.misfit, b.met and ", every target met" or "", r.stop, r.evaluations,
            r.tests_per_point))
    else
        print(string.format("no best point: no point had every target measured (%d points, stopped by %s)",
            r.evaluations, r.stop))
    end
    print("elasticities d ln(output) / d ln(parameter) of the last surfaces:")
    for _, t in ipairs(targets) do
        local e = r.elasticities[t.name]
        if e then
            local s = {}
            for _, p in ipairs(params) do s[#s + 1] = string.format("%s %+.2f", p.name, e[p.name]) end
            print(string.format("  %-8s %s", t.name, table.concat(s, ", ")))
        end
    end
    print(string.format("CPU: %.0f s for the tests and packings (%.0f s packings); this process %.0f s", r.cpu,
        r.packings, os.clock() - t0))
    local src = debug.getinfo(1, "S").source:sub(2)
    local tool = (src:match("^(.*)/examples/[^/]*$") or "scripts") .. "/plot_calibration.py"
    local png = string.format("%s/calibrate_%s.png", outdir, kind)
    -- Debian's python3 has matplotlib (python3-matplotlib); another python3 first on PATH may not
    local f = io.open("/usr/bin/python3")
    local py = f and "/usr/bin/python3" or "python3"
    if f then f:close() end
    local cmd = string.format("%s '%s' '%s' -o '%s' --title 'Lac du Bonnet, %s, scale %g'", py, tool, csv, png, kind,
        scale)
    if os.execute(cmd) then print("plot: " .. png) else print("plot: failed (" .. cmd .. ")") end
end
