-- SPDX-License-Identifier: MIT
--
-- ldb_flatjoint.lua: Lac du Bonnet granite with flat joints (Potyondy 2012; the calibrated
-- micro-parameters of M.lac_du_bonnet("fjoint"), docs/material.md "Lac du Bonnet"): UCS, E, nu,
-- Brazilian tensile strength and UCS/sigma_t over seeds, with their scatter, and with `phi` the
-- friction angle from biaxial tests at 10 and 20 MPa (Mohr-Coulomb over the UCS and those two).
--
--   talus run scripts/examples/ldb_flatjoint.lua [outdir] [nseeds] [scale] [first_seed] [phi] [material]
--       [--rate=R] [--max-steps=N] [--material=NAME]
--
-- The arguments of ldb_pbond.lua: scale < 1 shrinks the specimens (0.5: 15.9 x 31.7 mm, ~1 000
-- balls, and 15.5 mm disks), seeds first_seed .. first_seed + nseeds - 1. `phi` (or `-`) asks for
-- the biaxial tests (two more tests per seed). `material` = fjoint (default), pbond (parallel
-- bonds calibrated the same way), clumped (grains of 1-3 balls with parallel bonds, Cho et al.
-- 2007) or pbond-pc (Potyondy & Cundall's 2004 parallel-bonded material, as ldb_pbond.lua): the
-- same table for each, with the calibrated micro-parameters of M.ldb_calibrated. A Brazilian
-- test that is not valid (M.brazilian: it did not fail, slipped, was crushed, did not split, or
-- peaked after cracking) is marked * and left out of sigma_t. Writes OUTDIR/ldb_<material>_seeds_<first>.csv; every test runs through
-- talus.map (all cores; under mpirun, all ranks).
-- --rate: the loading rate as the axial strain per P-wave crossing of the specimen (default
-- M.strain_per_crossing, docs/material.md "Loading rate"); --max-steps: each test's step cap
-- (default: the steps that strain the specimen by 2% at the rate); --material as the 6th argument;
-- --hold (or --hold=0) loads with (without) the platens' equilibrium hold (docs/material.md,
-- "Loading rate"; off by default); --checkpoint=DIR keeps every packing and test there as it finishes (talus.map): a rerun goes on
-- from there, and a rerun at another rate makes its tests on the same packings.
local M = require("material")
local args, opt = require("talus_util.options").command_line(arg, { "rate", "max-steps", "material", "checkpoint", "hold" })
local outdir = args[1] or "out"
local n = tonumber(args[2] or "5")
local scale = tonumber(args[3] or "1")
local first = tonumber(args[4] or "1")
local phi = args[5] == "phi"
local kind = opt.material or args[6] or "fjoint"
talus.mkdir(outdir)
local mat, genesis, disk
if kind == "pbond-pc" then
    mat, genesis, disk = M.lac_du_bonnet("pbond")
else
    if not M.ldb_calibrated[kind] then
        error("ldb_flatjoint.lua: material '" .. kind .. "' (known: fjoint, pbond, clumped, pbond-pc)")
    end
    mat, genesis, disk = M.lac_du_bonnet(kind, M.ldb_calibrated[kind])
end
local seeds = {}
for i = 1, n do seeds[i] = first + i - 1 end
local t0 = os.clock()
local res = M.run_seeds{ material = mat, genesis = genesis, disk = disk, seeds = seeds, scale = scale,
                         confinements = phi and { 10e6, 20e6 } or nil, strain_per_crossing = opt.rate,
                         max_steps = opt["max-steps"], checkpoint = opt.checkpoint,
                         hold = opt.hold ~= nil and (opt.hold ~= 0 and opt.hold ~= "off") or nil,
                         key = opt.checkpoint and string.format("ldb %s scale %g seeds %d-%d", kind, scale, first,
                             first + n - 1) or nil }
if talus.rank() == 0 then
    M.print_seeds(res, string.format("Lac du Bonnet, %s, scale %g, seeds %d-%d, rate %g per P-wave crossing", kind,
        scale, first, first + n - 1, opt.rate or M.strain_per_crossing))
    print(string.format("CPU: %.0f s (tests %.0f s, packings %.0f s; this process %.0f s)", res.cpu,
        res.cpu - res.cpu_packings, res.cpu_packings, os.clock() - t0))
    M.write_csv(string.format("%s/ldb_%s_seeds_%d.csv", outdir, kind, first), res.rows,
        { "seed", "balls", "porosity", "ucs", "E", "nu", "E_elastic", "nu_elastic", "tensile", "tensile_peak", "valid",
          "reason", "ratio", "phi", "c", "m_i", "ci_ratio", "cd_ratio", "steps", "stop", "qs_difference", "qs_kinetic", "qs_ratio", "held", "holds",
          "stop_brazilian", "steps_brazilian", "cpu", "cpu_ucs", "cpu_brazilian" })
end
