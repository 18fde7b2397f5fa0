-- SPDX-License-Identifier: MIT
-- A pair whose bond broke and which separated is not bonded again when it touches again:
-- neither a bond installed by m:bond (the pair goes back to the
-- ordinary rules) nor one a cbond rule with cb_bond = 1 makes on touch (the host remembers the
-- pair and sets kFdNoAutoBond). Before this, the cb_bond rule bonded the re-formed contact.
local T = require("testlib")

local R, RHO = 0.1, 2600

-- Two balls overlapping by 1e-4 m on the x axis, no gravity.
local function pair(m)
    local a = m:ball{ pos = {-R + 5e-5, 0}, radius = R, density = RHO }
    local b = m:ball{ pos = {R - 5e-5, 0}, radius = R, density = RHO }
    return a, b
end

local function theContact(m)
    for c in m:contacts{} do return c end
    return nil
end

-- Pulls the pair apart at 1 m/s until it has separated, then drives it together again until it
-- touches; returns the re-formed contact and the bond breaks seen.
local function breakSeparateTouch(m, a, b)
    local breaks = 0
    m:on_event("bond_break", function(ev)
        breaks = breaks + 1
        T.check(ev.mode == "tension", "a tension break, got " .. tostring(ev.mode))
    end)
    a.vel, b.vel = {-0.5, 0}, {0.5, 0}
    local steps = 0
    repeat
        m:cycle(10)
        steps = steps + 10
    until (theContact(m) == nil and b.pos[1] - a.pos[1] > 2 * R + 1e-3) or steps > 100000
    T.check(theContact(m) == nil, "the broken pair separated")
    a.vel, b.vel = {0.5, 0}, {-0.5, 0}
    local c
    repeat
        m:cycle(1)
        c = theContact(m)
        steps = steps + 1
    until (c and c.overlap > 0) or steps > 200000
    T.check(c ~= nil, "the pair touches again")
    return c, breaks
end

-- 1. A bond installed by m:bond, the ordinary rule `linear`: the re-formed contact is linear.
do
    local m = talus.model{ gravity = {0, 0} }
    m:contact_model("linear", { kn = 1e8, ks = 5e7, fric = 0.5 })
    local a, b = pair(m)
    m:cycle(1)
    T.check(m:bond{ model = "cbond", props = { cb_tenf = 1e3, cb_shearf = math.huge } } == 1, "one bond")
    local c0 = theContact(m)
    T.check(c0.model == "cbond" and c0:prop("bonded") == 1, "bonded")
    local c, breaks = breakSeparateTouch(m, a, b)
    T.check(breaks == 1, "one break, got " .. breaks)
    T.check(c.model == "linear", "the re-formed contact has the ordinary model, got " .. c.model)
end

-- 2. A cbond rule with cb_bond = 1 bonds the first touch, and not the touch after the break.
do
    local m = talus.model{ gravity = {0, 0} }
    m:contact_model("cbond", { kn = 1e8, ks = 5e7, fric = 0.5, cb_bond = 1, cb_tenf = 1e3,
                               cb_shearf = math.huge })
    local a, b = pair(m)
    m:cycle(1)
    T.check(theContact(m):prop("bonded") == 1, "the rule bonds the first touch")
    local c, breaks = breakSeparateTouch(m, a, b)
    T.check(breaks == 1, "one break, got " .. breaks)
    T.check(c.model == "cbond" and c:prop("bonded") == 0 and c:prop("cb_state") == 0,
        "the re-formed contact is not bonded (bonded " .. c:prop("bonded") .. ")")
    -- Pulled apart again, it simply separates: no second break.
    a.vel, b.vel = {-0.5, 0}, {0.5, 0}
    m:cycle(3000)
    T.check(breaks == 1 and theContact(m) == nil, "no bond to break the second time")
    -- Another pair of the same model is still bonded by the rule on its first touch.
    local d = m:ball{ pos = {5, 0}, radius = R, density = RHO }
    local e = m:ball{ pos = {5 + 2 * R - 1e-4, 0}, radius = R, density = RHO }
    m:cycle(1)
    local bonded
    for cc in m:contacts{ ball = d } do bonded = cc:prop("bonded") end
    T.check(bonded == 1, "a new pair is bonded by the rule")
    T.check(e ~= nil, "")
end

-- 3. m:unbond removes the bond silently, and the rule does not bond the pair again either.
do
    local m = talus.model{ gravity = {0, 0} }
    m:contact_model("cbond", { kn = 1e8, ks = 5e7, fric = 0.5, cb_bond = 1, cb_tenf = 1e3,
                               cb_shearf = math.huge })
    local a, b = pair(m)
    m:cycle(1)
    local breaks = 0
    m:on_event("bond_break", function() breaks = breaks + 1 end)
    T.check(m:unbond{ model = "cbond" } == 1, "one bond removed")
    T.check(theContact(m):prop("bonded") == 0, "unbonded")
    a.vel, b.vel = {-0.5, 0}, {0.5, 0}
    m:cycle(3000)
    T.check(theContact(m) == nil and breaks == 0, "separates without a break event")
    a.vel, b.vel = {0.5, 0}, {-0.5, 0}
    local c
    for _ = 1, 100000 do
        m:cycle(1)
        c = theContact(m)
        if c and c.overlap > 0 then break end
    end
    T.check(c and c:prop("bonded") == 0, "not bonded again on touch")
end

T.done("bond_rebond")
