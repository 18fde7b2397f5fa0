-- SPDX-License-Identifier: MIT
-- Ball fields: read, write, set{}, groups, fixity, applied force, delete and stale ids.
local T = require("testlib")

local m = talus.model{ gravity = {0, 0} }
local b = m:ball{ pos = {1, 2}, radius = 0.2, density = 1000, vel = {0.5, -0.5}, spin = 3,
                  angle = 0.25, group = "rock", kn = 1e6, fix = {"spin"} }
T.check(b.id == 1, "first ball id is 1")
T.near(b.pos[1], 1, 0, "pos x"); T.near(b.pos[2], 2, 0, "pos y")
T.near(b.vel[1], 0.5, 0, "vel"); T.near(b.spin, 3, 0, "spin"); T.near(b.angle, 0.25, 0, "angle")
T.near(b.radius, 0.2, 0, "radius")
T.near(b.mass, 1000 * math.pi * 0.04, 1e-14, "disk mass = rho pi R^2")
T.near(b.inertia, 0.5 * b.mass * 0.04, 1e-14, "disk inertia = m R^2 / 2")
T.near(b.density, 1000, 0, "density")
T.check(b.kn == 1e6 and b.ks == nil and b.fric == nil, "inheritable props: set and unset")
T.check(#b.groups == 1 and b.groups[1] == "rock", "groups")
T.check(#b.fix == 1 and b.fix[1] == "spin", "fix")
T.check(b.alive, "alive")

-- writes
b.pos = {3, 4}; T.near(b.pos[1], 3, 0, "write pos")
b.vel = {1, 0}; T.near(b.vel[1], 1, 0, "write vel")
b.spin = 0; T.near(b.spin, 0, 0, "write spin")
b.radius = 0.1; T.near(b.mass, 1000 * math.pi * 0.01, 1e-14, "radius updates the mass")
b.density = 2000; T.near(b.mass, 2000 * math.pi * 0.01, 1e-14, "density updates the mass")
b:set{ fapp = {2, 0}, mapp = 0.5, fix = {}, kn = nil, fric = 0.3 }
T.near(b.fapp[1], 2, 0, "set fapp"); T.near(b.mapp, 0.5, 0, "set mapp")
T.check(#b.fix == 0, "set fix = {}")
T.near(b.fric, 0.3, 0, "set fric")
b.kn = nil
T.check(b.kn == nil, "kn = nil unsets")
b:add_group("boulder")
T.check(#b.groups == 2, "add_group")

-- an applied force accelerates the ball: v = v0 + F/m t (no gravity, no contacts)
m:timestep{ fixed = 1e-3 }
local mass, v0 = b.mass, b.vel[1]
m:cycle(100)
T.near(b.vel[1], v0 + 2 / mass * (100 - 0.5) * 1e-3, 1e-12, "applied force: v(t - dt/2)")
T.near(b.spin, 0.5 / b.inertia * (100 - 0.5) * 1e-3, 1e-12, "applied moment: spin")

-- fixity: a fixed velocity component is not integrated
local f = m:ball{ pos = {10, 0}, radius = 0.1, density = 1000, vel = {1, 0}, fix = {"x"} }
f.fapp = {5, 5}
m:cycle(10)
T.near(f.vel[1], 1, 0, "fixed x velocity stays")
T.check(f.vel[2] > 0, "free y velocity integrates")

-- iteration and identity
local n, rocks = 0, 0
for ball in m:balls() do n = n + 1 end
for ball in m:balls{ group = "rock" } do rocks = rocks + 1; T.check(ball == b, "ball == b") end
T.check(n == 2 and rocks == 1, "balls{} and balls{group}")
T.check(m:ball_count() == 2, "ball_count")
T.check(b ~= f, "different balls are not equal")
T.check(tostring(b):find("ball 1 at", 1, true), "tostring")

-- errors name the field and list the known ones
local s = T.script()
local l = T.line(); T.fails(function() return b.radiuss end,
    { s .. ":" .. (l) .. ":", "ball: unknown field 'radiuss'; did you mean 'radius'? (known: id, pos, vel" }, "unknown field")
T.fails(function() b.mass = 1 end, { "ball: field 'mass' is read-only (writable: pos" }, "read-only")
T.fails(function() b.vel = {1} end, { "ball: 'vel' must be a vector {x, y}" }, "bad vector")
T.fails(function() b:set{ radius = -1 } end, { "ball: radius must be > 0 (got -1)" }, "set radius")
T.fails(function() b.fix = {"z"} end, { "'fix' entry 1 must be one of \"x\", \"y\", \"spin\"" }, "fix")
T.fails(function() for _ in m:balls{ group = "nope" } do end end,
    { "balls: no group named 'nope' (groups: rock, boulder)" }, "unknown group")

-- delete: the ball userdata goes stale
local kept = b
b:delete()
T.check(not kept.alive, "alive is false after delete")
l = T.line(); T.fails(function() return kept.pos end,
    { s .. ":" .. l .. ":", "ball 1 was deleted (stale id)" }, "stale id")
T.fails(function() kept.vel = {0, 0} end, { "ball 1 was deleted (stale id)" }, "stale write")
-- a new ball may reuse the handle index, but the old userdata stays stale
local c = m:ball{ pos = {0, 0}, radius = 0.1, density = 1000 }
T.check(c.id == 1, "handle index reused")
T.fails(function() return kept.radius end, { "was deleted (stale id)" }, "stale after reuse")
T.check(m:ball_count() == 2, "ball_count after delete and create")
T.done("ball_state")
