-- SPDX-License-Identifier: MIT
-- A bond model sees the contacts the script built where it built them (docs/plugin-guide.md,
-- "When a model first sees a contact"): two balls placed within the bonding gap of a rule that
-- bonds on touch (cbond, cb_bond = 1, cb_gap = 1e-6; pbond, a rule with bonded = 1) and given
-- velocities apart before the first step are bonded, although the first step moves them apart
-- by more than the gap before the first force loop. Before, the law of motion ran first and the
-- bond never formed: no contact, no force, no warning.
local T = require("testlib")

local R, RHO, KN = 0.01, 2600, 1e7
local DT, V = 1e-5, 0.1                      -- each ball moves V DT = 1e-6 m in the first step
local M = RHO * math.pi * R * R              -- 0.817 kg per disk
local MEFF = M / 2
local OMEGA = math.sqrt(KN / MEFF)           -- 4948 rad/s: the bonded pair's relative mode
local AMP = 2 * V / OMEGA                    -- 4.04e-5 m: how far the bond lets them part

--- Two balls, 0.5e-6 m apart (within the 1e-6 m gap), moving apart at V each.
local function pair(model, props, opts)
    opts = opts or {}
    local m = talus.model{ gravity = {0, 0} }
    m:timestep{ fixed = DT }
    m:contact_model(model, props)
    local gap = opts.gap or 0.5e-6
    local a = m:ball{ pos = {0, 0}, radius = R, density = RHO, group = "a" }
    local b = m:ball{ pos = {2 * R + gap, 0}, radius = R, density = RHO, group = "b" }
    a.vel = {-V, 0}
    b.vel = {V, 0}
    if opts.energy then m:energy{ on = true } end  -- (with group books: the groups exist)
    return m, a, b
end

local function theContact(m)
    local found
    for c in m:contacts{} do found = c end
    return found
end

-- 1. cbond, bonded by its rule on the first call. After one step the centres have parted by
-- 2 V DT = 2e-6 m beyond where the bond formed (force-free at its gap, u_ref = u at bonding):
-- F_n = -kn 2 V DT = -20 N, to round-off of the positions.
do
    local m, a, b = pair("cbond", { kn = KN, ks = KN / 2, fric = 0.5, cb_tenf = 1e9,
                                    cb_shearf = 1e9, cb_bond = 1, cb_gap = 1e-6 })
    m:cycle(1)
    local c = theContact(m)
    T.check(c ~= nil, "cbond: the pair is a contact after the first step")
    T.check(c:prop("bonded") == 1, "cbond: the contact is bonded")
    T.near(c.normal_force, -KN * 2 * V * DT, 1e-6, "cbond: the bond's tension after one step")
    -- The bond holds the pair: the relative motion is a harmonic oscillation of the bond's
    -- stiffness and the reduced mass; the centres part by at most 2 V / omega (leapfrog's
    -- amplitude error is O((omega DT)^2) = 0.25%; bound 1%), and then come back together.
    local widest, back = 0, false
    for _ = 1, 200 do
        m:cycle(1)
        local d = b.pos[1] - a.pos[1] - 2 * R - 0.5e-6
        widest = math.max(widest, d)
        back = back or (b.vel[1] - a.vel[1] < 0)
    end
    T.near(widest, AMP, 1e-2, "cbond: the pair parts by 2 V / omega and no more")
    T.check(back, "cbond: the bond pulls the pair back together")
end

-- 2. The same with energy tracing and group books: the bond forms force-free at its gap, so
-- nothing is placed, and the balance closes (the oscillation's energy is the initial kinetic
-- energy, stored and returned by the bond) to the leapfrog's own error for an oscillator: its
-- energy at whole steps swings by (omega DT)^2 / 4 of the total (6e-4 here); bound twice that.
local LEAPFROG = (OMEGA * DT) ^ 2 / 2
do
    local m = pair("cbond", { kn = KN, ks = KN / 2, fric = 0.5, cb_tenf = 1e9, cb_shearf = 1e9,
                              cb_bond = 1, cb_gap = 1e-6 }, { energy = true })
    m:cycle(150)
    local e = m:energies()
    T.near(e.placement, 0, 1e-15, "cbond: a bond formed at a gap places no energy")
    T.check(e.bond + e.strain > 0.1 * e.initial_kinetic, "the bond stores part of the energy")
    T.check(math.abs(e.balance_error) < LEAPFROG * e.initial_kinetic,
        "cbond: balance " .. e.balance_error .. " J of " .. e.initial_kinetic .. " J")
    for _, g in ipairs({ "a", "b" }) do
        local ge = m:energies(g)
        T.check(math.abs(ge.balance_error) < LEAPFROG * e.initial_kinetic,
            "group " .. g .. " balance " .. ge.balance_error)
    end
end

