-- SPDX-License-Identifier: MIT
-- The servo's equilibrium hold (m:servo{hold = {ratio, max_steps}}, core/src/step/servo.cpp)
-- against closed forms, on the elastic column of servo_walls.lua (N balls in series between two
-- platens, E = kn gauge / (N + 1) per unit strain):
-- 1. step by step, the platens stop when the mechanical ratio at the start of the step rises
--    above the limit and move again once it falls to the resume ratio, their speed rising
--    linearly to rate * gauge / 2 over the ramp;
-- 2. where they resume, the column is in equilibrium: F = E strain to the ratio;
-- 3. the cap: a hold ends after max_steps, then the platens move until the ratio falls;
-- 4. save and restore in the middle of a hold; 5. errors.
local T = require("testlib")
local outdir = arg[1] or "."

local R, KN, N = 0.01, 1e8, 10
local H = 2 * N * R
local mass = 2600 * math.pi * R * R
local crossing = N * math.sqrt(mass / KN)
local E = KN * H / (N + 1)

local function column()
    local m = talus.model{}
    m:contact_model("linear", { kn = KN, ks = KN })
    m:damping{ damp = 0.7 }
    for i = 1, N do m:ball{ pos = { 0, (2 * i - 1) * R }, radius = R, density = 2600, fix = { "x", "spin" } } end
    local bottom = m:wall{ points = { { -1, 0 }, { 1, 0 } } }
    local top = m:wall{ points = { { -1, H }, { 1, H } } }
    return m, top, bottom
end

-- The relative error of the platens' mean force against E strain.
local function force_error(st)
    return 0.5 * (st.forces[1] + st.forces[2]) / (E * st.strain) - 1
end

-- 1 and 2: the column loaded at 2e-5 strain per P-wave crossing, its middle ball kicked at a
-- strain of 4e-4 (a stand-in for a crack cascade: a burst of unbalanced force). The hold stops
-- the platens when the ratio rises above 2e-3 (above the loading's own ratio, ~4e-4 at this
-- rate) and lets them go once it is at or below 1e-4. The servo's state machine is replayed in
-- Lua step by step; where the platens resume, the column is in equilibrium to the ratio: every
-- contact carries the same force to within about N x the resume ratio, so F = E strain within
-- 2 N x 1e-4 = 2e-3. The same kick without the hold leaves the force off by more than that.
local rate = 2e-5 / crossing
local hi, lo = 2e-3, 1e-4
local function load(hold)
    local m, top, bottom = column()
    local sv = m:servo{ walls = { top, bottom }, rate = rate, ramp = 2000 }
    local v = 0.5 * rate * H
    -- loaded to 2e-4 first: a column whose contacts carry no force yet has an unbounded ratio
    -- (the first touches), and the hold is for a loaded material
    while sv:state().strain < 2e-4 do m:cycle(10) end
    if hold then sv:set{ hold = hold } end
    local kicked, steps, holding, wrong, held, since = false, 0, false, 0, 0, -1
    local resumed, worst, after_kick = 0, 0, 0
    while sv:state().strain < 1e-3 do
        if not kicked and sv:state().strain > 4e-4 then
            for b in m:balls() do
                if b.id == N // 2 then b.vel = { 0, 10 * v } end
            end
            kicked = true
        end
        m:cycle(1)
        steps = steps + 1
        local st = sv:state()
        if hold then
            -- the servo's rule: a hold starts above `hi` and ends at or below `lo`; then the
            -- speed rises again over the ramp's 2000 steps
            local was = holding
            if holding then holding = st.ratio > lo else holding = st.ratio > hi end
            local want = 0
            if not holding then
                if was then since = 0 end
                want = since < 0 and v or v * math.min(1, (since + 1) / 2000)
                if since >= 0 then since = since + 1 end
            end
            if math.abs(st.speed - want) > 1e-12 * v then wrong = wrong + 1 end
            if holding then held = held + 1 end
            if was and not holding then
                resumed = resumed + 1
                worst = math.max(worst, math.abs(force_error(st)))
            end
        elseif kicked then
            after_kick = math.max(after_kick, math.abs(force_error(st)))
        end
        if steps > 100000 then error("the column did not reach its strain") end
    end
    return { steps = steps, wrong = wrong, held = held, resumed = resumed, worst = worst, after_kick = after_kick,
             st = sv:state() }
