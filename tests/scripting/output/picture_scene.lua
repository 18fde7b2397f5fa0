-- Pictures (m:picture): a scene picture_test.py checks pixel by pixel.
-- usage: talus run picture_scene.lua OUTDIR
-- Prints "PIXEL name px py" for the centre of each ball the test looks at.
local T = require("testlib")
local out = arg[1] or "."
local m = talus.model{ gravity = {0, -9.81} }
m:contact_model("linear", { kn = 1e6, ks = 1e6, fric = 0.3 })
m:wall{ points = {{0, 0}, {10, 0}} }
local a = m:ball{ pos = {3, 5}, radius = 1, density = 1000, group = "a" }
local b = m:ball{ pos = {7, 5}, radius = 1, density = 1000, group = "b" }
local c = m:ball{ pos = {5, 8}, radius = 0.8, density = 1000 }   -- no group: grey
local lo = m:ball{ pos = {2, 1}, radius = 0.5, density = 1000, vel = {0, 0} }
local hi = m:ball{ pos = {8, 1}, radius = 0.5, density = 1000, vel = {4, 0} }

local view = {0, 0, 10, 10}
local p = m:picture{ file = out .. "/groups.png", size = {400, 300}, view = view }
for name, ball in pairs{ a = a, b = b, c = c } do
    print(string.format("PIXEL groups.%s %.3f %.3f", name, p:pixel(ball.pos[1], ball.pos[2])))
end
print(string.format("PIXEL groups.empty %.3f %.3f", p:pixel(5, 3)))
-- a function of the ball: its x position, from 2 (lowest: the bottom of viridis) to 8 (top)
local f = m:picture{ file = out .. "/value.png", size = {400, 300}, view = view,
                     color = function(ball) return ball.pos[1] end, label = "x [m]" }
print(string.format("PIXEL value.lo %.3f %.3f", f:pixel(2, 1)))
print(string.format("PIXEL value.hi %.3f %.3f", f:pixel(8, 1)))
-- speed with a given range: 4 m/s in {0, 4} is the top colour
local s = m:picture{ file = out .. "/speed.png", size = {400, 300}, view = view,
                     color = "speed", range = {0, 4}, contacts = "force" }
print(string.format("PIXEL speed.hi %.3f %.3f", s:pixel(8, 1)))
-- vector formats, and the automatic view and height
m:picture{ file = out .. "/scene.svg", color = "clump", title = "picture test" }
m:picture{ file = out .. "/scene.pdf" }
-- numbered frames
local fr = m:picture{ file = out .. "/frames/frame.png", every = 5, size = {160, 120} }
m:cycle(20)
T.check(fr.frames == 5, "frames at steps 0, 5, 10, 15, 20 (got " .. fr.frames .. ")")
T.check(fr.file == out .. "/frames/frame_000004.png", "the last frame's name: " .. fr.file)

T.fails(function() m:picture{ file = out .. "/x.jpg" } end, {"must end in .png, .svg or .pdf"})
T.fails(function() m:picture{ file = out .. "/x.png", color = "colour" } end, {"'color'"})
T.fails(function() m:picture{ file = out .. "/x.png", groups = {"nope"} } end,
        {"unknown group 'nope'"})
T.fails(function() m:picture{ file = out .. "/x.png", view = {0, 0, -1, 1} } end, {"'view'"})
print("picture scene: done")