-- 3. pbond, a rule with bonded = 1 (no gap: it bonds at touch): two balls placed touching
-- (1e-9 m of overlap) are bonded at the first call, where they were placed, and held (in
-- tension by the bond's normal stiffness pb_kn 2 R_b = 2e7 N/m alone: they part by at most
-- 2 V / sqrt(2e7 / m_eff) = 2.9e-5 m, less than AMP).
do
    local m, a, b = pair("pbond", { kn = KN, ks = KN / 2, fric = 0.5, pb_kn = 1e9, pb_ks = 5e8,
                                    pb_ten = 1e12, pb_coh = 1e12, pb_rmul = 1, bonded = 1 },
                         { gap = -1e-9 })
    m:cycle(1)
    local c = theContact(m)
    T.check(c ~= nil and c:prop("bonded") == 1, "pbond: bonded after the first step")
    T.check(c.normal_force < 0, "pbond: the bond is in tension: " .. tostring(c and c.normal_force))
    local widest = 0
    for _ = 1, 200 do
        m:cycle(1)
        widest = math.max(widest, b.pos[1] - a.pos[1] - 2 * R)
    end
    T.check(widest < AMP, "pbond: the bond holds the pair (parted by " .. widest .. " m)")
end

-- 4. Placed overlapping: the bond forms at the placed overlap (cbond: u_ref = 0, so F = kn u),
-- its stored energy kn u^2 / 2 is placement energy, booked where it was placed, and the
-- balance closes. The guard notes the placed overlap as it does for any contact.
do
    local u = 1e-4
    local warnings = {}
    local m = pair("cbond", { kn = KN, ks = KN / 2, fric = 0.5, cb_tenf = 1e9, cb_shearf = 1e9,
                              cb_bond = 1, cb_gap = 1e-6 }, { energy = true, gap = -u })
    m:on_warning(function(w) warnings[#warnings + 1] = w end)
    m:cycle(0)  -- a run call of no step: the contact is seen, nothing moves
    local c = theContact(m)
    T.check(c ~= nil and c:prop("bonded") == 1, "placed overlap: bonded at once (cycle(0))")
    T.near(c.normal_force, KN * u, 1e-9, "placed overlap: F = kn u at the placed overlap")
    m:cycle(100)
    local e = m:energies()
    -- The books open at the first step (tracing switched on before it): what the contact held
    -- there is their initial strain energy, kn u^2 / 2 = 0.05 J.
    T.near(e.initial_strain + e.placement, KN * u * u / 2, 1e-6, "placed energy booked")
    T.check(math.abs(e.balance_error) < LEAPFROG * (e.initial_kinetic + KN * u * u / 2),
        "placed overlap: balance " .. e.balance_error)
    local noted = false
    for _, w in ipairs(warnings) do noted = noted or w:find("overlap", 1, true) ~= nil end
    T.check(noted, "the guard notes the placed overlap")
end

-- 4b. Placed overlapping while the books are open: placement energy, half to each ball's group.
do
    local u = 1e-4
    local m = talus.model{ gravity = {0, 0} }
    m:timestep{ fixed = DT }
    m:contact_model("cbond", { kn = KN, ks = KN / 2, fric = 0.5, cb_tenf = 1e9, cb_shearf = 1e9,
                               cb_bond = 1, cb_gap = 1e-6 })
    m:on_warning(function() end)  -- (the placed overlap is meant)
    m:ball{ pos = {0, 0}, radius = R, density = RHO, group = "a" }
    m:energy{ on = true }
    m:cycle(10)
    m:ball{ pos = {2 * R - u, 0}, radius = R, density = RHO, group = "b" }
    m:cycle(100)
    local e = m:energies()
    T.near(e.placement, KN * u * u / 2, 1e-9, "placed while tracing: placement energy")
    T.near(m:energies("a").placement, KN * u * u / 4, 1e-9, "half of it to group a")
    T.check(math.abs(e.balance_error) < LEAPFROG * e.placement, "balance " .. e.balance_error)
end

-- 5. Contacts the script makes between runs: a ball placed within the gap of a bonded pair
-- after a run, and given a velocity away from it, is bonded at the next run call.
do
    local m, a, b = pair("cbond", { kn = KN, ks = KN / 2, fric = 0.5, cb_tenf = 1e9,
                                    cb_shearf = 1e9, cb_bond = 1, cb_gap = 1e-6 })
    m:cycle(10)
    local x = b.pos[1] + 2 * R + 0.5e-6
    local c3 = m:ball{ pos = {x, b.pos[2]}, radius = R, density = RHO }
    c3.vel = {b.vel[1] + V, 0}
    m:cycle(1)
    local bonded = 0
    for c in m:contacts{ ball = c3 } do bonded = bonded + (c:prop("bonded") == 1 and 1 or 0) end
    T.check(bonded == 1, "a ball added between runs is bonded where it was placed")
end

T.done("bond_at_placement")
