-- SPDX-License-Identifier: MIT
-- Energy per group with clumps (analytic cases): a clump
-- is one body of its groups; its pebbles' contacts pass work to other groups through the
-- clump's motion (docs/physics/energy.md "Energy per group", docs/physics/clumps.md).
local T = require("testlib")

local ITEMS = { "body", "boundary", "kinetic", "strain", "slip", "dashpot", "damping",
                "initial_kinetic", "exchanged", "balance_error" }

-- 1. Free fall of a clump: body work = kinetic energy gained, per group and in total. Leapfrog
--    integrates constant gravity exactly, so the only error is round-off (1e-12 relative).
do
    local m = talus.model{ gravity = {0, -9.81} }
    m:contact_model("linear", { kn = 1e8 })
    local c = m:clump{ pebbles = { {-0.1, 0, 0.1}, {0.05, 0, 0.12} }, pos = {0, 5}, angle = 0.3,
                       density = 2600, vel = {1, 2}, spin = 3, group = "rock" }
    m:energy{ on = true }
    m:cycle(500)
    local e, t = m:energies("rock"), m:energies()
    T.near(e.body, e.kinetic - e.initial_kinetic, 1e-12 * e.kinetic, "free fall: body = kinetic gained")
    T.near(e.initial_kinetic, 0.5 * (c.mass * 5 + c.inertia * 9), 1e-12 * e.initial_kinetic,
        "a clump counts once, with its own mass and inertia")
    for _, k in ipairs(ITEMS) do T.near(e[k], t[k], 1e-12 * t.input, "free fall: rock = total, " .. k) end
end

-- 2. A clump sliding to rest on a frictional floor: the slip of its group is the kinetic energy
--    it lost. Stiff contacts (kn = 1e10 N/m: the static overlap m g / (2 kn) ~ 1e-7 m) make the
--    settling energy m g u ~ 1e-4 J against 1/2 m v0^2 = 320 J; critical normal damping removes
--    the settling bounce. Tolerance 1e-3 of the initial kinetic energy.
do
    local m = talus.model{ gravity = {0, -9.81} }
    m:contact_model("linear", { kn = 1e10, ks = 5e9, fric = 0.4, dp_nratio = 1 })
    m:wall{ points = { {-5, 0}, {20, 0} }, group = "floor" }
    local r = 0.1
    local c = m:clump{ pebbles = { {-0.1, r, r}, {0.1, r, r} }, density = 2600, vel = {2, 0},
                       group = "rock" }
    m:energy{ on = true }
    m:solve{ time = 1.5 }  -- stops after v0 / (mu g) = 0.51 s
    local e = m:energies("rock")
    T.check(math.abs(c.vel[1]) < 1e-6, "the clump came to rest (vx " .. c.vel[1] .. ")")
    T.near(e.slip, e.initial_kinetic, 1e-3 * e.initial_kinetic, "slip = kinetic energy lost")
    T.near(e.exchanged, 0, 1e-12 * e.initial_kinetic, "a fixed floor exchanges nothing")
    local f = m:energies("floor")
    T.near(f.slip, 0, 0, "ball-wall contacts book to the ball's group only")
end

-- 3. A clump (group "rock") hits a resting block of 3 x 3 balls (group "block"), no gravity.
--    Over the partition the exchanged items are equal and opposite (round-off), every group's
--    balance closes to the integration's accuracy (1% of its input is the guard's criterion;
--    measured ~1e-4), and the groups' items sum to the totals.
do
    local m = talus.model{}
    m:contact_model("linear", { kn = 1e8, ks = 5e7, fric = 0.3, dp_nratio = 0.05 })
    for i = 0, 2 do
        for j = 0, 2 do
            m:ball{ pos = {0.5 + 0.2 * i, -0.2 + 0.2 * j}, radius = 0.1, density = 2600, group = "block" }
        end
    end
    m:clump{ pebbles = { {-0.15, 0.05, 0.1}, {0.05, -0.05, 0.12} }, pos = {-0.4, 0.03}, density = 2600,
             vel = {4, 0}, spin = 2, group = "rock" }
    m:energy{ on = true }
    m:solve{ time = 0.5 }
    local a, b, t = m:energies("rock"), m:energies("block"), m:energies()
    T.check(a.exchanged < -1, "the clump gave work to the block (" .. a.exchanged .. " J)")
    T.near(a.exchanged, -b.exchanged, 1e-12 * t.input, "exchanged: equal and opposite")
    for _, k in ipairs(ITEMS) do
        T.near(a[k] + b[k], t[k], 1e-12 * t.input, "partition sums to the total: " .. k)
    end
    for name, e in pairs({ rock = a, block = b, total = t }) do
        T.check(math.abs(e.balance_error) < 1e-2 * e.input,
            name .. ": balance closes (" .. e.balance_error .. " J of " .. e.input .. " J)")
    end
end

print("clump group energy: ok")
