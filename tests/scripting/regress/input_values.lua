-- Every value a script gives, and every value derived from it, must be finite
-- and in range; errors name the option and carry the script line. Before the fix a radius of
-- 1e300 gave an infinite mass, `mass = 0/0` was reported as "density must be > 0 (got 0)",
-- `kn = 0/0` silently meant "not set", a wall at +-1e200 m failed later blaming the model and
-- m:solve{time = 1e308} ran for ever.
local T = require("testlib")
local S = T.script()
local m = talus.model{ gravity = {0, -9.81} }
m:contact_model("linear", { kn = 1e6 })

--- Expects fn (called on the next line of the caller) to fail at that line with `parts`.
local function refused(fn, parts, what)
    local line = debug.getinfo(2, "l").currentline
    table.insert(parts, 1, S .. ":" .. line .. ":")
    T.fails(fn, parts, what)
end

-- derived mass and inertia
refused(function() m:ball{ pos = {0, 0}, radius = 1e300, density = 1000 } end,
    { "ball: radius 1e+300 m is out of range" }, "radius 1e300")
refused(function() m:ball{ pos = {0, 0}, radius = 1e8, density = 1e300 } end,
    { "ball: density 1e+300 and radius 1e+08 give a mass of inf kg" }, "mass overflow")
refused(function() m:ball{ pos = {0, 0}, radius = 1e-13, density = 1000 } end,
    { "ball: radius 1e-13 m is out of range" }, "radius 1e-13")
refused(function() m:ball{ pos = {0, 0}, radius = 1e-6, mass = 1e-310 } end,
    { "ball: mass 1e-310 and radius 1e-06 give a mass of", "not a usable positive number" },
    "a subnormal mass whose inverse overflows")
-- kinetic energies that overflow (balance_error was -inf)
refused(function() m:ball{ pos = {0, 0}, radius = 0.1, density = 1000, spin = 1e300 } end,
    { "ball: spin 1e+300 gives a ball of inertia", "infinite kinetic energy" }, "spin 1e300")
refused(function() m:ball{ pos = {0, 0}, radius = 0.1, density = 1000, vel = {1e300, 0} } end,
    { "ball: vel (1e+300, 0) gives a ball of", "infinite kinetic energy" }, "vel 1e300")
-- NaN is never "not set"
refused(function() m:ball{ pos = {0, 0}, radius = 0.1, mass = 0 / 0 } end,
    { "ball: 'mass' must be a number (got nan)" }, "mass = 0/0")
refused(function() m:ball{ pos = {0, 0}, radius = 0.1, density = 1000, kn = 0 / 0 } end,
    { "ball: 'kn' must be a number (got nan)" }, "kn = 0/0")
refused(function() m:ball{ pos = {0 / 0, 0}, radius = 0.1, density = 1000 } end,
    { "'pos'", "component 1 is nan" }, "pos with a NaN")
local b = m:ball{ pos = {0, 0.2}, radius = 0.05, density = 2600 }
refused(function() b.kn = 0 / 0 end, { "kn", "must be a number (got nan)" }, "b.kn = 0/0")
T.check(b.kn == nil, "the refused kn left the ball's kn unset")
refused(function() b.spin = 1e300 end, { "infinite kinetic energy" }, "b.spin = 1e300")
refused(function() b.vel = {0, -1e300} end, { "infinite kinetic energy" }, "b.vel = 1e300")
refused(function() b.radius = 1e300 end, { "ball: radius 1e+300 m is out of range" }, "b.radius")
refused(function() b.pos = {1e200, 0} end, { "ball: pos (1e+200, 0) is out of range" }, "b.pos")
local big = m:ball{ pos = {50, 50}, radius = 10, density = 1000 }
refused(function() big.density = 1e308 end, { "give a mass of inf kg" }, "density overflow")
T.near(big.mass, 1000 * math.pi * 10 ^ 2, 1e-12, "the ball's mass is unchanged")
big.density = 1e290
refused(function() big.radius = 1e8 end,
    { "density 1e+290 and radius 1e+08 give a moment of inertia of inf" }, "inertia overflow")
T.near(big.radius, 10, 0, "the ball's radius is unchanged")
big:delete()
refused(function() m:contact_model("linear", { kn = 0 / 0 }) end,
    { "contact_model: linear: 'kn' must be a number (got nan)" }, "a model property NaN")
refused(function() m:contact_model("linear", { kn = 1 / 0 }) end,
    { "contact_model: linear: 'kn' must be finite (got inf N/m)" }, "an infinite stiffness")
-- walls far away
refused(function() m:wall{ points = {{-1e200, 0}, {1e200, 0}} } end,
    { "wall: point 1 (-1e+200, 0) is out of range", "1e+09 m" }, "a wall at 1e200 m")
refused(function() m:wall{ points = {{-1, 0}, {1, 0}}, center = {0 / 0, 0} } end,
    { "component 1 is nan" }, "a wall centre with a NaN")
-- durations no run can reach
refused(function() m:solve{ time = 1e308 } end,
    { "solve: time 1e+308 s cannot be reached" }, "solve 1e308")
refused(function() m:solve{ time = 1 / 0 } end, { "solve: time must be >= 0 (got inf)" },
    "solve inf")
refused(function() m:broadphase{ margin = 1e-320 } end,
    { "broadphase: margin must be 0 (automatic) or in [1e-9, 1e9] m" }, "margin 1e-320")

-- what was accepted still runs: the ball bounces on the floor (an undamped linear contact:
-- back up to about its drop height 0.2 m), never through it
m:wall{ points = {{-1, 0}, {1, 0}} }
local lowest = math.huge
for _ = 1, 100 do
    m:solve{ time = 0.01 }
    lowest = math.min(lowest, b.pos[2])
end
T.check(lowest > 0.04 and b.pos[2] < 0.2001, "the ball bounces on the floor, lowest y = " .. lowest)
T.done("input_values")
