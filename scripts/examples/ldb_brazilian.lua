-- SPDX-License-Identifier: MIT
--
-- ldb_brazilian.lua: Brazilian tests on Lac du Bonnet parallel-bond disks (the micro-properties
-- of scripts/examples/ldb_pbond.lua, M.lac_du_bonnet), made in a circular vessel (default) or
-- cut from ldb_pbond.lua's box packings (genesis seed 100 + i either way), between the ISRM
-- curved jaws (radius 1.5 R, the default of M.brazilian) or flat platens; per seed sigma_t = 2F/(pi D t), t = 1 m, and where the bonds broke (M.fracture:
-- does the disk split along the loaded diameter, or crush under a jaw). docs/material.md,
-- "Brazilian test".
--
--   talus run scripts/examples/ldb_brazilian.lua [outdir] [nseeds] [scale] [jaws] [first_seed] [jaw_angle] [disk]
--
-- disk = vessel (default: made in a circular vessel of diameter 0.98 x 31.7 mm x scale,
-- M.genesis_disk) or cut (the balls of a 31.7 x 31.7 mm x scale box packing of M.genesis
-- inside that circle, M.disk: the disks of ldb_pbond.lua). The vessel disks scatter less and
-- split more often between the curved jaws (docs/results/material.md, "Disks made in a circular
-- vessel"), hence the default. jaw_angle: give 20 (the default) to reach the 7th argument.
--
-- scale 1: 31.1 mm disks (~1 500 balls; cut: ~30.7 mm, ~1 440); 0.5: 15.5 mm (~378 balls; cut:
-- ~14.8 mm, ~345), same ball sizes (P&C: the ball size is not a free parameter, a smaller disk
-- is a different test). jaws = curved | flat.
-- Options: --rate (the axial strain per P-wave crossing, default M.strain_per_crossing),
-- --max-steps (default: the steps that strain the disk by 2% at the rate), --material (pbond-pc,
-- the default: Potyondy & Cundall's parallel bonds; or fjoint, pbond, clumped: M.ldb_calibrated).
-- The test stops at the split (docs/material.md "Brazilian test").
-- Writes OUTDIR/ldb_brazilian_<disk>_<jaws>_<scale>_<seed>.png (balls coloured by the distance
-- to the nearest broken bond, dark = at a break) and ldb_brazilian_<disk>_<jaws>_<scale>.csv.
local M = require("material")
local args, opt = require("talus_util.options").command_line(arg, { "rate", "max-steps", "material" })
local outdir = args[1] or "out"
local n = tonumber(args[2] or "5")
local scale = tonumber(args[3] or "1")
local jaws = args[4] or "curved"
local first = tonumber(args[5] or "1") - 1
local jaw_angle = tonumber(args[6]) -- degrees about the jaw's centre (M.make_jaws; default 20)
local disk = args[7] or "vessel"
local kind = opt.material or "pbond-pc"
if disk ~= "vessel" and disk ~= "cut" then
    error("ldb_brazilian.lua: disk = '" .. disk .. "' (known: vessel, cut)")
end
talus.mkdir(outdir)
-- as ldb_pbond.lua, Brazilian platens/jaws with friction 0.5 (the one change between the two
-- runs compared in docs/results/material.md is the jaw shape)
local mat, genesis, vessel_disk
if kind == "pbond-pc" then
    mat, genesis, vessel_disk = M.lac_du_bonnet("pbond")
elseif M.ldb_calibrated[kind] then
    mat, genesis, vessel_disk = M.lac_du_bonnet(kind, M.ldb_calibrated[kind])
else
    error("ldb_brazilian.lua: material '" .. kind .. "' (known: pbond-pc, fjoint, pbond, clumped)")
end
mat.platen.fric = 0.5
-- The disk's porosity: 1 - (the balls' area) / (pi D^2 / 4), D the ball extent as sigma_t uses
-- it (the same measure for a cut and a vessel disk; a cut disk's rough rim counts as pore).
local function disk_porosity(pts, D)
    local a = 0
    for _, p in ipairs(pts) do a = a + math.pi * p[3] * p[3] end
    return 1 - a / (math.pi * D * D / 4)
end
local res = talus.map(n, function(k)
    local i = first + k
    local t0 = os.clock()
    local pd
    if disk == "vessel" then
        pd = vessel_disk(0.98 * 0.0317 * scale, 100 + i)
    else
        pd = genesis(0.0317 * scale, 0.0317 * scale, 100 + i)
    end
    local md = {}
    for key, v in pairs(mat) do md[key] = v end
    md.seed = i
    local sp_idx = M.disk(pd)
    local sp = M.specimen(pd, md, { balls = sp_idx, jaws = jaws,
                                        jaw_angle = jaws == "curved" and jaw_angle or nil })
    local t1 = os.clock()
    local b = M.brazilian(sp, { strain_per_crossing = opt.rate, max_steps = opt["max-steps"] })
    local fr = b.fracture
    local at = b.breaks_at
    sp.model:picture{ file = string.format("%s/ldb_brazilian_%s_%s_%g_%d.png", outdir, disk, jaws, scale, i),
        color = function(ball)
            local dmin = math.huge
            for _, q in ipairs(at) do
                dmin = math.min(dmin, (ball.pos[1] - q[1]) ^ 2 + (ball.pos[2] - q[2]) ^ 2)
            end
            return math.sqrt(dmin) * 1e3
        end, range = { 0, 1.5 }, label = "distance to a broken bond [mm]", size = { 700, 744 }, cracks = true,
        title = b.valid and string.format("%s disk, %s, seed %d: sigma_t %.1f MPa", disk, jaws, i, b.tensile / 1e6)
            or string.format("%s disk, %s, seed %d: no split (peak %.1f MPa)", disk, jaws, i, b.peak / 1e6) }
    local pts = {}
    for _, k in ipairs(sp_idx) do pts[#pts + 1] = pd.balls[k] end
    return { seed = i, balls = b.balls, porosity = disk_porosity(pts, b.diameter), bonds = sp.bonds,
             D = b.diameter, tensile = b.tensile, peak = b.peak,
             force = b.force, breaks = fr.n, band = fr.band, cover = fr.cover, angle = fr.angle or -1,
             pre_peak = fr.pre_peak, jaw_first = fr.jaw_first, split = fr.split and 1 or 0,
             crush = fr.crush and 1 or 0, steps = b.steps, stop = b.stop, valid = b.valid, reason = b.reason,
             segments = sp.disk.segments or 0,
             -- where the jaws/platens first touch: degrees off the loaded diameter
             contact_top = sp.disk.first_contact[1], contact_bottom = sp.disk.first_contact[2],
             cpu_genesis = t1 - t0, cpu_test = os.clock() - t1 }
end)
-- A seed that failed is left out of the table and the statistics, and said so (M.finished).
res = M.finished(res, n)
print(string.format("LdB Brazilian, %s jaws, scale %g (disk %.1f mm, %s)", jaws, scale, 31.7 * scale * 0.98,
    disk == "vessel" and "made in a circular vessel" or "cut from a box packing"))
print("seed balls porosity bonds D[mm]  sigma_t[MPa] breaks band  cover angle  jaw/pre-peak  split crush  steps  stop       cpu(gen/test)[s]  1st contact top/bottom [deg]")
local nsplit = 0
for _, r in ipairs(res) do
    nsplit = nsplit + r.split
    print(string.format("%4d %5d %.4f %5d %6.2f %10s    %5d  %.2f  %.2f  %5.1f  %3d/%-3d       %d     %d   %6d  %-9s  %.0f/%.0f           %6.1f %6.1f",
        r.seed, r.balls, r.porosity, r.bonds, r.D * 1e3, r.tensile and string.format("%.2f", r.tensile / 1e6)
        or string.format("(%.2f)*", r.peak / 1e6), r.breaks, r.band, r.cover, r.angle,
        r.jaw_first, r.pre_peak, r.split, r.crush, r.steps, r.stop, r.cpu_genesis, r.cpu_test,
        r.contact_top, r.contact_bottom))
end
local t, st, nvalid = M.mean_sd(res, "tensile")
local ncrush = 0
for _, r in ipairs(res) do ncrush = ncrush + r.crush end
print(string.format("sigma_t %.2f +- %.2f MPa (mean +- sd over the %d valid tests of %d seeds); %d of %d split along the "
    .. "loaded diameter, %d crushed", t / 1e6, st / 1e6, nvalid, #res, nsplit, #res, ncrush))
for _, r in ipairs(res) do
    if not r.valid then print(string.format("seed %d not valid: %s", r.seed, r.reason)) end
end
M.write_csv(string.format("%s/ldb_brazilian_%s_%s_%g.csv", outdir, disk, jaws, scale), res,
    { "seed", "balls", "porosity", "bonds", "D", "tensile", "peak", "valid", "reason", "force", "breaks", "band", "cover", "angle", "pre_peak",
      "jaw_first", "split", "crush", "steps", "cpu_genesis", "cpu_test", "contact_top", "contact_bottom" })
