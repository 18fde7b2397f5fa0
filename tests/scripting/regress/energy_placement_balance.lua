-- SPDX-License-Identifier: MIT
-- Bodies created overlapping, and the run-level energy check.
local T = require("testlib")

-- 1. A ball created 40% of its radius inside a stiff wall (dashpot 0.7) leaves with far more
-- energy than it had: that energy is booked as `placement`, one warning names the contact, and
-- the balance closes. Tolerance: the release is resolved by the resolution rule, so the books
-- close to the order of a resolved impact (1e-4 of the throughput). (This test placed the ball
-- of a stress seed 68% into a wall, its centre on the far side of the segment: such a placement
-- is refused now, see the end of the block.)
do
    local m = talus.model{ gravity = {0, 0} }
    local kn = 841855499579.6508
    m:contact_model("linear", { kn = kn, ks = 0.3 * kn, fric = 0.5, dp_nratio = 0.7, dp_sratio = 0.2 })
    local warnings = {}
    m:on_warning(function(text) warnings[#warnings + 1] = text end)
    m:wall{ points = {{-1, 0}, {2, 0}} }
    local R = 0.10354907335659588
    local overlap = 0.4 * R
    m:ball{ pos = {0.5, R - overlap}, radius = R, density = 19129.25279341629, vel = {-2, -3}, spin = -17.55 }
    m:energy{ on = true }
    m:cycle(500)
    local e = m:energies()
    -- stored energy of a linear spring at the placement overlap (the shear spring starts
    -- unloaded): kn u^2 / 2, less the approach within the first step (< 1%)
    T.near(e.placement, 0.5 * kn * overlap ^ 2, 0.02, "placement ~ kn u^2 / 2 (approach share < 1%)")
    T.check(e.kinetic > 10 * e.initial_kinetic, "the ball was launched by the placed overlap")
    local throughput = e.initial_kinetic + e.placement
    T.check(math.abs(e.balance_error) < 1e-4 * throughput, "balance closes: " .. e.balance_error)
    local placed = 0
    for _, w in ipairs(warnings) do
        if w:find("started overlapping", 1, true) then
            placed = placed + 1
            T.check(w:find("ball 1", 1, true) and w:find("overlap 0.0414", 1, true) and w:find("placement", 1, true), w)
        end
    end
    T.check(placed == 1, "one aggregated warning, got " .. placed)
    -- the stress seed's ball, its centre 0.033 m behind the right arm of the V (68% of its radius
    -- in it): refused at placement, naming the segment
    local v = talus.model{}
    v:wall{ points = {{0, 2.0}, {1.0, 0}, {1.1, 0.04}, {2.0, 2.0}} }
    T.fails(function()
        v:ball{ pos = {1.5022551249554357, 0.8371770663479843}, radius = R, density = 1000 }
    end, { "ball: pos (1.50226, 0.837177) puts its centre 0.0329", "wall 1 segment 3",
           "at most half its radius" }, "a ball placed through a wall")
end

-- 2. The run-level check: energy put into a contact behind the engine's back (a script pushing
-- a resting ball 2 mm deeper into the floor: the books see the strain appear with no work behind
-- it; a velocity the script sets is booked as `script`, script_work_energy.lua) is reported,
-- naming the window and `strain` as the item that moved most; with balance = "error" the run
-- stops at the script line.
do
    local m = talus.model{ gravity = {0, -9.81} }
    m:contact_model("linear", { kn = 1e6 })
    m:wall{ points = {{-1, 0}, {1, 0}} }
    local b = m:ball{ pos = {0, 0.1}, radius = 0.1, density = 1000 }
    m:energy{ on = true }
    m:guard{ balance = "error" }
    m:timestep{ fixed = 1e-4 }
    m:cycle(100)
    T.check(math.abs(m:energies().balance_error) < 1e-4 * m:energies().input, "the ball settles")
    b.pos = {0, b.pos[2] - 0.002}
    local l = T.line(); T.fails(function() m:cycle(10) end,
        { "regress/energy_placement_balance.lua:" .. l .. ":", "energy balance:", "J created",
          "of the throughput", "in steps 100-110", "strain +" }, "unbooked energy stops the run")
