-- SPDX-License-Identifier: MIT
--
-- material: bonded-particle rock specimens and their laboratory tests (docs/material.md).
--
--   local M = require("material")
--   local pk = M.genesis{ width = 0.0317, height = 0.0634, rmin = 0.27e-3, rmax = 0.448e-3,
--                         porosity = 0.16, kn = 62e9, ks = 62e9 / 2.5, seed = 1 }
--   local sp = M.specimen(pk, { model = "cbond", kn = 6.4e10, ks = 9.6e9, fric = 0.5,
--                               density = 2600, bond = { cb_tenf = 1e9, cb_shearf = 1e10 } })
--   local r = M.compress(sp, { post_peak = 0.8, csv = "out/ucs.csv" })
--   print(r.ucs, r.E, r.nu)
--
-- The parts, one file each in this folder:
--   genesis.lua     Potyondy & Cundall's (2004) genesis, its steps written once for any vessel
--                   and kind of body: M.genesis (balls in a box), M.genesis_disk (balls in a
--                   circle: a disk whose rim balls touch its circle), M.clump_genesis (rigid
--                   grains of 1-3 balls in a box); a packing is a plain table, no model
--   vessels.lua, bodies.lua, floaters.lua   what the genesis steps are parameterised by
--                   (M.group_grains: touching balls grouped into grains; M.floater_circle)
--   grain_disk.lua  M.clump_genesis_disk: a disk of rigid grains made in a circular vessel
--   packing.lua     M.save_packing / M.load_packing: a packing as a Lua file
--   specimen.lua    M.specimen(pk, mat, opts): a model with the packing's balls, platens (side
--                   walls, or a disk's jaws) and bonds, relaxed; M.install_bonds
--   compress.lua    M.compress(sp, opts): UCS test, or biaxial test with opts.confinement
--   brazilian.lua   M.disk(pk) / M.brazilian(sp, opts): the Brazilian test on a disk;
--                   M.fracture: where it broke
--   jaws.lua        M.make_jaws: the ISRM curved jaws (radius 1.5 R)
--   loading.lua     the platen loop of the tests, M.columns of its history
--   cracks.lua      the tests' crack lists: M.write_cracks(file, list), M.crack_columns
--   statistics.lua  M.analyse (E tangent at 50%, secant E50, nu), M.mean_sd over seeds, M.finished
--   ldb.lua         M.lac_du_bonnet(kind, p): Lac du Bonnet granite with parallel bonds, flat
--                   joints or clumped grains
--   seeds.lua       M.run_seeds, M.print_seeds: a material's UCS, Brazilian and biaxial tests
--                   over seeds, with their scatter
--   envelope.lua    M.envelope: biaxial tests over confinements and seeds, M.mohr_coulomb and
--                   M.hoek_brown fits of their peaks, M.thresholds (crack initiation, damage)
--   calibration.lua M.calibrate: micro-parameters fitted to several targets at once (E, nu,
--                   UCS, tensile strength, friction angle) over seeds, resumable
--
-- Sign conventions: axial stress and strain are compression positive; lateral strain is
-- extension positive, so nu = d(eps_lat)/d(eps_ax) is positive. 2D: unit thickness (t = 1 m),
-- E and nu are those of the disk assembly.

local U = require("material.util")
local E = require("material.equilibrium")
local Wl = require("material.walls")
local F = require("material.floaters")
local B = require("material.bodies")
local G = require("material.genesis")
local P = require("material.packing")
local S = require("material.specimen")
local J = require("material.jaws")
local L = require("material.loading")
local C = require("material.compress")
local Br = require("material.brazilian")
local St = require("material.statistics")
local Ldb = require("material.ldb")
local GD = require("material.grain_disk")
local Cr = require("material.cracks")
local Env = require("material.envelope")
local Cal = require("material.calibration")
local Sd = require("material.seeds")

return {
    -- genesis
    genesis = G.box, genesis_disk = G.disk, clump_genesis = G.clumps, clump_genesis_disk = GD.clump_genesis_disk,
    group_grains = B.group_grains,
    tangent_circles = F.tangent_circles, floater_circle = F.floater_circle,
    save_packing = P.save, load_packing = P.load,
    -- specimens and tests
    specimen = S.specimen, install_bonds = S.install_bonds,
    compress = C.compress,
    disk = Br.disk, brazilian = Br.brazilian, fracture = Br.fracture, brazilian_validity = Br.validity,
    brazilian_peak_stiffness = Br.peak_stiffness, brazilian_split = Br.split,
    make_jaws = J.make_jaws, jaw_points = J.jaw_points, contact_angles = J.contact_angles,
    columns = L.columns, crack_columns = Cr.columns, write_cracks = Cr.write_csv,
    strain_per_crossing = L.strain_per_crossing, quasi_static = L.quasi_static, hold = L.hold,
    analyse = St.analyse, mean_sd = St.mean_sd, finished = St.finished, write_csv = U.write_csv,
    lac_du_bonnet = Ldb.lac_du_bonnet, ldb_defaults = Ldb.defaults, ldb_calibrated = Ldb.calibrated,
    run_seeds = Sd.run, print_seeds = Sd.print, seeds_stat = Sd.stat,
    -- strength envelope
    envelope = Env.run, envelope_fit = Env.fit, mohr_coulomb = Env.mohr_coulomb, hoek_brown = Env.hoek_brown,
    thresholds = Env.thresholds,
    -- calibration against several targets
    calibrate = Cal.calibrate, write_calibration = Cal.write_csv, calibration_outputs = Cal.point_outputs,
    calibration_unmeasured = Cal.unmeasured,
    -- tools the parts share
    new_model = E.new_model, solve_ratio = E.solve_ratio, unbalanced_ratio = E.unbalanced_ratio,
    drawer = U.drawer, servo = Wl.servo,
}
