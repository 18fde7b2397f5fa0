-- SPDX-License-Identifier: MIT
-- pbond: bond_break events carry the stresses at failure, and an unbreakable bond is
-- pb_ten = math.huge (docs/models/pbond.md). The bond's forces move linearly inside a step, and
-- the model finds where on that path the strength was met (bisection to rounding), so the
-- event's stresses are the strength itself: sigma = pb_ten for a tension break, tau = pb_coh for
-- a shear break with pb_fa = 0. Tolerance 1e-12 relative: the bisection leaves 2^-60 of one
-- step's stress increment, the rest is rounding.
local T = require("testlib")

local R, RHO = 0.01, 2600
local TEN, COH = 1e6, 2e6

local function pair(extra)
    local m = talus.model{ gravity = {0, 0} }
    local p = { kn = 1e6, ks = 1e6, fric = 0.5, pb_kn = 1e12, pb_ks = 5e11, pb_ten = TEN,
                pb_coh = COH, bonded = 1 }
    for k, v in pairs(extra or {}) do p[k] = v end
    m:contact_model("pbond", p)
    local a = m:ball{ pos = {-R + 0.5e-9, 0}, radius = R, density = RHO }
    local b = m:ball{ pos = {R - 0.5e-9, 0}, radius = R, density = RHO }
    m:cycle(1)
    local events = {}
    m:on_event("bond_break", function(ev) events[#events + 1] = ev end)
    return m, a, b, events
end

local function rel(a, b) return math.abs(a - b) / math.abs(b) end

-- 1. Tension: the disks fly apart; sigma at failure is pb_ten.
do
    local m, a, b, events = pair()
    a.vel = {-0.5, 0}
    b.vel = {0.5, 0}
    m:cycle(2000)
    T.check(#events == 1 and events[1].mode == "tension", "tension: one tension break")
    local ev = events[1]
    print(string.format("pbond_events tension: sigma %.15g Pa, tau %.3g Pa", ev.sigma, ev.tau))
    T.check(rel(ev.sigma, TEN) < 1e-12, "tension: sigma at failure " .. ev.sigma .. " = pb_ten")
    T.check(ev.tau >= 0 and ev.tau < COH, "tension: tau " .. ev.tau .. " below the shear strength")
end

-- 2. Shear: opposite tangential velocities, pb_fa = 0: tau at failure is pb_coh.
do
    local m, a, b, events = pair{ pb_ten = 1e8 }
    a.vel = {0, -2}
    b.vel = {0, 2}
    m:cycle(2000)
    T.check(#events == 1 and events[1].mode == "shear", "shear: one shear break")
    local ev = events[1]
    print(string.format("pbond_events shear: tau %.15g Pa, sigma %.3g Pa", ev.tau, ev.sigma))
    T.check(rel(ev.tau, COH) < 1e-12, "shear: tau at failure " .. ev.tau .. " = pb_coh")
    T.check(ev.sigma < 1e8, "shear: sigma " .. ev.sigma .. " below pb_ten")
    -- The contact's own record agrees (pb_sigma, pb_tau hold the values at failure).
    for c in m:contacts{} do
        T.check(c:prop("pb_state") == 2, "shear: pb_state broken in shear")
        T.check(c:prop("pb_tau") == ev.tau, "shear: pb_tau = the event's tau")
    end
end

-- 3. Unbreakable: pb_ten = math.huge (a +inf strength passes the host's check for a stress)
-- holds the disks together where pb_ten = TEN broke; -inf is refused with the name.
do
    local m, a, b, events = pair{ pb_ten = math.huge, pb_coh = math.huge }
    for c in m:contacts{} do T.check(c:prop("pb_ten") == math.huge, "pb_ten reads back inf") end
    a.vel = {-0.5, 0}
    b.vel = {0.5, 0}
    m:cycle(2000)
    T.check(#events == 0, "unbreakable: no break")
    T.check(m:contact_count{} == 1, "unbreakable: still in contact")
    for c in m:contacts{} do T.check(c:prop("pb_state") == 3, "unbreakable: still bonded") end
    local probe = talus.model{}
    T.fails(function() probe:contact_model("pbond", { pb_ten = -math.huge }) end, { "pb_ten" },
            "-inf is no strength")
    T.fails(function() probe:contact_model("pbond", { pb_emod = math.huge }) end, { "pb_emod" },
            "a modulus stays finite")
end

-- 4. cbond reports no stresses: the event has no sigma.
do
    local m = talus.model{ gravity = {0, 0} }
    m:contact_model("cbond", { kn = 1e6, ks = 1e6, fric = 0.5, cb_tenf = 1, cb_shearf = 1, cb_bond = 1 })
    local a = m:ball{ pos = {-R + 1e-7, 0}, radius = R, density = RHO }
    local b = m:ball{ pos = {R - 1e-7, 0}, radius = R, density = RHO }
    m:cycle(1)
    local events = {}
    m:on_event("bond_break", function(ev) events[#events + 1] = ev end)
    a.vel = {-0.5, 0}
    b.vel = {0.5, 0}
    m:cycle(200)
    T.check(#events == 1 and events[1].sigma == nil, "cbond: an event without stresses")
end
print("pbond_events: " .. T.checks .. " checks passed")
