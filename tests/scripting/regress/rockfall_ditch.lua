-- SPDX-License-Identifier: MIT
-- Shadow angles on a slope with a ditch at its toe: a 35 degree slope 50 m high, a 1.5 m deep
-- ditch with 45 degree walls, a flat run-out. The far wall of the ditch rises in the direction
-- of travel and must never define the shadow-angle apex; an apex at or below the run-out is
-- reported in a note (its shadow angles are 0 or negative); `shadow_apex` and `shadow_steep`
-- are options of rockfall.analysis{} and reach the statistics; the Monte Carlo prints the apex
-- it used.
local T = require("testlib")
local rockfall = require("rockfall")
local stats = require("rockfall_stats")

local toe = 50 / math.tan(math.rad(35)) -- 71.407 m
local ditch = {
    { 0, 50 }, { toe, 0 }, { toe + 1.5, -1.5 }, -- slope, near wall (down, 45 deg)
    { toe + 10.5, -1.5 }, { toe + 12, 0 },      -- ditch bottom, far wall (up, 45 deg)
    { 150, 0 },                                 -- flat run-out
}

-- Rocks at rest on the flat run-out (centres one radius above it), released at the crest.
local records = {}
for i, x in ipairs({ 90, 95, 100, 110, 120 }) do
    records[i] = { rock = i, stop = "rest", end_x = x, end_y = 0.5, r_eq = 0.5,
        release = { x = 0.5, y = 50.6 } }
end

-- 1. The derived apex is the toe of the near (downslope) wall, not of the far (upslope) one.
local apex = stats.shadow_apex({ profile = ditch })
T.check(apex ~= nil, "a 45 degree downslope segment makes an apex")
T.near(apex.x, toe + 1.5, 1e-12, "apex x: the toe of the near wall")
T.near(apex.y, -1.5, 1e-12, "apex y: the ditch bottom")
T.check(apex.rule:find("downslope", 1, true), "the rule says downslope: " .. apex.rule)

-- ... and it is below the run-out, so the result says so.
local ang = stats.angles(records, { profile = ditch })
T.check(ang.note and ang.note:find("at or below the run-out", 1, true),
    "a note for an apex below the run-out: " .. tostring(ang.note))
T.check(ang.shadow.max < 0, "(the shadow angles from it are negative, hence the note)")

-- 2. An upward step alone is no cliff: no apex, no shadow angles.
local berm = { { 0, 10 }, { 20, 0 }, { 30, 0 }, { 31, 2 }, { 50, 2 } }
T.check(stats.shadow_apex({ profile = berm }) == nil,
    "a segment that rises in the direction of travel never defines the apex")
-- Rocks travelling toward -x over the same profile meet the step as a drop: then it is a cliff.
local back = stats.shadow_apex({ profile = berm, direction = -1 })
T.check(back and back.x == 30 and back.y == 0,
    "toward -x the step from (31, 2) down to (30, 0) is a cliff: its toe is the apex")

-- 3. A given apex (the crest: the whole slope is talus) gives positive shadow angles with no note.
local given = stats.angles(records, { profile = ditch, shadow_apex = { 0, 50 } })
T.check(given.note == nil, "no note for a sensible given apex")
T.near(given.per_rock[3].shadow, math.deg(math.atan(50, 100)), 1e-12,
    "shadow angle from the given apex to the ground under x = 100")
-- shadow_steep moves the threshold: at 50 degrees no segment qualifies.
T.check(stats.shadow_apex({ profile = ditch, shadow_steep = 50 }) == nil, "shadow_steep = 50")
T.fails(function() stats.shadow_apex({ profile = ditch, shadow_steep = 0 }) end,
    { "shadow_steep must be an angle in (0, 90]" }, "shadow_steep out of range")

-- 4. rockfall.analysis{} accepts shadow_apex and shadow_steep and hands them to the statistics.
local function analysis(extra)
    local opts = {
        profile = ditch,
        materials = { slope = { model = "linear",
            props = { kn = 1e7, ks = 5e6, fric = 0.6, dp_nratio = rockfall.dp_nratio(0.3) } } },
        seeders = { { kind = "point", at = { 1, 51 }, vx = 1, rock = { shape = "ball", radius = 0.3 } } },
        seed = 3, t_max = 2,
    }
    for k, v in pairs(extra) do opts[k] = v end
    return rockfall.analysis(opts)
end
local an = analysis({ shadow_apex = { 0, 50 }, shadow_steep = 40 })
local d = rockfall.describe(an)
T.check(d.shadow_apex[1] == 0 and d.shadow_apex[2] == 50, "describe() carries shadow_apex")
T.check(d.shadow_steep == 40, "describe() carries shadow_steep")
T.fails(function() analysis({ shadow_steep = 95 }) end, { "analysis.shadow_steep must be <= 90" },
    "shadow_steep checked by rockfall.analysis")

-- 5. The Monte Carlo prints the apex it used (2 rocks; the time cap keeps them short: the
-- apex does not depend on where they stop).
local out = os.tmpname()
os.remove(out)
local printed = {}
local saved_print = print
print = function(...) printed[#printed + 1] = table.concat({ ... }, " ") end
local ok, err = pcall(rockfall.monte_carlo, analysis({}), { n = 2, outdir = out, jobs = 1 })
print = saved_print
T.check(ok, tostring(err))
local text = table.concat(printed, "\n")
T.check(text:find(string.format("shadow angles from the apex (%.4g, -1.5)", toe + 1.5), 1, true),
    "the apex is printed: " .. text)
T.check(text:find("at or below the run-out", 1, true), "and the note: " .. text)
local csv = io.open(out .. "/angles.csv"):read("a")
T.check(csv:find("shadow," .. string.format("%.12g", toe + 1.5) .. ",-1.5,", 1, true),
    "angles.csv has the apex: " .. csv)
os.execute("rm -rf '" .. out .. "'")

T.done("rockfall_ditch")
