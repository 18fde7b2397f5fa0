-- SPDX-License-Identifier: MIT
-- Paths in pictures (m:picture{path =, paths =}): a ball thrown over a floor with a tracker
-- keeping its centre every sample, and a path given as points; picture_path_test.py checks the
-- pixels along both. Prints "PIXEL name x y" for the points it checks (out:pixel).
-- usage: talus run picture_path_scene.lua OUTDIR
local out = assert(arg[1], "usage: picture_path_scene.lua OUTDIR")
talus.mkdir(out)

local m = talus.model{ gravity = {0, -9.81} }
m:contact_model("linear", { kn = 1e7, ks = 5e6, fric = 0.5, dp_nratio = 0.3 })
m:wall{ points = {{-1, 0}, {11, 0}} }
-- Thrown from (0, 1) at (4, 4) m/s: a parabola up to 1 + 16 / (2 g) = 1.82 m, over the floor.
local b = m:ball{ pos = {0, 1}, radius = 0.1, density = 2600, vel = {4, 4} }
local tr = m:track(b, { path = 1 })
local view = { -1, -0.5, 11, 3.5 }
-- A series: its first picture has the path of one sample, its last the whole flight.
local series = m:picture{ file = out .. "/flight.png", every = 100, color = "none", legend = false,
    scale_bar = false, size = {1200, 400}, view = view, path = tr, contacts = "none" }
m:timestep{ fixed = 1e-4 }
m:cycle(800)  -- 0.08 s... and on to t = 0.8 s, in flight (lands at t = 0.97 s)
m:cycle(7200)
local final = m:picture{ file = out .. "/paths.png", color = "none", legend = false, scale_bar = false,
    size = {1200, 400}, view = view, contacts = "none",
    paths = { tr, { {2, 3}, {9, 3} }, { {0.5, 0.5, 0.5}, {0.9, 9.5, 0.5} } } }
local bare = m:picture{ file = out .. "/bare.png", color = "none", legend = false, scale_bar = false,
    size = {1200, 400}, view = view, contacts = "none" }

-- Points on the flight path, away from the ball at its end (x < 2.8 m): the tracked centres.
local path = tr:path()
assert(#path == 8001, "one point per step: " .. #path)
for k = 100, 5000, 700 do
    local p = path[k]
    print(string.format("PIXEL on.%d %.3f %.3f", k, final:pixel(p[2], p[3])))
    -- 0.25 m below the path (8 px at 33 px/m... 25 px at 100 px/m): background
    print(string.format("PIXEL below.%d %.3f %.3f", k, final:pixel(p[2], p[3] - 0.25)))
end
print(string.format("PIXEL line2 %.3f %.3f", final:pixel(5.5, 3)))   -- the second path, {x, y}
print(string.format("PIXEL line3 %.3f %.3f", final:pixel(5.0, 0.5))) -- the third, {t, x, y}
print(string.format("PIXEL start %.3f %.3f", final:pixel(0, 1)))    -- the tracker's first point
-- At t = 0 the path is one point; at x = 2 m (t = 0.5 s) the flight has passed by frame 5+.
print(string.format("PIXEL mid %.3f %.3f", final:pixel(2, 1 + 4 * 0.5 - 0.5 * 9.81 * 0.25)))
print("FRAMES " .. series.frames)

-- Bad input names the option.
local function fails(fn, part)
    local ok, err = pcall(fn)
    assert(not ok and tostring(err):find(part, 1, true), tostring(err))
end
local other = talus.model{}
local ob = other:ball{ pos = {0, 0}, radius = 1, density = 1000 }
fails(function() m:picture{ file = out .. "/x.png", path = other:track(ob, { path = 1 }) } end,
    "belongs to another model")
local b2 = m:ball{ pos = {5, 2}, radius = 0.1, density = 1000 }
fails(function() m:picture{ file = out .. "/x.png", path = m:track(b2, {}) } end,
    "keeps no path (make it with m:track{path = 1")
fails(function() m:picture{ file = out .. "/x.png", paths = { { {1, 2}, {3} } } } end,
    "'paths' entry 1, point 2: expected {x, y} or {t, x, y}")
fails(function() m:picture{ file = out .. "/x.png", path = 5 } end,
    "must be a tracker or a list of points")
fails(function() m:picture{ file = out .. "/x.png", path = {} } end, "'path' has no points")
print("picture paths: scene done")