end

-- 3. No false alarm in what users run for hours: a damped ball bouncing to rest on a floor and
-- resting there for 20,000 steps, and a ball rolling across a wall chain (warnings collected).
do
    local m = talus.model{ gravity = {0, -9.81} }
    m:contact_model("linear", { kn = 1e6, ks = 1e6, fric = 0.5, dp_nratio = 0.3 })
    local warnings = {}
    m:on_warning(function(text) warnings[#warnings + 1] = text end)
    m:wall{ points = {{-5, 0}, {5, 0}} }
    m:ball{ pos = {0, 0.5}, radius = 0.05, density = 2600, vel = {0.5, 0} }
    m:energy{ on = true }
    m:cycle(20000)
    for _, w in ipairs(warnings) do T.check(not w:find("energy balance", 1, true), w) end
    local e = m:energies()
    T.check(math.abs(e.balance_error) < 1e-3 * e.input, "bounce-to-rest balance " .. e.balance_error)
end
-- 4. Tracing switched on in a loaded packing (the UCS workflow: generate, settle, then trace):
-- what the contacts hold is `initial_strain`, not energy created. A column of five balls at rest
-- holds sum over contacts of F^2 / (2 kn), F_k = k m g at the k-th contact from the top (linear).
do
    local m = talus.model{ gravity = {0, -9.81} }
    local kn = 1e6
    m:contact_model("linear", { kn = kn, ks = kn, fric = 0.5, dp_nratio = 0.3 })
    local warnings = {}
    m:on_warning(function(text) warnings[#warnings + 1] = text end)
    m:wall{ points = {{-1, 0}, {1, 0}} }
    local balls = {}
    for k = 0, 4 do balls[#balls + 1] = m:ball{ pos = {0, 0.1 + 0.2 * k}, radius = 0.1, density = 1000 } end
    m:cycle(20000)
    m:energy{ on = true }
    m:cycle(4000)
    local e = m:energies()
    local w, held = balls[1].mass * 9.81, 0
    -- the model's kn is the contact's stiffness, ball-ball and ball-wall alike
    for k = 1, 5 do held = held + (k * w) ^ 2 / (2 * kn) end
    T.near(e.initial_strain, held, 1e-6, "initial_strain = what the column holds")
    T.check(math.abs(e.balance_error) < 1e-9 * held, "books balance in the packing: " .. e.balance_error)
    T.check(#warnings == 0, "no warning: " .. tostring(warnings[1]))
end
-- 5. A ball deleted in the middle of an impact leaves with its kinetic energy (`deleted`) and its
-- contact's stored energy (`released`); the books of what remains still close (stress seed 67
-- lost 3.8% of its throughput there). The impact is cut short, so its mid-impact discretisation
-- error (~2e-3 of its energy at 30 steps per impact) stays in the books: the deletion itself may
-- add no more than 1e-3 of the input (without the booking it adds the ball's 45 J).
do
    local m = talus.model{ gravity = {0, -9.81} }
    m:contact_model("linear", { kn = 1e6, ks = 1e6, fric = 0.5 })
    m:wall{ points = {{-1, 0}, {1, 0}} }
    local a = m:ball{ pos = {-0.3, 0.2}, radius = 0.1, density = 1000 }
    local b = m:ball{ pos = {0.3, 0.2}, radius = 0.1, density = 1000, vel = {0, -1} }
    m:energy{ on = true }
    local deleted, before = false, nil
    while not deleted do
        m:cycle(1)
        local c
        for x in m:contacts{} do if x.ball1 == b or x.ball2 == b then c = x end end
        if c and c.overlap > 1e-3 then before = m:energies().balance_error; b:delete(); deleted = true end
    end
    m:cycle(3)
    local e = m:energies()
    T.check(e.deleted > 40 and e.released > 0, "deleted " .. e.deleted .. ", released " .. e.released)
    T.check(math.abs(e.balance_error - before) < 1e-3 * e.input, "balance after a deletion: " .. e.balance_error .. " J, before it " .. before .. " J")
end
print("energy_placement_balance: " .. T.checks .. " checks passed")
