-- SPDX-License-Identifier: MIT
-- The shadow-angle apex on constructed profiles (Evans & Hungr 1993: the top of the talus below
-- the cliff the rocks fall from). A ditch, a step or a bench below the talus never makes one;
-- where there is no talus apex there are no shadow angles (NaN, with the reason); shadow angles
-- below Evans & Hungr's 27.5 deg are warned about. The held-out case: a 40 degree slope with a
-- 2 m ditch of 50 degree walls at its toe (the old rule took the ditch's bottom, y = -2, and gave
-- a mean shadow angle of -10.6 deg). `shadow_apex`, `shadow_steep` and `shadow_talus` are options
-- of rockfall.analysis{}; the Monte Carlo prints what it used and writes the reason.
local T = require("testlib")
local rockfall = require("rockfall")
local stats = require("rockfall_stats")

local function t(deg) return math.tan(math.rad(deg)) end
local function isnan(v) return v ~= v end

-- Rocks at rest at x on a profile (centres 0.5 above the ground), released at `release`.
local function resting(xs, ground, release)
    local r = {}
    for i, x in ipairs(xs) do
        r[i] = { rock = i, stop = "rest", end_x = x, end_y = ground(x) + 0.5, r_eq = 0.5,
            release = { x = release[1], y = release[2] } }
    end
    return r
end
local function ground_of(pts) return function(x) return rockfall.ground(pts, x) end end

-- 1. The held-out slope: 40 deg from (0, 30) to its toe, a ditch 2 m deep with 50 deg walls and
-- a 3 m floor, a flat run-out. No cliff above a talus: no apex, no shadow angles, the reason.
local toe = 30 / t(40)
local wall = 2 / t(50)
local ditch = { { 0, 30 }, { toe, 0 }, { toe + wall, -2 }, { toe + wall + 3, -2 },
    { toe + 2 * wall + 3, 0 }, { 120, 0 } }
local release = { 0.5, 30.5 }
local apex, why = stats.shadow_apex({ profile = ditch, release = release })
T.check(apex == nil, "no apex on a 40 deg slope with a ditch (got "
    .. (apex and string.format("(%g, %g)", apex.x, apex.y) or "none") .. ")")
T.check(why and why:find("40 deg slope", 1, true) and why:find("no talus apex", 1, true),
    "the reason names the slope: " .. tostring(why))
local recs = resting({ toe + wall + 1.5, 50, 60, 80 }, ground_of(ditch), release)
local ang = stats.angles(recs, { profile = ditch, release = release })
T.check(ang.apex == nil and ang.shadow.n == 0 and isnan(ang.shadow.mean) and isnan(ang.shadow.min),
    "no shadow angles without an apex (NaN)")
for i = 1, #recs do T.check(isnan(ang.per_rock[i].shadow), "rock " .. i .. ": shadow NaN") end
T.check(ang.no_apex == why, "angles() carries the reason")
T.check(ang.energy_line.n == 4, "the energy-line angles are still there")

-- 2. A cliff (70 deg), a talus (35 deg), the same ditch at the talus toe: the apex is the cliff's
-- toe, the top of the talus; the ditch walls (50 deg) never make one.
local cliff_x = 40 / t(70)
local talus_toe = cliff_x + 20 / t(35)
local p2 = { { 0, 60 }, { cliff_x, 20 }, { talus_toe, 0 }, { talus_toe + wall, -2 },
    { talus_toe + wall + 3, -2 }, { talus_toe + 2 * wall + 3, 0 }, { 150, 0 } }
apex = stats.shadow_apex({ profile = p2, release = { 0.5, 61 } })
T.check(apex and apex.x == cliff_x and apex.y == 20, "apex at the top of the talus, not the ditch")
T.check(apex.rule:find("top of the talus below the cliff", 1, true), "rule: " .. apex.rule)
-- Shadow angles from it, against the closed form atan((20 - y_ground) / (x - x_apex)).
local r2 = resting({ talus_toe + wall + 1, 70, 90 }, ground_of(p2), { 0.5, 61 })
local a2 = stats.angles(r2, { profile = p2, release = { 0.5, 61 } })
T.near(a2.per_rock[1].shadow, math.deg(math.atan(22, talus_toe + wall + 1 - cliff_x)), 1e-12,
    "shadow angle of the rock in the ditch")
