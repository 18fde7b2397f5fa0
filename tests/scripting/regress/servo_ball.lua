-- SPDX-License-Identifier: MIT
-- Wall servo (core/src/step/wall_servo.cpp) on the smallest scene with a closed form: one ball
-- between a fixed floor and a servo wall above it, no gravity. At equilibrium the servo wall
-- carries the target force F, so does the floor, and each contact overlaps F / kn (linear).
local T = require("testlib")

local R, KN, F = 0.1, 1e8, 1e4

local function scene(servo)
    local m = talus.model{ gravity = {0, 0} }
    m:contact_model("linear", { kn = KN, ks = KN, fric = 0.5 })
    local floor = m:wall{ points = {{-1, 0}, {1, 0}} }
    local b = m:ball{ pos = {0, R}, radius = R, density = 2600 }
    local top = m:wall{ points = {{-1, 2 * R + 0.01}, {1, 2 * R + 0.01}} }
    m:damping{ damp = 0.7 }
    local st = top:servo(servo)
    return m, floor, b, top, st
end

-- 1. Defaults: the direction is the wall's normal toward the material (down), PFC's gain.
do
    local m, floor, b, top, st = scene{ force = F, vmax = 0.1 }
    T.near(st.dir[1], 0, 0, "default direction x")
    T.near(st.dir[2], -1, 0, "default direction: into the material (down)")
    T.check(st.on and st.mode == "force" and st.target == F and st.alpha == 0.5, "settings")
    -- Before any contact the wall moves at vmax toward the ball.
    m:cycle(1)
    st = top:servo()
    T.near(st.vel, 0.1, 0, "no contact: moves at vmax")
    T.check(st.gain == math.huge, "no contact stiffness: infinite gain")
    T.near(top.vel[2], -0.1, 1e-15, "the wall's velocity is the servo's")
    local worst = 0
    for _ = 1, 200 do
        m:cycle(20)
        worst = math.max(worst, top.force[2])
    end
    st = top:servo()
    -- Equilibrium: the servo's error decays by (1 - alpha) per step once the ball is at rest;
    -- after 4000 steps the force is at the target to rounding. 1e-9 relative.
    T.near(st.force, F, 1e-9 * F, "servo force reaches the target")
    T.near(top.force[2], F, 1e-9 * F, "the servo reads the wall force the model reports")
    T.near(floor.force[2], -F, 1e-9 * F, "the floor carries the same force")
    -- Overlaps F / kn = 1e-4 m at both walls: ball centre at R - F/kn, wall at 2R - 2F/kn.
    T.near(b.pos[2], R - F / KN, 1e-12, "ball overlaps the floor by F/kn")
    T.near(top.points[1][2], 2 * R - 2 * F / KN, 1e-12, "servo wall overlaps the ball by F/kn")
    T.near(st.gain, 0.5 / (KN * m:dt()), 1e-12 * st.gain, "PFC gain alpha / (kn dt)")
    -- The approach at vmax = 0.1 m/s loads the contact by kn vmax dt per step before the gain
    -- takes over (here 1e8 * 0.1 * 2.6e-5 = 260 N), and local damping holds the ball, so the
    -- force never overshoots the target by more than a few percent (measured 1.00 F + < 3%).
    T.check(worst < 1.05 * F, string.format("no overshoot: peak %.6g N for a target of %g N", worst, F))
    -- Off: the wall stops; the target can change later.
    st = top:servo{ on = false }
    T.check(not st.on and top.vel[2] == 0, "servo off stops the wall")
    m:cycle(10)
    T.near(top.points[1][2], 2 * R - 2 * F / KN, 1e-12, "switched off: the wall stays")
    st = top:servo{ on = true, force = 2 * F }
    m:cycle(4000)
    T.near(top:servo().force, 2 * F, 1e-9 * F, "a new target is reached")
end

-- 2. Stress form: stress = force / length, gain alpha L / (kn dt).
do
    local m, floor, b, top = scene{ stress = F / 0.5, length = 0.5, vmax = 0.1 }
    m:cycle(4000)
    local st = top:servo()
    T.check(st.mode == "stress" and st.length == 0.5, "stress form settings")
    T.near(st.stress, F / 0.5, 1e-9 * F, "stress target reached")
    T.near(st.force, F, 1e-9 * F, "force = stress * length")
    T.near(st.gain, 0.5 * 0.5 / (KN * m:dt()), 1e-12 * st.gain, "PFC gain alpha L / (kn dt)")
    T.near(b.pos[2], R - F / KN, 1e-12, "overlap F/kn")
end

-- 3. The gain matters. Start in contact (the wall touching the ball) so only the control law
-- acts. The quasi-static error obeys e' = (1 - alpha) e: with PFC's gain (alpha = 0.5) the force
-- never passes the target; a fixed gain 5 times larger (alpha = 2.5 > 2) is unstable: the error
-- grows by 1.5 per step until the speed cap holds it, a limit cycle of +-kn vmax dt / 2 about
-- the target (measured 5.8e3 to 1.58e4 N for 1e4 N). So the check can fail, and it is the gain
-- that decides.
local function peak(opts)
    local m = talus.model{ gravity = {0, 0} }
    m:contact_model("linear", { kn = KN, ks = KN, fric = 0.5 })
    m:wall{ points = {{-1, 0}, {1, 0}} }
    m:ball{ pos = {0, R}, radius = R, density = 2600, fix = true }
    local top = m:wall{ points = {{-1, 2 * R - 1e-6}, {1, 2 * R - 1e-6}} }
    m:timestep{ fixed = 1e-5 }
    m:cycle(1)  -- the contact forms (100 N): the servo's first step has its stiffness
    opts.force = F
    top:servo(opts)
    local worst, last = 0, 0
    for _ = 1, 400 do
        m:cycle(1)
        worst = math.max(worst, top.force[2])
        last = top.force[2]
    end
    return worst, last
end
local worst, last = peak{ vmax = 10 }
T.check(worst <= F * (1 + 1e-9), string.format("formula gain: no overshoot (peak %.9g)", worst))
T.near(last, F, 1e-9 * F, "formula gain: converges")
local bad_gain = 5 * 0.5 / (KN * 1e-5)
worst, last = peak{ vmax = 10, gain = bad_gain }
T.check(worst > 1.5 * F, string.format("5x the gain overshoots (peak %.6g)", worst))
T.check(math.abs(last - F) > 0.1 * F, "5x the gain does not settle")

-- 4. Bad input names what and where.
do
    local m = talus.model{}
    local w = m:wall{ points = {{0, 0}, {1, 0}} }
    T.fails(function() w:servo{ vmax = 1 } end, { "wall 1: servo: the first call needs a target" },
        "no target")
    T.fails(function() w:servo{ force = 1, stress = 1 } end, { "not both" }, "both targets")
    T.fails(function() w:servo{ force = 1 } end, { "no balls to tell the material's side" },
        "no default direction without balls")
    T.fails(function() w:servo{ force = 1, dir = {0, 1}, alpha = 3 } end,
        { "wall 1 servo: alpha must be in (0, 2)" }, "alpha range")
    T.fails(function() w:servo{ force = 1, dir = {0, 0} } end, { "dir must be a finite non-zero" },
        "zero direction")
    T.fails(function() w:servo{ force = 1, dir = {0, 1}, vmax = -1 } end, { "vmax must be > 0" },
        "vmax")
    T.fails(function() w:servo{ forse = 1 } end, { "unknown option 'forse'" }, "typo")
    T.check(w:servo() == nil, "no servo: nil")
end

T.done("servo_ball")
