-- SPDX-License-Identifier: MIT
-- A contact bonded as it touches is an impact all the same (the time step
-- part). The time step used to give bonded contacts the stability rule
-- only, against docs/models/cbond.md: the impact took 4-5 steps (the step doubled through it)
-- and created 25 J of the 66.8 J put in (38%). Now the resolution rule holds through the bonded
-- impact: dt = pi sqrt(m/kn) / 30.
local T = require("testlib")

local R, rho, kn = 0.1, 1000, 3.3e7
local mass = rho * math.pi * R * R
local m = talus.model{}
m:contact_model("cbond", { kn = kn, ks = 4.8e6, fric = 0.6, cb_bond = 1, cb_tenf = 0, cb_shearf = math.huge, cb_gap = 2.2e-9 })
m:wall{ points = {{-1, 0}, {1, 0}} }
local b = m:ball{ pos = {0, 0.101}, radius = R, density = rho, vel = {0.5, -2} }
m:energy{ on = true }
local warnings = {}
m:on_warning(function(text) warnings[#warnings + 1] = text end)
local breaks = 0
m:on_event("bond_break", function() breaks = breaks + 1 end)

local dt_res = math.pi * math.sqrt(mass / kn) / 30
local bonded_steps, was_bonded = 0, false
for _ = 1, 400 do
    m:cycle(1)
    local c = m:contacts{}()
    local bonded = c ~= nil and c:prop("bonded") == 1
    -- every step taken while the bond held (the step is chosen before the cycle, so from the
    -- second bonded cycle on) is the resolved one
    if bonded and was_bonded then
        bonded_steps = bonded_steps + 1
        T.check(m:dt() <= dt_res * (1 + 1e-12), string.format("bonded step %.4g > resolved %.4g (%s)", m:dt(), dt_res, m:timestep().reason))
    end
    was_bonded = bonded
end
T.check(breaks == 1, "one bond break, got " .. breaks)
-- The bond breaks at the first tension, near the end of the half period pi sqrt(m/kn): about 30
-- resolved steps (the defect: 5).
T.check(bonded_steps >= 25, "steps while bonded: " .. bonded_steps)
T.check(b.vel[2] > 0, "the ball rebounds")
-- The books close to 1% of the energy put in (the bound; measured 0.46%, the rest is the
-- bond's released-energy booking in cbond.cpp, a separate item; the defect: 38%).
local e = m:energies()
local input = 0.5 * mass * (0.5 ^ 2 + 2 ^ 2)
T.near(e.initial_kinetic or input, input, 1e-9, "input")
T.check(math.abs(e.balance_error) <= 0.01 * input, string.format("balance error %.4g J vs input %.4g J", e.balance_error, input))
for _, w in ipairs(warnings) do
    T.check(not w:find("fewer than", 1, true) and not w:find("gave back more energy", 1, true), w)
end

T.done("step_cbond_impact")
