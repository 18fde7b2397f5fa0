-- SPDX-License-Identifier: MIT
-- material/ldb.lua: Lac du Bonnet granite with parallel bonds (Potyondy & Cundall 2004).
local G = require("material.genesis")

local Ldb = {}

--- Lac du Bonnet granite with parallel bonds (Potyondy & Cundall 2004; docs/material.md "Lac du
--- Bonnet"): returns the material table of M.specimen (frictionless platens; a test that wants
--- others sets mat.platen.fric), genesis(width, height, seed), a block's packing, and
--- disk(diameter, seed), a Brazilian disk's packing made in a circular vessel (M.genesis_disk).
--- Shared by scripts/examples/ldb_pbond.lua and ldb_brazilian.lua, which compare tests of one
--- material.
function Ldb.lac_du_bonnet()
    local E, kratio = 62e9, 2.5
    local mat = {
        model = "pbond", kn = E, ks = E / kratio, fric = 0.5, density = 2630,
        -- platens: a ball-wall contact of the deformability form has length R, area 2R: kn = 2 E
        platen = { kn = 2 * E, ks = 2 * E / kratio, fric = 0 },
        bond = { emod = E, kratio = kratio, pb_emod = E, pb_kratio = kratio, pb_rmul = 1,
                 pb_mcf = 1, pb_ten = { mean = 157e6, sd = 36e6, dist = "normal" },
                 pb_coh = { mean = 157e6, sd = 36e6, dist = "normal" }, pb_fa = 0 },
    }
    local function genesis(w, h, seed)
        return G.box{ width = w, height = h, rmin = 0.27e-3, rmax = 1.66 * 0.27e-3,
                      porosity = 0.16, kn = E, ks = E / kratio, density = 2630, seed = seed }
    end
    local function disk(diameter, seed)
        return G.disk{ diameter = diameter, rmin = 0.27e-3, rmax = 1.66 * 0.27e-3, porosity = 0.16,
                       kn = E, ks = E / kratio, density = 2630, seed = seed }
    end
    return mat, genesis, disk
end

return Ldb
