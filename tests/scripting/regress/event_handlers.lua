-- SPDX-License-Identifier: MIT
-- m:on_event handlers chain: a second handler of a kind is added beside the first (both run,
-- in the order of registration), m:remove_on_event(handle) removes one, on_event(kind, nil)
-- removes all of the kind. A library routine removes only the handler it added: a user's
-- recorder on a specimen sees every bond that breaks inside M.compress, and still hears later
-- ones. (Before, a second on_event replaced the first, and M.compress's cleanup removed the
-- user's: the recorder saw 0 breaks while 42 bonds broke.)
local T = require("testlib")
local M = require("material")

-- 1. Balls that graze a wall one after the other; each contact bonds (cbond, cb_bond = 1) and
-- the weak bond (cb_shearf = 1 N) breaks in shear in its first step: one break per ball, at
-- times that differ (the balls start 0.5, 1.5 and 2.5 mm above the wall, falling at 1 cm/s).
local m = talus.model{}
m:contact_model("cbond", { kn = 1e8, ks = 1e8, fric = 0.5, cb_bond = 1, cb_gap = 1e-4, cb_tenf = 10, cb_shearf = 1 })
m:wall{ points = { { -10, 0 }, { 10, 0 } } }
for k = 0, 2 do
    m:ball{ pos = { 2 * k, 0.1 + 5e-4 + 1e-3 * k }, radius = 0.1, density = 1000, vel = { 1, -0.01 } }
end
local order = {}
local h1 = m:on_event("bond_break", function(ev) order[#order + 1] = { "first", ev.time } end)
local h2 = m:on_event("bond_break", function(ev) order[#order + 1] = { "second", ev.time } end)
T.check(math.type(h1) == "integer" and math.type(h2) == "integer" and h1 ~= h2, "on_event returns a handle")
repeat m:cycle(100) until #order > 0 or m:step() > 100000
T.check(#order == 2, "one break, both handlers ran (" .. #order .. " calls)")
T.check(order[1][1] == "first" and order[2][1] == "second", "in the order of registration")
T.check(order[1][2] == order[2][2], "the same event")
local t_first = order[1][2]

-- 2. remove_on_event: the next break reaches only the handler left
T.check(m:remove_on_event(h1) == true, "remove_on_event says it removed")
T.check(m:remove_on_event(h1) == false, "a handle removed twice: false")
local n0 = #order
repeat m:cycle(100) until #order > n0 or m:step() > 200000
T.check(#order == n0 + 1 and order[#order][1] == "second" and order[#order][2] > t_first,
    "after remove_on_event(first), the next break reaches the second only")

-- 3. a handler that adds another and removes itself during delivery: the one added waits for
-- the next event, the removal holds from then on
local log = {}
m:on_event("bond_break", nil) -- removes every bond_break handler
local self_h
self_h = m:on_event("bond_break", function()
    log[#log + 1] = "self"
    m:remove_on_event(self_h)
    m:on_event("bond_break", function() log[#log + 1] = "added" end)
end)
repeat m:cycle(100) until #log > 0 or m:step() > 400000
T.check(#log == 1 and log[1] == "self", "the third break: a handler added during delivery does not get that event ("
    .. #log .. " calls)")
T.check(#order == n0 + 1, "on_event(kind, nil) removed the second handler")

-- 4. M.compress beside a user's recorder: the recorder sees every break of the test, and is
-- still registered afterwards.
local pk = M.genesis{ width = 0.01, height = 0.02, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16,
                      kn = 6.4e10, ks = 9.6e9, seed = 3 }
local sp = M.specimen(pk, { model = "cbond", kn = 6.4e10, ks = 9.6e9, fric = 0.5, density = 2600,
                            bond = { cb_tenf = 4.6e4, cb_shearf = 4.6e5 } })
local seen = 0
local mine = sp.model:on_event("bond_break", function() seen = seen + 1 end)
local r = M.compress(sp, { post_peak = 0.8, strain_per_crossing = 2e-5 })
local n = r.breaks.tension + r.breaks.shear
T.check(n > 0, "bonds broke in the test (" .. n .. ")")
T.check(seen == n, string.format("the user's recorder saw %d of the %d breaks", seen, n))
T.check(sp.model:remove_on_event(mine) == true, "the user's handler is still registered after M.compress")
T.done("event_handlers")
