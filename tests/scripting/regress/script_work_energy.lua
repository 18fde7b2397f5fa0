-- SPDX-License-Identifier: MIT
-- Work done by the script is booked as `script`, so the balance closes (docs/physics/energy.md,
-- "Work done by the script"). Every scene here is free flight under gravity, whose balance closes
-- to round-off step by step: each script action must keep it there, and `script` must equal the
-- change of the kinetic energy the next snapshot takes, in closed form. The snapshot at the start
-- of a step takes v(t) = v_half + a dt_prev / 2 (a the acceleration of the step, dt_prev the step
-- before), one step behind m:time().
-- Before: a velocity set, a ball added, a gravity change were booked nowhere: 1.0e+04 J created
-- for a ball at rest set to 10 m/s; a ball added at 1 m/s created its 0.5 m v^2; a gravity change
-- created m v . dg dt / 2 (74% of the throughput one step after it for a ball at the top of its
-- flight).
local T = require("testlib")

local DT = 1e-3
local G = -9.81
local ROUND = 1e-12 -- of the throughput

local function scene(opts)
    opts = opts or {}
    local m = talus.model{ gravity = { 0, G } }
    m:contact_model("linear", { kn = 1e7 })
    m:timestep{ fixed = DT }
    if opts.damping then m:damping(opts.damping) end
    local b = m:ball{ pos = { 0, 10 }, radius = 0.1, density = 1000, vel = { 1, 2 }, spin = 3,
                      group = "a" }
    local c = m:ball{ pos = { 5, 10 }, radius = 0.1, density = 2000, vel = { -1, 0 }, group = "b" }
    m:energy{ on = true }
    m:cycle(20)
    return m, b, c
end

-- The balance (whole model and each group) is what it was before the action (`base`, taken
-- before it; free flight closes to round-off, with local damping to a constant left by the first
-- cycle), to round-off of the input.
local function balances(m)
    return { m:energies().balance_error, m:energies("a").balance_error, m:energies("b").balance_error }
end
local function closes(m, what, base, slack)
    local e = m:energies()
    local now = balances(m)
    for k, name in ipairs({ "whole model", "group a", "group b" }) do
        T.check(math.abs(now[k] - base[k]) <= ROUND * e.input + (slack or 0),
            string.format("%s: %s balance_error %.6g J, before the action %.6g J (input %.3g J)",
                what, name, now[k], base[k], e.input))
    end
    return e
end

-- The kinetic energy the next snapshot takes for a free body with half-step velocity v, spin w,
-- acceleration a (no moment).
local function ke(mass, inertia, v, w, a)
    local vx, vy = v[1] + a[1] * DT / 2, v[2] + a[2] * DT / 2
    return 0.5 * mass * (vx * vx + vy * vy) + 0.5 * inertia * w * w
end

-- Runs the action between two steps and checks script = expected (a function of the state before,
-- called before the action) and that the balance stays closed for 200 more steps.
local function check(what, act, expected, opts)
    local m, b, c = scene(opts)
    local before, base = m:energies().script, balances(m)
    local want = expected(m, b, c)
    act(m, b, c)
    m:cycle(2) -- the snapshot of the next step takes the change; energies() lags one step
    local slack = opts and opts.slack
    local e = closes(m, what, base, slack)
    if want then T.near(e.script - before, want, 1e-11, what .. ": script") end
    m:cycle(200)
    closes(m, what .. ", 200 steps on", base, slack)
    return m, e
end

check("velocity set", function(_, b) b.vel = { 10, -3 } end, function(_, b)
    return ke(b.mass, b.inertia, { 10, -3 }, b.spin, { 0, G }) - ke(b.mass, b.inertia, b.vel, b.spin, { 0, G })
end)
check("spin set", function(_, b) b.spin = -40 end, function(_, b)
    return 0.5 * b.inertia * (40 * 40 - b.spin * b.spin)
end)
check("ball added at 1 m/s", function(m)
    m:ball{ pos = { -5, 10 }, radius = 0.2, density = 2600, vel = { 1, 0 }, group = "b" }
end, function()
    local mass = 2600 * math.pi * 0.04
    return ke(mass, 0, { 1, 0 }, 0, { 0, G })
end)
do -- a ball deleted: its energy leaves as `deleted`, nothing is script work
    local m, _, c = scene()
    local want = ke(c.mass, c.inertia, c.vel, c.spin, { 0, G })
    local before, base = m:energies(), balances(m)
    c:delete()
    m:cycle(2)
    local e = closes(m, "ball deleted", base)
    T.near(e.deleted - before.deleted, want, 1e-11, "ball deleted: deleted")
    T.check(e.script == before.script, "ball deleted: no script work")