end
local free = load(nil)
local with = load{ ratio = hi, resume = lo, max_steps = 100000 }
print(string.format("column at 2e-5 per crossing, kicked: without the hold max |F/(E strain) - 1| after the kick "
    .. "%.3g (%d steps); with it %.3g where the platens resumed (%d times), %d steps, %d held in %d holds",
    free.after_kick, free.steps, with.worst, with.resumed, with.steps, with.st.held, with.st.holds))
T.check(with.wrong == 0, string.format("the platens stand still exactly while held (%d steps wrong)", with.wrong))
T.check(with.held > 0 and with.st.held == with.held, "the column held, and the servo counts its held steps")
T.check(with.resumed > 0, "the platens resumed")
T.check(with.worst < 2 * N * lo, string.format("at every resume F = E strain within 2 N x resume (%.3g)", with.worst))
T.check(free.after_kick > 2 * N * lo,
    string.format("without the hold the kicked column is off by more (%.3g)", free.after_kick))

-- 3. The cap: a limit no state reaches holds max_steps, then the platens move (and keep moving,
-- the ratio never falling to the limit), so a test always ends.
do
    local m, top, bottom = column()
    local sv = m:servo{ walls = { top, bottom }, rate = rate, hold = { ratio = 1e-300, max_steps = 50 } }
    m:cycle(1)
    -- at the first step no contact carries a force yet: an infinite ratio holds nothing
    local st = sv:state()
    T.check(st.ratio == math.huge and st.held == 0 and st.speed > 0, "no contact force: the platens move")
    local m2, top2, bottom2 = column()
    -- pressed first, so that every contact carries a force
    local pre = m2:servo{ walls = { top2, bottom2 }, rate = rate }
    m2:cycle(2000)
    pre:remove()
    sv = m2:servo{ walls = { top2, bottom2 }, rate = rate, hold = { ratio = 1e-300, max_steps = 50 } }
    m2:cycle(50)
    st = sv:state()
    T.check(st.held == 50 and st.speed == 0 and st.holds == 1, "held for max_steps")
    m2:cycle(100)
    st = sv:state()
    T.check(st.held == 50 and st.holds_capped == 1 and st.speed > 0,
        string.format("after the cap the platens move (held %d, capped %d)", st.held, st.holds_capped))
end

-- 4. Saved in the middle of a hold and restored: the restored servo holds the rest of it and
-- then moves, bit for bit as the one that went on (a servo restored without its hold would move
-- at once).
do
    local function text(x) return T.state_text(x, { walls = true }) end
    local m, top, bottom = column()
    local pre = m:servo{ walls = { top, bottom }, rate = rate }
    m:cycle(2000)
    pre:remove()
    local sv = m:servo{ walls = { top, bottom }, rate = rate, hold = { ratio = 1e-300, max_steps = 50 } }
    m:cycle(20)
    local file = outdir .. "/servo_hold.sav"
    m:save(file)
    m:cycle(100)
    T.check(sv:state().held == 50, "the servo held 50 steps")
    local r = talus.restore(file)
    r:cycle(100)
    T.check(text(m) == text(r), "saved mid-hold, restored: the same state after 100 more steps")
end

-- 5. Errors.
do
    local m, top, bottom = column()
    T.fails(function() m:servo{ walls = { top, bottom }, stress = 1e6, hold = { ratio = 1e-3, max_steps = 10 } } end,
        { "hold: an equilibrium hold stops walls that move at a rate" }, "a hold on a stress servo")
    T.fails(function() m:servo{ walls = { top, bottom }, rate = 1, hold = { ratio = 1e-3 } } end,
        { "give the ratio limit and the longest hold" }, "a hold without max_steps")
    T.fails(function() m:servo{ walls = { top, bottom }, rate = 1, hold = { ratio = -1, max_steps = 10 } } end,
        { "hold: ratio must be > 0" }, "a negative ratio")
    T.fails(function() m:servo{ walls = { top, bottom }, rate = 1, hold = { ratio = 1e-3, max_steps = 0 } } end,
        { "max_steps must be >= 1" }, "a zero cap")
    T.fails(function() m:servo{ walls = { top, bottom }, rate = 1, hold = { ratoi = 1e-3, max_steps = 1 } } end,
        { "did you mean 'ratio'" }, "a misspelt option")
    local sv = m:servo{ walls = { top, bottom }, rate = 1, hold = { ratio = 1e-3, max_steps = 10 } }
    sv:set{ hold = false }
    T.check(sv:state().hold == nil, "hold = false switches it off")
end
T.done("servo_hold")
