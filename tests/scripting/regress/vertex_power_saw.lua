-- SPDX-License-Identifier: MIT
-- A ball bouncing on a sawtooth profile with `power`. Its
-- contact ran over a crest while unloading, ended there and restarted on the next segment on
-- power's virgin loading line: the normal force jumped from 2.72e4 N to 2.88e4 N, and the run
-- lost 17% of the input (5.44 J of 32.3 J). With the contact handed over with its state, the force
-- goes on along the unloading curve and the balance closes to 0.04% (bound: 1% of the input, as
-- the issue asks; one restarted contact costs 17 times that).
local T = require("testlib")

local m = talus.model{ gravity = { 0.0, -9.81 } }
m:contact_model("power", { kn = 53610410.55267015, ks = 6102214.901904889, fric = 0.0,
    transition = 12352160.690744607, exp_mode = 3, target_e = 0.8721949698345304 })
m:wall{ points = { { -0.0338059233829403, -0.024791010480822887 }, { -0.02704473870635224, -0.04665893238618894 },
    { -0.02028355402976418, -0.024791010480822887 }, { -0.01352236935317612, -0.04665893238618894 },
    { -0.00676118467658806, -0.024791010480822887 }, { 0.0, -0.04665893238618894 },
    { 0.00676118467658806, -0.024791010480822887 }, { 0.01352236935317612, -0.04665893238618894 },
    { 0.02028355402976418, -0.024791010480822887 }, { 0.02704473870635224, -0.04665893238618894 },
    { 0.0338059233829403, -0.024791010480822887 } } }
m:ball{ pos = { 0.006649372046425683, -0.006047442225926012 }, radius = 0.006412171766314512,
    density = 5036.5417717862065, vel = { -3.6475257231392773, -7.321231390995401 }, spin = 1246.6826407025223 }
m:energy{ on = true }

-- The normal force along each contact: at a handover it must go on smoothly. Its second
-- difference there is compared with the largest elsewhere in the same run, over steps with two
-- loaded steps of the same contact before and after (touch and separation are corners of the law);
-- the restart gave 4.0e3 N (the force turned up onto the virgin line) where the contacts' own are
-- below 600 N; with the handover it is 270 N.
local contacts, cur, seg = {}, nil, nil
local handovers = 0
for _ = 1, 200 do
    m:cycle(1)
    local c0 = nil
    for c in m:contacts{} do c0 = c end
    if c0 and c0.normal_force > 0 then
        if not cur then cur, seg = { f = {}, hand = {} }, nil; contacts[#contacts + 1] = cur end
        local h = seg ~= nil and c0.segment ~= seg
        seg = c0.segment
        cur.f[#cur.f + 1], cur.hand[#cur.f + 1] = c0.normal_force, h
        if h then handovers = handovers + 1 end
    else
        cur = nil
    end
end
local dd_hand, dd_else = 0, 0
for _, c in ipairs(contacts) do
    local f = c.f
    for k = 3, #f - 2 do
        local dd = math.abs(f[k] - 2 * f[k - 1] + f[k - 2])
        if c.hand[k] then dd_hand = math.max(dd_hand, dd) else dd_else = math.max(dd_else, dd) end
    end
end
local e = m:energies()
local rel = e.balance_error / e.initial_kinetic
print(string.format("power saw: balance error %.3e J = %.3f%% of the input; %d handovers; " ..
    "second difference of Fn at a handover %.4g N, elsewhere <= %.4g N", e.balance_error, 100 * rel,
    handovers, dd_hand, dd_else))
T.check(handovers >= 1, "the contact crosses a crest")
T.check(math.abs(rel) < 0.01, string.format("balance error %.3g%% of the input", 100 * rel))
T.check(dd_hand < 2 * dd_else, string.format("Fn jumps at the handover: %.4g vs %.4g", dd_hand, dd_else))

T.done("vertex_power_saw")