T.near(a2.per_rock[3].shadow, math.deg(math.atan(20, 90 - cliff_x)), 1e-12, "shadow angle at x = 90")
T.check(a2.note == nil, "no note")

-- 3. A step below the talus: cliff, talus, a 60 deg step, a second talus, a flat. The apex stays
-- at the first cliff's toe.
local p3 = { { 0, 50 }, { 10, 20 }, { 30, 10 }, { 32, 6 }, { 45, 0 }, { 100, 0 } }
apex = stats.shadow_apex({ profile = p3, release = { 1, 51 } })
T.check(apex and apex.x == 10 and apex.y == 20, "a step below the talus never makes the apex")

-- 4. A flat crest before the cliff (rocks rolled off the edge): the cliff below the crest.
local p4 = { { 0, 40 }, { 5, 40 }, { 10, 10 }, { 30, 0 }, { 80, 0 } }
apex = stats.shadow_apex({ profile = p4, release = { 1, 40.5 } })
T.check(apex and apex.x == 10 and apex.y == 10, "crest, cliff, talus: the cliff's toe")
-- 5. Rocks released on the talus below the cliff: the top of that talus.
apex = stats.shadow_apex({ profile = p4, release = { 15, 8 } })
T.check(apex and apex.x == 10 and apex.y == 10, "released on the talus: the top of it")
T.check(apex.rule:find("start on", 1, true), "rule: " .. apex.rule)

-- 6. A cliff straight onto a flat (no talus), and Nejati's (2008) benches: no apex, the reason.
apex, why = stats.shadow_apex({ profile = { { 0, 30 }, { 5, 0 }, { 60, 0 } }, release = { 0.5, 31 } })
T.check(apex == nil and why:find("does not go down", 1, true), "cliff onto a flat: " .. tostring(why))
local nejati = { { 0, 60 }, { 7.3, 40 }, { 19.3, 40 }, { 26.2, 20 }, { 38.6, 20 }, { 46, 0 }, { 170, 0 } }
apex, why = stats.shadow_apex({ profile = nejati, release = { 1.5, 61 } })
T.check(apex == nil and why:find("(7.3, 40)", 1, true), "benches are no talus: " .. tostring(why))
-- shadow_talus sets what counts as talus: at 30 deg the 26.6 deg slope below the cliff does not.
apex = stats.shadow_apex({ profile = p4, release = { 1, 40.5 }, shadow_talus = 30 })
T.check(apex == nil, "shadow_talus = 30: the 26.6 deg slope is no talus")

-- 7. An upward step alone (a berm) is no cliff; toward -x the same step is a drop onto a bench.
local berm = { { 0, 10 }, { 20, 0 }, { 30, 0 }, { 31, 2 }, { 50, 2 } }
T.check(stats.shadow_apex({ profile = berm }) == nil, "a rising segment never makes the apex")
local back = { { -10, 20 }, { 0, 10 }, { 20, 0 }, { 30, 0 } }
apex = stats.shadow_apex({ profile = back, direction = -1, release = { 29, 0.5 } })
T.check(apex == nil, "toward -x the slope rises: no apex")
local mirrored = {}
for i = #p4, 1, -1 do mirrored[#mirrored + 1] = { -p4[i][1], p4[i][2] } end
apex = stats.shadow_apex({ profile = mirrored, release = { -1, 40.5 } })
T.check(apex and apex.x == -10 and apex.y == 10, "the mirrored profile (toward -x): the same apex")

