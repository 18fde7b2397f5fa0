-- ParaView output (m:vtk): a scene whose state vtk_readback.py compares, array by array, with
-- what VTK's own reader finds in the files. Writes out/expected_*.csv with the state of the
-- last frame (values printed with %.17g: read back as the same doubles).
-- usage: talus run vtk_scene.lua OUTDIR
local T = require("testlib")
local out = assert(arg[1], "usage: vtk_scene.lua OUTDIR")
local dir = out .. "/vtk"

local function scene()
    local m = talus.model{ gravity = {0, -9.81} }
    m:contact_model("linear", { kn = 1e6, ks = 5e5, fric = 0.5, dp_nratio = 0.1 })
    m:wall{ points = {{-1, 0}, {1, 0}, {1, 1}, {-1, 1}}, closed = true, group = "box" }
    m:wall{ points = {{-0.9, 0.5}, {-0.6, 0.45}} }
    -- a row of balls resting on the floor, in two groups, touching each other
    for i = 0, 5 do
        m:ball{ pos = {-0.5 + 0.1 * i, 0.05}, radius = 0.05, density = 2600,
                group = i % 2 == 0 and "even" or "odd", vel = {0.01 * i, 0} }
    end
    m:ball{ pos = {0.5, 0.6}, radius = 0.04, density = 2000, vel = {0.3, -1}, spin = 2 }
    m:clump{ pebbles = {{-0.03, 0, 0.03}, {0.03, 0, 0.03}}, pos = {0.2, 0.5}, density = 2600,
             group = "rock" }
    return m
end

-- 1. A series every 20 steps with built-in and Lua fields.
local m = scene()
local v = m:vtk{ dir = dir, every = 20, fields = {"force", "mass", "speed",
                 height = function(b) return b.pos[2] end,
                 double_vel = function(b) return {2 * b.vel[1], 2 * b.vel[2]} end} }
T.check(v.frames == 1, "the first frame is the state at creation")
m:cycle(100)
T.check(v.frames == 6, "frames at steps 0, 20, ..., 100 (got " .. v.frames .. ")")
T.check(v.file == dir .. "/talus.pvd", "the .pvd path")

-- Pebbles are not balls to the Lua API (m:balls() skips them) but they are particles in the
-- files: their position and radius from c:pebbles(), their velocity the clump's rigid motion.
local f = assert(io.open(out .. "/expected_pebbles.csv", "w"))
f:write("x,y,radius,clump,vx,vy,spin\n")
for c in m:clumps() do
    for _, p in ipairs(c:pebbles()) do
        local rx, ry = p.pos[1] - c.pos[1], p.pos[2] - c.pos[2]
        f:write(string.format("%.17g,%.17g,%.17g,%d,%.17g,%.17g,%.17g\n", p.pos[1], p.pos[2],
            p.radius, c.id, c.vel[1] - c.spin * ry, c.vel[2] + c.spin * rx, c.spin))
    end
end
f:close()
f = assert(io.open(out .. "/expected_balls.csv", "w"))
f:write("id,x,y,radius,vx,vy,spin,clump,mass,fx,fy,group\n")
for b in m:balls() do
    local c = 0
    local g = b.groups[1] or ""
    f:write(string.format("%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%.17g,%.17g,%.17g,%s\n",
        b.id, b.pos[1], b.pos[2], b.radius, b.vel[1], b.vel[2], b.spin, c, b.mass,
        b.force[1], b.force[2], g))
end
f:close()
f = assert(io.open(out .. "/expected_contacts.csv", "w"))
f:write("end1,end2,wall,fn,fs,overlap\n")
local n = 0
for c in m:contacts() do
    n = n + 1
    f:write(string.format("%d,%d,%d,%.17g,%.17g,%.17g\n", c.ball1.id,
        c.wall and c.wall.id or c.ball2.id, c.wall and 1 or 0, c.normal_force,
        c.shear_force, c.overlap))
end
f:close()
T.check(n >= 5, "the scene has contacts to write (" .. n .. ")")
f = assert(io.open(out .. "/expected_meta.txt", "w"))
f:write(string.format("%.17g %d\n", m:time(), m:step()))
f:close()

-- 2. Going on with a series (a restored run): a fresh model at t = 0 keeps frame 0 of the
-- .pvd, writes no duplicate of it, and numbers its frames from 1.
local m2 = scene()
local v2 = m2:vtk{ dir = dir, name = "cont", every = 10 }
m2:cycle(30)
T.check(v2.frames == 4, "a second series in the same directory")
local m3 = scene()
local v3 = m3:vtk{ dir = dir, name = "cont", every = 10, append = true }
T.check(v3.frames == 1, "append keeps the frames up to the model's time (got " .. v3.frames .. ")")
m3:cycle(20)
T.check(v3.frames == 3, "append goes on numbering: 0 kept, 1 and 2 new")

-- 3. Bad input names what is wrong.
T.fails(function() m:vtk{ dir = dir, fields = {"colour"} } end, {"unknown ball field 'colour'"})
T.fails(function() m:vtk{ dir = dir, every = 0 } end, {"'every' must be >= 1"})
T.fails(function() m:vtk{ every = 5 } end, {"'dir' is required"})
T.fails(function() m:vtk{ dir = dir, fields = {mass = function() return 1 end} } end,
        {"built-in field name"})
print("vtk scene: wrote " .. v.frames .. " frames to " .. v.file)