end
check("gravity changed", function(m) m:gravity({ 3, -20 }) end, function(_, b, c)
    local w = 0
    for _, x in ipairs({ b, c }) do
        w = w + ke(x.mass, x.inertia, x.vel, x.spin, { 3, -20 }) - ke(x.mass, x.inertia, x.vel, x.spin, { 0, G })
    end
    return w
end)
check("density changed", function(_, b) b.density = 3000 end, function(_, b)
    return (3000 / 1000 - 1) * ke(b.mass, b.inertia, b.vel, b.spin, { 0, G })
end)
check("radius changed", function(_, b) b.radius = 0.2 end, function(_, b)
    return (4 - 1) * ke(b.mass, 0, b.vel, 0, { 0, G }) + (16 - 1) * 0.5 * b.inertia * b.spin * b.spin
end)
check("applied force set", function(_, b) b.fapp = { 50, 100 } end, function(_, b)
    local a = { 50 / b.mass, G + 100 / b.mass }
    return ke(b.mass, b.inertia, b.vel, b.spin, a) - ke(b.mass, b.inertia, b.vel, b.spin, { 0, G })
end)
-- a fixed component keeps its velocity; the fixity's reaction R = -m g does the work R v dt / 2
-- before the snapshot (an input, `boundary`): together -m g^2 dt^2 / 8
check("y fixed", function(_, b) b.fix = { "y" } end, function(_, b)
    return ke(b.mass, b.inertia, b.vel, b.spin, { 0, 0 }) + DT / 2 * b.mass * G * b.vel[2]
        - ke(b.mass, b.inertia, b.vel, b.spin, { 0, G })
end)
do -- moved up: gravity's work is booked as it is done (`body`), so nothing is booked for the move
    local m, b = scene()
    local before, base = m:energies().script, balances(m)
    b.pos = { 0, 30 }
    m:cycle(300)
    local e = closes(m, "moved up", base)
    T.check(e.script == before, "a move books no script work")
end
do -- set from inside a callback, every 50 steps
    local m, b = scene()
    local base = balances(m)
    m:on_cycle(function() b.vel = { b.vel[1] + 1, 5 } end, 50)
    m:cycle(400)
    local e = closes(m, "set from on_cycle", base)
    T.check(e.script > 0, "on_cycle: script work booked")
end
-- with damping: the snapshot also splits the damping impulse (local: at t; viscous: v_mid)
check("velocity set, local damping", function(_, b) b.vel = { -4, 7 } end, function() end,
    { damping = { damp = 0.3 } })
-- Viscous damping leaves the scheme's own residual (D_0^2 - D_n^2) dt^2 / (8 m), D = c m v the
-- damping force (docs/physics/energy.md), which the new velocity changes: up to
-- c^2 m v^2 dt^2 / 4 here (c = 2 /s, m = 31.4 kg, |v| < 8.1 m/s: 2e-3 J, against ~1e3 J unbooked).
check("velocity set, viscous damping", function(_, b) b.vel = { -4, 7 } end, function() end,
    { damping = { viscous = 2 }, slack = 2e-3 })
check("damping changed", function(m) m:damping{ damp = 0.5, viscous = 1 } end, function() end,
    { slack = 2e-3 })
check("spin fixed, local damping", function(_, b) b.fix = { "spin", "x" } end, function() end,
    { damping = { damp = 0.2 } })

-- Clumps: a rigid body's kinetic energy, 1/2 (m v^2 + I w^2), at the snapshot.
local function clumpScene()
    local m = talus.model{ gravity = { 0, G } }
    m:contact_model("linear", { kn = 1e7 })
    m:timestep{ fixed = DT }
    local k = m:clump{ pebbles = { { -0.1, 0, 0.1 }, { 0.1, 0, 0.1 } }, pos = { 0, 10 }, density = 1000,
                       vel = { 1, 1 }, spin = 2, group = "a" }
    local b1 = m:ball{ pos = { 5, 10 }, radius = 0.1, density = 2000, vel = { -1, 0 }, spin = 5, group = "b" }
    local b2 = m:ball{ pos = { 5.3, 10 }, radius = 0.1, density = 2000, vel = { 1, 2 }, spin = -1, group = "b" }
    m:energy{ on = true }
    m:cycle(20)
    return m, k, b1, b2
end
local function clumpCheck(what, act, expected)
    local m, k, b1, b2 = clumpScene()
    local before, base = m:energies(), balances(m)
    local want = expected(k, b1, b2)
    act(m, k, b1, b2)
    m:cycle(2)
    local e = closes(m, what, base)
    if want then T.near(e.script - before.script, want, 1e-11, what .. ": script") end
    m:cycle(200)
    closes(m, what .. ", 200 steps on", base)
    return e, before
end
clumpCheck("clump velocity and spin set", function(_, k) k:set{ vel = { -3, 4 }, spin = 10 } end,
    function(k) return ke(k.mass, k.inertia, { -3, 4 }, 10, { 0, G }) - ke(k.mass, k.inertia, k.vel, k.spin, { 0, G }) end)
-- two balls made one clump: momentum is kept, kinetic energy is not
clumpCheck("clump made of balls", function(m, _, b1, b2) m:clump{ balls = { b1, b2 } } end, function() end)
clumpCheck("clump released", function(_, k) k:release() end, function() end)
do
    local e, before = clumpCheck("clump deleted", function(_, k) k:delete() end, function() return 0 end)
    T.check(e.deleted > before.deleted, "clump deleted: its energy leaves as deleted")
end
-- A change made before a save is booked after the restore as in the run that went on.
do
    local m, b = scene()
    b.vel = { 7, 7 }
    local path = os.tmpname()
    m:save(path)
    local r = talus.restore(path, { quiet = true })
    os.remove(path)
    m:cycle(50)
    r:cycle(50)
    local e, f = m:energies(), r:energies()
    T.check(e.script ~= 0 and e.script == f.script and e.balance_error == f.balance_error,
        "save and restore between a change and the next step: script " .. e.script .. " / " .. f.script)
end
T.done("script_work_energy")
