-- SPDX-License-Identifier: MIT
-- material/grain_disk.lua: a Brazilian disk of rigid grains made in a circular vessel: the
-- genesis of M.clump_genesis (grains of 1-3 balls) in the circle of M.genesis_disk, so that the
-- disk's rim grains touch its circle and the curved jaws load it over an arc (a disk cut from a
-- box packing has a rim as rough as a grain).
local U = require("material.util")
local G = require("material.genesis")
local V = require("material.vessels")
local B = require("material.bodies")
local raise = require("talus_util.errors").raise

local GD = {}

local kKnown = U.set_of { "diameter", "rmin", "rmax", "porosity", "density", "kn", "ks", "seed", "stress", "damp",
    "ratio", "tolerance", "stages", "max_steps", "min_contacts", "verbose", "check_every", "floater_rounds", "shares",
    "segments", "roughness" }

--- M.clump_genesis_disk{diameter =, rmin =, rmax =, kn =, ...}: the options of M.clump_genesis
--- (shares, ...) with diameter for width and height, and M.genesis_disk's segments and
--- roughness (the polygon a circle to roughness x rmin, 0.01). Defaults as theirs. Returns a
--- packing as M.genesis_disk's, with clumps and grain_counts as M.clump_genesis's; M.disk(pk)
--- returns all its balls, and M.specimen makes the grains rigid.
function GD.clump_genesis_disk(opts)
    U.check_known(opts, kKnown, "clump_genesis_disk")
    local o = {
        name = "clump_genesis_disk",
        rmin = U.req(opts, "rmin", "clump_genesis_disk"), rmax = U.req(opts, "rmax", "clump_genesis_disk"),
        kn = U.req(opts, "kn", "clump_genesis_disk"),
        porosity = opts.porosity or 0.16, density = opts.density or 2600, stress = opts.stress or 1e5,
        ratio = opts.ratio or 1e-3, tolerance = opts.tolerance or 0.1, stages = opts.stages or 8,
        max_steps = opts.max_steps or 3000, min_contacts = opts.min_contacts or 3, check_every = opts.check_every or 50,
        floater_passes = 3, floater_rounds = opts.floater_rounds or 2, seed = opts.seed or 1, damp = opts.damp,
        verbose = opts.verbose,
    }
    o.ks = opts.ks or o.kn
    if not (o.rmin > 0 and o.rmax >= o.rmin) then raise("material.clump_genesis_disk: need 0 < rmin <= rmax") end
    local D0 = U.req(opts, "diameter", "clump_genesis_disk")
    -- a grain of three balls spans up to 4 rmax + 2 rmax: the disk holds a few across
    if not (D0 > 12 * o.rmax) then
        raise(string.format("material.clump_genesis_disk: diameter %g m must exceed 12 rmax (%g m)", D0, 12 * o.rmax))
    end
    local shares = opts.shares or { 1 / 3, 1 / 3, 1 / 3 }
    -- the segment count of M.genesis_disk: a polygon within roughness x rmin of its circle
    local e_rough = opts.roughness or 0.01
    local N = opts.segments or 4 * math.ceil(math.pi * math.sqrt(0.5 * D0 / (2 * e_rough * o.rmin)) / 4)
    if math.type(N) ~= "integer" or N < 8 then
        raise("material.clump_genesis_disk: segments must be an integer >= 8 (got " .. tostring(N) .. ")")
    end
    local pk = G.run(V.circle(D0, N), B.grains(o.rmin, o.rmax, shares), o)
    return pk -- not a tail call: the errors of run name the caller's line
end

return GD
