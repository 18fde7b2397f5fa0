-- SPDX-License-Identifier: MIT
-- The crack log survives a save and restore (docs/save-format.md, HOST version 3): the restored
-- model lists the same cracks, value for value, and a ParaView series with `cracks = true`
-- goes on writing its cracks block.
local T = require("testlib")
local M = require("material")
local out = assert(arg[1], "usage: crack_restore.lua OUTDIR") .. "/crack_restore"
talus.mkdir(out)

local pk = M.genesis{ width = 0.01, height = 0.02, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16,
                      kn = 6.4e10, ks = 9.6e9, seed = 3 }
local sp = M.specimen(pk, { model = "cbond", kn = 6.4e10, ks = 9.6e9, fric = 0.5, density = 2600,
                            bond = { cb_tenf = 4.6e4, cb_shearf = 3.5e4 } })
local m = sp.model
M.compress(sp, { post_peak = 0.3, strain_per_crossing = 2e-5 })
local before = m:cracks()
T.check(#before > 0, "cracks to save (" .. #before .. ")")
m:vtk{ dir = out, name = "s", every = 100, cracks = true }
m:save(out .. "/m.save")

local m2, notes = talus.restore(out .. "/m.save", { quiet = true })
local after = m2:cracks()
T.check(#after == #before, string.format("%d cracks restored of %d", #after, #before))
for i, c in ipairs(before) do
    local k = after[i] or {}
    for _, f in ipairs { "time", "step", "x", "y", "mode", "ball1", "ball2", "radius", "width", "nx", "ny", "sigma", "tau" } do
        T.check(k[f] == c[f], "crack " .. i .. ": " .. f)
    end
end
local continues = false
for _, n in ipairs(notes) do if n:find("vtk series", 1, true) and n:find("continues", 1, true) then continues = true end end
T.check(continues, "the series continues: " .. table.concat(notes, "; "))
m2:cycle(100)
local f = assert(io.open(out .. "/s_000001.vtm"))
local vtm = f:read("a")
f:close()
T.check(vtm:find('name="cracks"', 1, true) ~= nil, "the restored series still writes its cracks")
T.done("crack_restore")
