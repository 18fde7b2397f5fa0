-- SPDX-License-Identifier: MIT
-- rockfall.mass_release reads the engine's trackers (m:track) instead of sampling every rock and
-- every contact from Lua at every step. The physics is the same, so the records must be the
-- same to the last bit: this scene (10 rocks, balls and clumps, rock-rock contact, two
-- collectors, a barrier that stops one rock and lets the others pass or fly over, rocks that
-- rest, leave and run out of time) gave the digest below with the per-step Lua hook that
-- mass_release used before (scripts/lib/rockfall.lua at commit f477834), run on this engine.
--
-- The digest covers every field of every record (numbers to 17 digits). If the engine's
-- arithmetic changes (a different summation order in the force loop), every number changes and
-- the digest with them: then run this script with the old module first in the path, e.g.
--   git show f477834:scripts/lib/rockfall.lua > /tmp/old/rockfall.lua
--   TALUS_LUA_PATH=/tmp/old:tests/scripting REGEN=1 talus run tests/scripting/regress/rockfall_mass_release.lua
-- and paste its digest and table here after checking that the new module gives the same.
local T = require("testlib")
local rf = require("rockfall")

local function lin(rn, fric)
    return { model = "linear", props = { kn = 1e7, ks = 5e6, fric = fric, dp_nratio = rf.dp_nratio(rn) } }
end
local an = rf.analysis{
    profile = { { 0, 8 }, { 6, 2 }, { 9, 0 }, { 24, 0 } },
    materials = { hard = lin(0.5, 0.5), soft = lin(0.35, 0.7) },
    zones = { { material = "hard", x_from = 0, x_to = 9 }, { material = "soft", x_from = 9, x_to = 24 } },
    rock_contact = { model = "linear", props = { kn = 1e7, ks = 5e6, fric = 0.5, dp_nratio = 0.3 } },
    seeders = { { kind = "line", from = { 0.3, 8.9 }, to = { 1.8, 8.9 },
        vx = { dist = "uniform", min = 0, max = 4 },
        rock = { { shape = "ball", radius = 0.5, scale = { dist = "uniform", min = 0.24, max = 0.5 }, weight = 2 },
                 { shape = "thesis_a", radius = 0.1, weight = 1 } } } },
    collectors = { { name = "c1", x = 8 }, { name = "c2", x = 16 } },
    barriers = { { name = "fence", x = 12, energy = 400, height = 0.45 } },
    envelope = { x0 = 0, x1 = 24, dx = 1 },
    -- The margin is given: mass_release's default changed with the trackers (docs/rockfall.md),
    -- and the margin decides the pairs' order, hence the last bits.
    margin = 0.25, t_max = 8, seed = 11, n = 10,
}
local recs = rf.mass_release(an, { n = 10 })

-- Every field of every record (T.digest).
local digest = T.digest(recs)

local rows = {}
for _, r in ipairs(recs) do
    local bars = {}
    for _, b in ipairs(r.barrier) do bars[#bars + 1] = b.stopped and "stop" or (b.over and "over" or "pass") end
    rows[#rows + 1] = string.format("%d %s %s %.6f %.6f %.6f %d %d %s", r.rock, r.shape, r.stop, r.end_x,
        r.end_y, r.t_end, #r.impacts, #r.crossings, table.concat(bars, ","))
end
if os.getenv("REGEN") then
    print("digest " .. digest)
    for _, row in ipairs(rows) do print(row) end
    return
end

-- rock shape stop end_x end_y t_end impacts crossings barrier (old hook's numbers)
local expected = {
    "1 thesis_a rest 13.393748 0.157615 6.747394 18 1 pass",
    "2 ball time 15.019146 0.205286 8.000017 8 1 pass",
    "3 ball left 24.000340 0.184701 7.006119 8 2 pass",
    "4 ball time 16.071934 0.231827 8.000017 7 2 pass",
    "5 ball left 24.000814 0.226583 3.981495 3 2 pass",
    "6 ball time 15.643763 0.166014 8.000017 6 2 pass",
    "7 thesis_a rest 17.632446 0.157476 5.847966 9 2 over",
    "8 ball barrier 12.000000 0.120996 3.176422 9 1 stop",
    "9 ball rest 17.292245 0.146065 6.590600 9 2 pass",
    "10 ball time 16.701980 0.219140 8.000017 5 2 over",
}
local expected_digest = "71e49a883efc4182"
T.check(#rows == #expected, "one record per rock")
for k, row in ipairs(rows) do T.check(row == expected[k], "rock " .. k .. ": got '" .. row .. "'") end
T.check(digest == expected_digest, "every record bit for bit: digest " .. digest .. " (the hook's " ..
    expected_digest .. ")")
T.done("rockfall_mass_release")
