-- SPDX-License-Identifier: MIT
-- Servos over sets of walls (m:servo, core/src/step/servo.cpp) against closed forms:
-- 1. a strain rate on an elastic specimen, a column of balls in series between two platens:
--    the platens close at the rate, and the force is the column's stiffness times the closure;
-- 2. a force and a stress target on a linear spring (a fixed ball under a wall): PFC's gain
--    closes the fraction alpha of the error each step, so the force reaches the target
--    geometrically and never passes it;
-- 3. a ramped target and the span length; 4. save and restore mid-ramp; 5. errors.
local T = require("testlib")
local outdir = arg[1] or "."

local R, KN = 0.01, 1e8

-- 1. A column of N balls touching (no overlap), x fixed, between two platens touching the end
-- balls. N + 1 linear contacts in series: F = kn / (N + 1) * closure, closure = gauge * strain
-- (gauge = the platen gap), so F = E * strain with E = kn gauge / (N + 1) [N per unit strain].
do
    local N = 10
    local m = talus.model{}
    m:contact_model("linear", { kn = KN, ks = KN })
    m:damping{ damp = 0.7 }
    for i = 1, N do m:ball{ pos = { 0, (2 * i - 1) * R }, radius = R, density = 2600, fix = { "x", "spin" } } end
    local H = 2 * N * R
    local bottom = m:wall{ points = { { -1, 0 }, { 1, 0 } } }
    local top = m:wall{ points = { { -1, H }, { 1, H } } }
    -- The column's P-wave crossing: N masses m on springs kn, c = 2R sqrt(kn / m) per ball
    -- spacing; the rate strains it by 1e-6 per crossing, so the dynamic part of the force (the
    -- ramp's transient, damped) is far below the tolerance below.
    local mass = 2600 * math.pi * R * R
    local crossing = N * math.sqrt(mass / KN)
    local rate = 1e-6 / crossing
    local ramp = 2000
    local sv = m:servo{ walls = { top, bottom }, rate = rate, ramp = ramp }
    local st = sv:state()
    T.near(st.gauge, H, 1e-15 * H, "rate: the gauge is the platen gap")
    T.check(st.control == "rate" and st.vmax == math.huge, "rate: no speed cap unless given")
    m:cycle(ramp)
    st = sv:state()
    local v = 0.5 * rate * H
    T.near(st.speed, v, 1e-15 * v, "after the ramp each platen moves at rate * gauge / 2")
    T.near(top.vel[2], -v, 1e-15 * v, "the top platen's velocity is the servo's (down)")
    T.near(bottom.vel[2], v, 1e-15 * v, "the bottom platen's velocity is the servo's (up)")
    -- the strain grows at the rate: over n steps of dt, rate n dt
    local e0, t0 = st.strain, m:time()
    m:cycle(20000)
    st = sv:state()
    T.near((st.strain - e0) / (m:time() - t0), rate, 1e-9 * rate, "the strain rate is the rate")
    local gap = top.points[1][2] - bottom.points[1][2]
    T.near(H - gap, st.strain * H, 1e-12 * H, "strain = platen closure / gauge")
    local E = KN * H / (N + 1)
    local F = 0.5 * (st.forces[1] + st.forces[2])
    -- tolerance 1e-3 of the force: the rate's dynamic overstress of a column loaded at 1e-6 per
    -- crossing is of that order of the strain (~1e-6 / strain 4e-3 here), and the damped ramp
    -- transient decays within a few hundred crossings
    print(string.format("column: F %.10g, E strain %.10g, relative %.3g", F, E * st.strain, F / (E * st.strain) - 1))
    T.near(F, E * st.strain, 1e-3 * F, string.format("F = E strain (E %.4g N, strain %.4g)", E, st.strain))
    T.near(st.forces[1], st.forces[2], 1e-3 * F, "top and bottom platens carry the same force")
    sv:remove()
    T.near(top.vel[2], 0, 0, "removed: the platens stop")
end

-- 2. A linear spring: a fixed ball under a wall with a servo. Moving the wall by v dt changes the
-- contact force by kn v dt = alpha (target - F), so the error falls by exactly (1 - alpha) per
-- step once the wall touches, and the force never passes the target (alpha <= 1).
local function spring(opts)
    local m = talus.model{}
    m:contact_model("linear", { kn = KN, ks = KN })
    m:ball{ pos = { 0, R }, radius = R, density = 2600, fix = true }
    local top = m:wall{ points = { { -1, 2 * R + 1e-4 }, { 1, 2 * R + 1e-4 } } }
    opts.walls = { top }
    return m, top, m:servo(opts)
end
do
    local F0 = 1e3
    local m, top, sv = spring{ force = F0, vmax = 0.05, alpha = 0.5 }
    local worst, last_err, ratios = 0, nil, {}
    -- (while the speed is capped at vmax, the wall is still closing in: not counted)
    local capped = true
    for _ = 1, 400 do
        m:cycle(1)
        local st = sv:state()
        local f = st.force
        worst = math.max(worst, f)
        local err = F0 - f
        if last_err and not capped and last_err > 1e-6 * F0 then ratios[#ratios + 1] = err / last_err end
        last_err = f > 0 and err or nil
        capped = math.abs(st.speed) >= 0.05
    end
    T.check(worst <= F0 * (1 + 1e-12), string.format("force: no overshoot (largest %.15g of %g)", worst, F0))
    T.near(sv:state().force, F0, 1e-9 * F0, "force: held at the target")
    local rmin, rmax = math.huge, -math.huge
    for i = 2, #ratios do rmin = math.min(rmin, ratios[i]); rmax = math.max(rmax, ratios[i]) end
    T.near(rmin, 0.5, 1e-6, "the error falls by 1 - alpha per step (smallest ratio)")
    T.near(rmax, 0.5, 1e-6, "the error falls by 1 - alpha per step (largest ratio)")
    -- a new target: the ramp takes it there linearly, the force follows within a step's lag
    sv:set{ force = 2 * F0, ramp = 100 }
    m:cycle(50)
    local f = sv:state().force
    T.check(f > 1.4 * F0 and f < 1.5 * F0, string.format("ramped target: %.4g at half the ramp", f))
    m:cycle(200)
    T.near(sv:state().force, 2 * F0, 1e-9 * F0, "ramped target reached")
end

-- 3. Stress over a fixed length and over the gap between two walls (span).
do
    local S0, Lf = 5e4, 0.02
    local m, top, sv = spring{ stress = S0, length = Lf, vmax = 1 }
    m:cycle(500)
    local st = sv:state()
    T.near(st.stress, S0, 1e-9 * S0, "stress target over a length")
    T.near(st.force, S0 * Lf, 1e-9 * S0 * Lf, "force = stress x length")
    local a = m:wall{ points = { { 5, -0.5 }, { 6, -0.5 } } }
    local b = m:wall{ points = { { 5, 0.25 }, { 6, 0.25 } } }
    st = sv:set{ span = { a, b } }
    m:cycle(500)
    st = sv:state()
    T.near(st.length, 0.75, 1e-15, "span: the length is the gap between the two walls")
    T.near(st.force, S0 * 0.75, 1e-9 * S0, "span: the force is the stress over that gap")
end

-- 4. Save mid-ramp and restore: the restored model goes on bit-identically.
do
    local function scene()
        local m = talus.model{}
        m:contact_model("linear", { kn = KN, ks = KN })
        m:damping{ damp = 0.7 }
        for i = 1, 4 do m:ball{ pos = { 0, (2 * i - 1) * R }, radius = R, density = 2600, fix = { "x" } } end
        local bottom = m:wall{ points = { { -1, 0 }, { 1, 0 } } }
        local top = m:wall{ points = { { -1, 8 * R }, { 1, 8 * R } } }
        m:servo{ walls = { top, bottom }, rate = 50, ramp = 300 }
        return m
    end
    local m = scene()
    m:cycle(100)
    local file = outdir .. "/servo_walls.sav"
    m:save(file)
    m:cycle(400)
    local r = talus.restore(file)
    r:cycle(400)
    local function text(x) return T.state_text(x, { walls = true }) end
    T.check(text(m) == text(r), "save mid-ramp, restore: the same state after 400 more steps")
end

-- 5. Errors name the servo and what is wrong.
do
    local m = talus.model{}
    m:contact_model("linear", { kn = KN, ks = KN })
    m:ball{ pos = { 0, R }, radius = R, density = 2600 }
    local w1 = m:wall{ points = { { -1, 0 }, { 1, 0 } } }
    local w2 = m:wall{ points = { { -1, 3 * R }, { 1, 3 * R } } }
    T.fails(function() m:servo{ walls = { w1 } } end, { "give a target" }, "no target")
    T.fails(function() m:servo{ walls = { w1 }, rate = 1, force = 2 } end, { "give one target" }, "two targets")
    T.fails(function() m:servo{ walls = { w1 }, rate = 1 } end, { "a rate needs gauge" }, "rate, one wall")
    T.fails(function() m:servo{ walls = { w1, w1 }, force = 1 } end, { "listed twice" }, "a wall twice")
    local sv = m:servo{ walls = { w1 }, force = 1 }
    T.fails(function() m:servo{ walls = { w1, w2 }, force = 1 } end, { "is moved by servo 1" }, "a wall in two servos")
    T.fails(function() sv:set{ alpha = 3 } end, { "alpha must be in (0, 2)" }, "alpha")
    T.fails(function() sv:set{ rat = 1 } end, { "did you mean 'rate'" }, "did you mean")
    T.fails(function() m:servo{ walls = { 5 }, force = 1 } end, { "must be a wall" }, "not a wall")
    sv:remove()
    T.fails(function() sv:state() end, { "no such servo" }, "removed")
end

T.done("servo_walls")
