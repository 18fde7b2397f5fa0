-- SPDX-License-Identifier: MIT
-- Cracks drawn (m:picture{cracks = true}) and written (m:vtk{cracks = true}): a small bonded
-- specimen crushed by M.compress, contact-bond strengths that break bonds in tension and in
-- shear. crack_test.py checks the files against what this script prints.
-- usage: talus run crack_scene.lua OUTDIR [picture]   (picture: talus built with cairo)
-- Prints "CRACK i x y nx ny width mode ball1 ball2 time step" for every crack of m:cracks()
-- (%.17g) and "PIXEL name px py" for each crack's centre and ends in the pictures.
local T = require("testlib")
local M = require("material")
local out = arg[1] or "."
local pictures = arg[2] == "picture" -- built with cairo
talus.mkdir(out)

local pk = M.genesis{ width = 0.01, height = 0.02, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16,
                      kn = 6.4e10, ks = 9.6e9, seed = 3 }
local sp = M.specimen(pk, { model = "cbond", kn = 6.4e10, ks = 9.6e9, fric = 0.5, density = 2600,
                            bond = { cb_tenf = 4.6e4, cb_shearf = 3.5e4 } })
local m = sp.model
local before = #m:cracks()
local r = M.compress(sp, { post_peak = 0.3, strain_per_crossing = 2e-5 })
local cracks = m:cracks()
-- m:cracks() is the model's log: the test's list is its tail, the same values
T.check(#cracks == before + #r.cracks, "m:cracks() holds the test's cracks")
for i, c in ipairs(r.cracks) do
    local k = cracks[before + i]
    T.check(k.x == c.x and k.y == c.y and k.mode == c.mode and k.width == c.width and k.nx == c.nx
        and k.ball1 == c.ball1 and k.time == c.time, "crack " .. i .. " as the test listed it")
end
T.check(#m:cracks{ since = cracks[#cracks].time } >= 1, "cracks{since}")

m:vtk{ dir = out .. "/vtk", name = "cracks", cracks = true }
local view = { -0.001, -0.001, 0.011, 0.021 }
local with, without
if pictures then
    with = m:picture{ file = out .. "/cracks.png", size = { 600, 1000 }, view = view, cracks = true }
    without = m:picture{ file = out .. "/plain.png", size = { 600, 1000 }, view = view }
end
local modes = {}
for i, c in ipairs(cracks) do
    modes[c.mode] = (modes[c.mode] or 0) + 1
    print(string.format("CRACK %d %.17g %.17g %.17g %.17g %.17g %s %d %d %.17g %d", i, c.x, c.y, c.nx, c.ny,
        c.width, c.mode, c.ball1, c.ball2, c.time, c.step))
    if pictures then
        local tx, ty = -c.ny * 0.5 * c.width, c.nx * 0.5 * c.width
        print(string.format("PIXEL c%d %.3f %.3f", i, with:pixel(c.x, c.y)))
        print(string.format("PIXEL c%d.a %.3f %.3f", i, with:pixel(c.x + tx, c.y + ty)))
        print(string.format("PIXEL c%d.b %.3f %.3f", i, with:pixel(c.x - tx, c.y - ty)))
        local px, py = with:pixel(c.x, c.y)
        local qx, qy = without:pixel(c.x, c.y)
        T.check(px == qx and py == qy, "both pictures map the model alike")
    end
end
T.check((modes.tension or 0) > 0 and (modes.shear or 0) > 0,
    string.format("tension (%d) and shear (%d) cracks", modes.tension or 0, modes.shear or 0))
T.done("crack_scene")
