-- Defects the stress suite's bad-input matrix found in clumps (docs/stress.md, "Defects found
-- with clumps"): before the fix a pebble radius of 1e-320 (given, or a scale of 1e-320 or 1e300)
-- reached the user as "internal error: union of disks has a positive area"; a pebble radius of
-- 1e300 was blamed on the mass; a direct centroid of 1e300 m on "ball: pos"; `balls = {}` on the
-- density; `c.pos = {1e300, 0}` was accepted; and an applied moment of 1e300 N m on a body away
-- from every contact ran on with an infinite kinetic energy in the balance and no error.
local T = require("testlib")
local S = T.script()
local m = talus.model{ gravity = { 0, -9.81 } }
m:contact_model("linear", { kn = 1e6 })

--- Expects fn (called on the next line of the caller) to fail at that line with `parts`.
local function refused(fn, parts, what)
    local line = debug.getinfo(2, "l").currentline
    table.insert(parts, 1, S .. ":" .. line .. ":")
    T.fails(fn, parts, what)
end

local two = { { -0.04, 0, 0.05 }, { 0.04, 0, 0.04 } }
refused(function() m:clump{ pebbles = { { 0, 0, 1e-320 } }, pos = { 0, 1 }, density = 1000 } end,
    { "clump: pebble 1 radius", "out of range" }, "pebble radius 1e-320")
refused(function() m:clump{ pebbles = { { 0, 0, 1e300 } }, pos = { 0, 1 }, density = 1000 } end,
    { "clump: pebble 1 radius 1e+300", "out of range" }, "pebble radius 1e300")
refused(function() m:clump{ pebbles = two, pos = { 0, 1 }, density = 1000, scale = 1e-320 } end,
    { "clump: pebble 1 radius", "scale" }, "scale 1e-320")
refused(function() m:clump{ pebbles = two, pos = { 0, 1 }, density = 1000, scale = 1e300 } end,
    { "clump: pebble 1 radius", "scale 1e+300" }, "scale 1e300")
refused(function() m:clump_template{ pebbles = { { 0, 0, 1e-320 } } } end,
    { "clump template: pebble 1 radius" }, "template pebble radius 1e-320")
local far = { pebbles = two, pos = { 0, 1 }, mass = 1, inertia = 0.01, centroid = { 1e300, 0 } }
refused(function() m:clump(far) end, { "clump: centroid", "out of range" }, "centroid 1e300")
local b1 = m:ball{ pos = { 5, 1 }, radius = 0.05, density = 1000 }
refused(function() m:clump{ balls = {} } end, { "clump: 'balls' is empty" }, "balls = {}")
T.check(b1.alive, "the ball is untouched")

-- A clump's pos is a ball's: within 1e9 m (the write was accepted and placed the pebbles there).
local c = m:clump{ pebbles = two, pos = { -2, 1 }, density = 1000 }
refused(function() c.pos = { 1e300, 0 } end, { "pos", "out of range" }, "c.pos = {1e300, 0}")
T.check(c.pos[1] == -2, "the refused write left the clump where it was")

-- An applied moment whose spin overflows the kinetic energy (finite velocities, infinite
-- 1/2 I w^2): the run must stop with a non-finite-state error naming the body, not carry inf.
m:energy{ on = true }
c.mapp = 1e300
refused(function() m:cycle(20) end, { "non-finite state", "clump 1", "energy" }, "clump mapp 1e300")

local m2 = talus.model{}
local b = m2:ball{ pos = { 0, 0 }, radius = 0.1, density = 1000 }
m2:energy{ on = true }
b.mapp = 1e300
refused(function() m2:cycle(20) end, { "non-finite state", "ball 1", "energy" }, "ball mapp 1e300")

-- A normal applied moment still runs: the check only fires on an overflow.
local m3 = talus.model{}
local c3 = m3:clump{ pebbles = two, pos = { 0, 0 }, density = 1000 }
m3:energy{ on = true }
c3.mapp = 1
m3:cycle(100)
local e = m3:energies()
-- Free rotation under a constant moment: the moment's work is all kinetic energy (round-off).
T.near(e.kinetic, e.body, 1e-9 * e.body, "mapp work = kinetic energy")
T.done("stress_clump_input")