-- 8. A given apex wins; the options are checked.
local given = stats.angles(recs, { profile = ditch, release = release, shadow_apex = { 0, 30 } })
T.check(given.apex.rule == "given" and given.no_apex == nil, "a given apex is used as given")
T.near(given.per_rock[3].shadow, math.deg(math.atan(30, 60)), 1e-12, "shadow from the given apex")
T.fails(function() stats.shadow_apex({ profile = ditch, shadow_steep = 0 }) end,
    { "shadow_steep must be an angle in (0, 90]" }, "shadow_steep out of range")
T.fails(function() stats.shadow_apex({ profile = ditch, shadow_talus = 50 }) end,
    { "shadow_talus (50) must be less than shadow_steep (45)" }, "talus steeper than a cliff")

-- 9. Evans & Hungr's 27.5 deg: angles below it are warned about, with the count and the lowest.
local far = resting({ 40, 50, 140 }, ground_of(p2), { 0.5, 61 })
local a9 = stats.angles(far, { profile = p2, release = { 0.5, 61 } })
local low = math.deg(math.atan(20, 140 - cliff_x))
T.check(low < 27.5 and a9.warning and a9.warning:find("1 of 3 rocks", 1, true)
    and a9.warning:find(string.format("%.3g deg", low), 1, true), "warning: " .. tostring(a9.warning))
local near = stats.angles(resting({ 40 }, ground_of(p2), { 0.5, 61 }), { profile = p2, release = { 0.5, 61 } })
T.check(near.shadow.min > 27.5 and near.warning == nil, "no warning above 27.5 deg")

-- 10. rockfall.analysis{} takes the options and hands them to the statistics.
local function analysis(extra)
    local opts = {
        profile = ditch,
        materials = { slope = { model = "linear",
            props = { kn = 1e7, ks = 5e6, fric = 0.6, dp_nratio = rockfall.dp_nratio(0.3) } } },
        seeders = { { kind = "point", at = { 1, 31 }, vx = 1, rock = { shape = "ball", radius = 0.3 } } },
        seed = 3, t_max = 2,
    }
    for k, v in pairs(extra) do opts[k] = v end
    return rockfall.analysis(opts)
end
local d = rockfall.describe(analysis({ shadow_apex = { 0, 50 }, shadow_steep = 40, shadow_talus = 20 }))
T.check(d.shadow_apex[1] == 0 and d.shadow_apex[2] == 50 and d.shadow_steep == 40
    and d.shadow_talus == 20, "describe() carries shadow_apex, shadow_steep and shadow_talus")
T.fails(function() analysis({ shadow_steep = 95 }) end, { "analysis.shadow_steep must be <= 90" },
    "shadow_steep checked by rockfall.analysis")

-- 11. The Monte Carlo on the held-out slope: it prints why there are no shadow angles and writes
-- NaN and the reason (2 rocks; the time cap keeps them short).
local out = os.tmpname()
os.remove(out)
local printed = {}
local saved_print = print
print = function(...) printed[#printed + 1] = table.concat({ ... }, " ") end
local ok, err = pcall(rockfall.monte_carlo, analysis({}), { n = 2, outdir = out, jobs = 1 })
print = saved_print
T.check(ok, tostring(err))
local text = table.concat(printed, "\n")
T.check(text:find("rockfall: no shadow angles: the rocks start on a 40 deg slope", 1, true),
    "the reason is printed: " .. text)
local csv = io.open(out .. "/angles.csv"):read("a")
local row = csv:match("\nshadow,([^\n]*)")
T.check(row and row:find("^nan,nan,") and row:find("no apex: the rocks start on a 40 deg slope", 1, true),
    "angles.csv: no apex, NaN and the reason: " .. tostring(row))
for line in io.lines(out .. "/endpoints.csv") do
    if not line:find("^rock,") then T.check(line:find(",nan$"), "endpoints.csv: shadow_deg nan: " .. line) end
end
os.execute("rm -rf '" .. out .. "'")

T.done("rockfall_ditch")
