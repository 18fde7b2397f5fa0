-- SPDX-License-Identifier: MIT
-- m:solve's criteria (core/src/api/solve.cpp) and m:unbalanced() (core/src/api/measure.cpp).
local T = require("testlib")

local KN, R = 1e7, 0.1
local function drop()
    local m = talus.model{ gravity = {0, -9.81} }
    m:contact_model("linear", { kn = KN, ks = KN, fric = 0.5 })
    m:wall{ points = {{-1, 0}, {1, 0}} }
    local b = m:ball{ pos = {0, 0.3}, radius = R, density = 2600 }
    m:damping{ damp = 0.7 }
    return m, b
end

-- 1. A ball settles on a floor: solve{ratio} stops when the mean unbalanced force over the mean
-- contact force is 1e-5. One body, one contact: |kn d - m g| <= 1e-5 kn d, so the overlap is
-- m g / kn to 1e-5.
do
    local m, b = drop()
    local u0 = m:unbalanced()
    T.check(u0.ratio == math.huge and u0.contacts == 0, "no contact force yet: ratio infinite")
    local reason = m:solve{ ratio = 1e-5 }
    T.check(reason == "ratio", "stops on the ratio: " .. tostring(reason))
    local u = m:unbalanced()
    T.check(u.ratio <= 1e-5 and u.bodies == 1 and u.contacts == 1, "ratio reached: " .. u.ratio)
    T.near(u.mean_contact, b.mass * 9.81, 1e-5 * b.mass * 9.81, "contact force = weight")
    T.near(u.max_unbalanced, u.mean_unbalanced, 0, "one body: max = mean")
    T.near(u.ratio, u.mean_unbalanced / u.mean_contact, 1e-15, "ratio = mean unbalanced / mean contact")
    local overlap = R - b.pos[2]
    T.near(overlap, b.mass * 9.81 / KN, 1e-5 * b.mass * 9.81 / KN, "overlap m g / kn")
    print(string.format("solve_ratio: settled in %d steps, t = %.4f s, ratio %.3g", m:step(), m:time(), u.ratio))
    -- Again: the ratio is judged after each step, so at least one is taken (the ball still
    -- oscillates below 1e-5 under local damping: measured 62 steps to the next crossing).
    local s0 = m:step()
    T.check(m:solve{ ratio = 1e-5 } == "ratio", "at rest: ratio again")
    T.check(m:step() > s0, "at least one step")
end

-- 2. steps, until, time and their combinations: the first reached wins.
do
    local m = drop()
    local s0 = m:step()
    T.check(m:solve{ steps = 10 } == "steps" and m:step() == s0 + 10, "steps = 10")
    T.check(m:solve{ steps = 0 } == "steps" and m:step() == s0 + 10, "steps = 0 takes none")
    s0 = m:step()
    local seen
    local reason = m:solve{ ["until"] = function(mm) seen = mm; return mm:step() >= s0 + 7 end }
    T.check(reason == "until" and m:step() == s0 + 7, "until stops when it returns true")
    T.check(seen == m, "until gets the model")
    s0 = m:step()
    T.check(m:solve{ steps = 5, time = 1e3 } == "steps" and m:step() == s0 + 5, "steps before time")
    local t0 = m:time()
    T.check(m:solve{ steps = 100000, time = 1e-3 } == "time", "time before steps")
    T.near(m:time(), t0 + 1e-3, 1e-15, "time lands exactly")
    T.check(m:solve{ time = 1e-3 } == "time", "time alone returns 'time'")
end

-- 3. Caps end the run with a message naming the cap and the target not reached.
do
    local m = drop()
    local warnings = {}
    m:on_warning(function(text) warnings[#warnings + 1] = text end)
    local s0 = m:step()
    T.check(m:solve{ ratio = 1e-15, max_steps = 50 } == "max_steps", "max_steps cap")
    T.check(m:step() == s0 + 50, "the cap's steps")
    local w = warnings[#warnings] or ""
    T.check(w:find("solve: stopped by the cap max_steps = 50 after 50 steps", 1, true) and
        w:find("before reaching ratio 1e-15", 1, true), "cap message: " .. w)
    -- the wall-clock cap: 1 ns has passed by the first check (the outcome is deterministic)
    T.check(m:solve{ ratio = 1e-15, max_time = 1e-9 } == "max_time", "max_time cap")
    T.check((warnings[#warnings] or ""):find("max_time = 1e-09 s (wall clock)", 1, true), "max_time message")
    -- a cap alone is a criterion; a target reached first wins over it
    s0 = m:step()
    T.check(m:solve{ max_steps = 3 } == "max_steps" and m:step() == s0 + 3, "max_steps alone")
    T.check(m:solve{ steps = 3, max_steps = 3 } == "steps", "target before cap at the same step")
    -- a ball in flight has no contact force: the ratio is never reached
    local f = talus.model{ gravity = {0, -9.81} }
    f:on_warning(function() end)
    f:ball{ pos = {0, 10}, radius = R, density = 2600 }
    T.check(f:solve{ ratio = 1e-3, max_steps = 10 } == "max_steps", "no contacts: ratio not reached")
end

-- 4. solve{time} alone keeps the old path (Model::solveTime); the general loop with a cap that
-- is never reached takes exactly the same steps: the states agree to the last bit.
do
    local a, ba = drop()
    local b, bb = drop()
    a:solve{ time = 0.2 }
    T.check(b:solve{ time = 0.2, max_steps = 1000000000 } == "time", "general path: time")
    T.check(a:step() == b:step() and a:time() == b:time(), "same steps and time")
    T.check(ba.pos[1] == bb.pos[1] and ba.pos[2] == bb.pos[2] and ba.vel[2] == bb.vel[2],
        "bit-identical state")
end

-- 5. Errors.
do
    local m = drop()
    local l = T.line(); T.fails(function() m:solve{} end,
        { T.script() .. ":" .. l .. ":", "solve: give a criterion" }, "no criterion")
    T.fails(function() m:solve{ ratio = -1 } end, { "solve: ratio must be >= 1e-15" }, "ratio < 0")
    T.fails(function() m:solve{ ratio = 1e-320 } end, { "solve: ratio must be >= 1e-15" },
        "a ratio below rounding")
    T.fails(function() m:solve{ ["until"] = 3 } end, { "'until' must be a function" }, "until type")
    T.fails(function() m:solve{ steps = -2 } end, { "'steps' must be >= 0" }, "steps < 0")
    T.fails(function() m:solve{ max_steps = 0 } end, { "'max_steps' must be >= 1" }, "max_steps")
    T.fails(function() m:solve{ max_time = 0 } end, { "max_time must be > 0" }, "max_time")
    T.fails(function() m:solve{ max_time = math.huge } end, { "at most 1e9" }, "max_time inf")
    T.fails(function() m:solve{ ratoi = 1e-5 } end,
        { "solve: unknown option 'ratoi'; did you mean 'ratio'? (known: " }, "typo")
    -- an error in the until function keeps its own line and stops the run
    local s0 = m:step()
    l = T.line(); T.fails(function() m:solve{ ["until"] = function() error("boom") end } end,
        { T.script() .. ":" .. l .. ":", "boom" }, "until error")
    T.check(m:step() == s0 + 1, "the failing until stopped the run after its step")
end

T.done("solve_ratio")
