-- SPDX-License-Identifier: MIT
--
-- ldb_flatjoint.lua: Lac du Bonnet granite with flat joints (Potyondy 2012; the calibrated
-- micro-parameters of M.lac_du_bonnet("fjoint"), docs/material.md "Lac du Bonnet"): UCS, E, nu,
-- Brazilian tensile strength and UCS/sigma_t over seeds, with their scatter, and with `phi` the
-- friction angle from biaxial tests at 10 and 20 MPa (Mohr-Coulomb over the UCS and those two).
--
--   talus run scripts/examples/ldb_flatjoint.lua [outdir] [nseeds] [scale] [first_seed] [phi] [material]
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
local M = require("material")
local outdir = arg[1] or "out"
local n = tonumber(arg[2] or "5")
local scale = tonumber(arg[3] or "1")
local first = tonumber(arg[4] or "1")
local phi = arg[5] == "phi"
local kind = arg[6] or "fjoint"
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
                         confinements = phi and { 10e6, 20e6 } or nil }
if talus.rank() == 0 then
    M.print_seeds(res, string.format("Lac du Bonnet, %s, scale %g, seeds %d-%d", kind, scale, first, first + n - 1))
    print(string.format("CPU: %.0f s (tests %.0f s, packings %.0f s; this process %.0f s)", res.cpu,
        res.cpu - res.cpu_packings, res.cpu_packings, os.clock() - t0))
    M.write_csv(string.format("%s/ldb_%s_seeds_%d.csv", outdir, kind, first), res.rows,
        { "seed", "balls", "porosity", "ucs", "E", "nu", "E_elastic", "nu_elastic", "tensile", "valid", "ratio", "phi",
          "c", "m_i", "ci_ratio", "cd_ratio", "steps", "cpu" })
end
