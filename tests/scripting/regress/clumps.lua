-- SPDX-License-Identifier: MIT
-- Clumps from Lua (docs/lua-api.md, "Clumps"; engine tests in tests/core/test_clumps.cpp):
-- creation from pebbles and from a template, the clump fields, iteration, pebbles not listed as
-- balls, a clump resting on a wall, contacts naming their clump, release and delete, errors.
local T = require("testlib")

local rho, R = 2600.0, 0.1

-- 1. Creation, fields, union mass (two disks at distance R overlap: the lens counts once).
do
    local m = talus.model{ gravity = {0, -9.81} }
    m:contact_model("linear", { kn = 1e8, ks = 1e8, fric = 0.5, dp_nratio = 0.3 })
    local c = m:clump{ pebbles = {{-0.5 * R, 0, R}, {0.5 * R, 0, R}}, pos = {0, 1}, density = rho,
                       group = "rock" }
    -- Union area of two unit-distance disks of radius R: 2 pi R^2 - lens, lens = 2 R^2 acos(1/2)
    -- - (R/2) sqrt(4 R^2 - R^2) (closed form, to round-off).
    local lens = 2 * R * R * math.acos(0.5) - 0.5 * R * math.sqrt(3 * R * R)
    T.near(c.mass, rho * (2 * math.pi * R * R - lens), 1e-12, "union mass")
    T.near(c.pos[1], 0, 1e-15, "centroid x")
    T.near(c.pos[2], 1, 1e-15, "centroid y")
    T.check(m:clump_count() == 1, "clump_count")
    T.check(m:ball_count() == 0, "pebbles are not balls")
    local n = 0
    for _ in m:balls() do n = n + 1 end
    T.check(n == 0, "m:balls() skips pebbles")
    n = 0
    for k in m:clumps{ group = "rock" } do n = n + 1; T.check(k == c, "iterator gives the clump") end
    T.check(n == 1, "m:clumps{group}")
    T.check(#c:pebbles() == 2 and c:pebbles()[1].radius == R, "c:pebbles()")
    T.check(c.groups[1] == "rock", "groups")

    -- Rests on a floor: after 1 s its weight is carried by its contacts, which name the clump.
    m:wall{ points = {{-1, 0}, {1, 0}} }
    c.pos = {0, R - 0.5 * c.mass * 9.81 / 1e8}
    m:solve{ time = 1.0 }
    T.near(c.force[2], c.mass * 9.81, 1e-6, "contact force carries the weight")
    T.near(c.vel[2], 0, 1e-6, "at rest")
    local seen = 0
    for ct in m:contacts() do
        seen = seen + 1
        T.check(ct.clump1 == c and ct.clump2 == nil and ct.wall ~= nil, "contact names its clump")
    end
    T.check(seen == 2, "two pebble contacts")

    -- Set fields.
    c:set{ vel = {1, 0}, spin = 2, fapp = {0, 5}, mapp = 1, kn = 2e8 }
    T.check(c.vel[1] == 1 and c.spin == 2 and c.fapp[2] == 5 and c.mapp == 1, "set{}")
    T.check(c.kn == 2e8, "kn")
    T.fails(function() c.mass = 1 end, {"clump: field 'mass' is read-only"}, "read-only")
    T.fails(function() return c.colour end, {"clump: unknown field 'colour'"}, "unknown field")

    -- Release: the pebbles become balls with their disk mass.
    local balls = c:release()
    T.check(#balls == 2 and m:ball_count() == 2 and m:clump_count() == 0, "release")
    T.near(balls[1].mass, rho * math.pi * R * R, 1e-12, "released ball mass")
    T.fails(function() return c.pos end, {"was deleted (stale id)"}, "stale clump")
end

-- 2. Templates: mass scales with scale^2, inertia with scale^4.
do
    local m = talus.model{}
    local t = m:clump_template{ pebbles = {{0, 0, R}, {R, 0, R}, {0.5 * R, R, 0.8 * R}} }
    local a = m:clump{ template = t, pos = {0, 0}, density = rho }
    local b = m:clump{ template = t, pos = {3, 0}, angle = 0.5, scale = 2, density = rho }
    T.near(a.mass, rho * t.area, 1e-12, "template mass")
    T.near(a.inertia, rho * t.inertia, 1e-12, "template inertia")
    T.near(b.mass, 4 * a.mass, 1e-12, "scale^2")
    T.near(b.inertia, 16 * a.inertia, 1e-12, "scale^4")
    T.near(b.angle, 0.5, 0, "angle")
    b:delete()
    T.check(m:clump_count() == 1, "delete")
    -- Direct mode.
    local d = m:clump{ pebbles = {{0, 0, R}}, pos = {5, 5}, mass = 3, inertia = 0.2 }
    T.check(d.mass == 3 and d.inertia == 0.2, "direct mass")
end

-- 3. Errors name the script line and the field.
do
    local m = talus.model{}
    local line = T.line() + 1
    local err = T.fails(function() m:clump{ pebbles = {{0, 0, -1}}, density = rho, pos = {0, 0} } end,
                        {"pebble 1 radius must be > 0"}, "bad radius")
    T.check(err:find(":" .. line .. ":", 1, true), "error names the line: " .. err)
    T.fails(function() m:clump{ pebbles = {{0, 0}}, density = rho } end, {"clump: pebble 1 must be {x, y, r}"},
            "bad pebble")
    T.fails(function() m:clump{ pebbles = {{0, 0, 1}} } end, {"'density'"}, "no density")
    T.fails(function() m:clump{ pebbles = {{0, 0, 1}}, density = 1, colour = 1 } end, {"colour"},
            "unknown option")
    local ms = talus.model{ mass = "sphere" }
    T.fails(function() ms:clump{ pebbles = {{0, 0, 1}}, density = 1 } end, {"union of spheres"},
            "sphere mode")
end

-- 4. A clump from existing balls: they keep their ids and become pebbles.
do
    local m = talus.model{}
    local a = m:ball{ pos = {0, 0}, radius = R, density = rho, vel = {-1, 0} }
    local b = m:ball{ pos = {2 * R, 0}, radius = R, density = rho, vel = {1, 0} }
    local c = m:clump{ balls = {a, b}, group = "pair" }
    T.near(c.mass, 2 * rho * math.pi * R * R, 1e-12, "mass of two touching disks")
    T.near(c.vel[1], 0, 1e-15, "momentum kept")
    T.check(m:ball_count() == 0 and m:clump_count() == 1, "balls became pebbles")
    T.fails(function() a:delete() end, {"is a pebble of clump 1"}, "pebbles are deleted with the clump")
    T.fails(function() m:clump{ balls = {a}, pos = {0, 0} } end, {"'pos' does not go with 'balls'"},
            "pos with balls")
end

T.done("clumps")
