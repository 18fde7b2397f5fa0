-- SPDX-License-Identifier: MIT
-- The bond_break event carries the bond's half width, read from the model as the bond broke
-- (docs/plugin-abi.md, "Bonds"; Event::radius), and the crack drawn from it is as long as the
-- bond is wide. A pair pulled apart ends its contact in the breaking step, so by the time the
-- event is delivered its model is a fresh object: the cracks took the smaller ball's radius,
-- exact only for pb_rmul = 1 (pb_rmul 0.5 gave 6 mm for a 3 mm bond). Balls of R 10 mm and 6 mm,
-- bonded at touch, pulled apart at 2 m/s.
local T = require("testlib")

local function pulled(model, props)
    local m = talus.model{ gravity = { 0, 0 } }
    m:contact_model(model, props)
    local a = m:ball{ pos = { -0.01 + 0.5e-9, 0 }, radius = 0.01, density = 2600 }
    local b = m:ball{ pos = { 0.006 - 0.5e-9, 0 }, radius = 0.006, density = 2600 }
    m:cycle(1)
    T.check(m:contact_count{} == 1, model .. ": bonded at touch")
    local events = {}
    m:on_event("bond_break", function(ev) events[#events + 1] = ev end)
    a.vel = { -1, 0 }
    b.vel = { 1, 0 }
    m:cycle(2000)
    T.check(#events == 1, model .. ": one break, got " .. #events)
    T.check(m:contact_count{} == 0, model .. ": the contact ended with the break")
    return events[1], m:cracks()[1]
end

local strong = { kn = 1e6, ks = 1e6, fric = 0.5 }
for _, rmul in ipairs({ 0.5, 1.5 }) do
    local props = { pb_kn = 1e12, pb_ks = 5e11, pb_ten = 1e6, pb_coh = 1e8, bonded = 1, pb_rmul = rmul }
    for k, v in pairs(strong) do props[k] = v end
    local ev, crack = pulled("pbond", props)
    T.near(ev.radius, rmul * 0.006, 1e-15, "pbond pb_rmul " .. rmul .. ": event radius")
    T.near(crack.radius, rmul * 0.006, 1e-15, "pbond pb_rmul " .. rmul .. ": crack radius")
    T.near(crack.width, 2 * rmul * 0.006, 1e-15, "pbond pb_rmul " .. rmul .. ": crack width")
end

-- A flat joint: its interface's half length fj_radius = fj_rmul min(R).
local ev = pulled("fjoint", { fj_kn = 1e12, fj_ks = 5e11, fj_ten = 1e6, fj_coh = 1e8, fj_nr = 4,
                              fj_fric = 0.5, bonded = 1, fj_rmul = 0.7 })
T.near(ev.radius, 0.7 * 0.006, 1e-15, "fjoint fj_rmul 0.7: event radius")

-- A contact bond has no size of its own: the smaller ball's radius.
local ev_cb, crack_cb = pulled("cbond", { kn = 1e6, ks = 1e6, fric = 0.5, cb_tenf = 1, cb_shearf = 100,
                                          cb_bond = 1 })
T.near(ev_cb.radius, 0.006, 1e-15, "cbond: the smaller ball's radius")
T.near(crack_cb.radius, 0.006, 1e-15, "cbond: crack radius")
print(string.format("bond_break_radius: %d checks passed", T.checks))
