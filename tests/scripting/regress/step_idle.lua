-- SPDX-License-Identifier: MIT
-- The automatic step of an idle scene: with nothing moving and no gravity the growth rule used to double the
-- step every cycle (6e26 s after 100 steps, t = inf at step 1034), and the first step after
-- gravity, an applied force or a velocity appeared gave the ball 1e27 m/s. Now an idle step is
-- bounded by the scene's time scales (docs/physics/timestep.md, "Idle scenes") and the step
-- after it restarts the integrator, so the motion that starts is exact.
local T = require("testlib")

local g = 9.81
local R, rho, kn = 0.1, 1000, 1e6
local mass = rho * math.pi * R * R

-- 1. A lone ball, no gravity, no walls: no pair gives a time scale, so the step is the documented
-- 1 ms, kept while idle; time advances by exactly steps * dt.
do
    local m = talus.model{}
    m:contact_model("linear", { kn = kn })
    m:ball{ pos = {0, 0}, radius = R, density = rho }
    for _ = 1, 12 do
        m:cycle(100)
        T.check(m:dt() == 1e-3, "idle step stays 1 ms, got " .. m:dt())
        T.check(m:timestep().rule == "idle", "rule " .. m:timestep().rule)
    end
    T.near(m:time(), 1.2, 1e-12, "time after 1200 idle steps")
end

-- 2. Idle, then gravity / an applied force / a velocity. The wall is 0.2 m below the ball, beyond
-- the broadphase margin (no pair). From the change on the ball moves as the closed form says, to
-- round-off (the restart makes the first velocity update use half the new step only; before it,
-- half of the huge idle step went into it); then it lands on the wall with an overlap no deeper
-- than a linear impact at the closing speed: v sqrt(m/k) plus the static overlap 2 m a / k for
-- the load (energy bound), + 5% for the discrete contact.
for _, what in ipairs({"gravity", "fapp", "vel"}) do
    local m = talus.model{}
    m:contact_model("linear", { kn = kn })
    m:wall{ points = {{-1, -0.1}, {1, -0.1}} }
    local b = m:ball{ pos = {0, 0.2}, radius = R, density = rho }
    m:cycle(100)
    T.check(m:dt() <= 1e-3, what .. ": idle step bounded, got " .. m:dt())
    local a, v0 = 0, 0
    if what == "gravity" then
        m:gravity({0, -g}); a = g
    elseif what == "fapp" then
        b.fapp = {0, -100}; a = 100 / mass
    else
        b.vel = {0, -1}; v0 = 1
    end
    local t0, y0 = m:time(), b.pos[2]
    -- free flight until the ball is within 1 cm of the wall: exact to round-off (1e-12 m)
    local steps = 0
    while b.pos[2] > 0.01 and steps < 100000 do
        m:cycle(1)
        steps = steps + 1
        local t = m:time() - t0
        T.near(b.pos[2], y0 - v0 * t - 0.5 * a * t * t, 1e-12, what .. ": free flight after idle, step " .. steps)
    end
    T.check(steps > 1 and steps < 100000, what .. ": free flight took " .. steps .. " steps")
    local v_touch = math.sqrt(v0 * v0 + 2 * a * 0.2)
    local bound = 1.05 * (v_touch * math.sqrt(mass / kn) + 2 * mass * a / kn)
    local lowest = math.huge
    for _ = 1, 500 do
        m:cycle(1)
        lowest = math.min(lowest, b.pos[2])
    end
    T.check(0 - lowest <= bound, string.format("%s: overlap %.4g m > bound %.4g m", what, -lowest, bound))
end

-- 3. A ball resting 1 mm above a floor (a broadphase pair): the idle step is the step that pair's
-- contact would need, pi sqrt(m/kn) / 30 (resolution rule; the approach rule's limit); after
-- gravity appears the first loaded step overlaps by at most one such step's travel,
-- (sqrt(2 g gap) + g dt) dt, as for a ball released at rest (tests/core/test_timestep.cpp).
do
    local gap = 1e-3
    local m = talus.model{}
    m:contact_model("linear", { kn = kn })
    m:wall{ points = {{-1, 0}, {1, 0}} }
    local b = m:ball{ pos = {0, R + gap}, radius = R, density = rho }
    m:cycle(200)
    local dt_res = math.pi * math.sqrt(mass / kn) / 30
    T.near(m:dt(), dt_res, 1e-12, "idle step near a floor = the pair's resolved step")
    T.check(m:timestep().rule == "idle", "rule " .. m:timestep().rule)
    m:gravity({0, -g})
    local first
    for _ = 1, 3000 do
        m:cycle(1)
        if not first and b.pos[2] < R then first = R - b.pos[2] end
    end
    local travel = (math.sqrt(2 * g * gap) + g * dt_res) * dt_res
    T.check(first and first <= travel * (1 + 1e-9), string.format("first overlap %s > %.4g", tostring(first), travel))
end

T.done("step_idle")
