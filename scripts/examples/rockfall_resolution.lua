-- SPDX-License-Identifier: MIT
--
-- rockfall_resolution.lua: the example's run-out statistics against the contact resolution (the
-- time-step rule's steps per contact duration, m:timestep{resolution =}), with their confidence
-- intervals and the CPU each took, so that the default can be set where a coarser step changes
-- the answers by less than their sampling error (docs/rockfall.md, "Contact resolution").
--
--   talus run scripts/examples/rockfall_resolution.lua [outdir] [--n=1000] [--seed=2026]
--                 [--resolutions=10,15,20,30,60] [--jobs=1]
--
-- The same rocks (seed, 1..n) on the example's slope (rockfall_nejati.lua) at each resolution.
-- With --jobs=1 (the default) every rock runs in this process, so os.clock is the CPU of the
-- rocks; prints a Markdown table and writes <outdir>/rockfall_resolution.csv. Then, rock by
-- rock against the finest resolution (the last): the mean change of the end point with its
-- standard error (a systematic shift shows there even when each rock's path changes), and
-- <outdir>/rockfall_resolution_rocks.csv (end x of every rock at every resolution).
local rockfall = require("rockfall")
local stats = rockfall.stats
local C = require("calibrate")
local Csv = require("talus_util.csv")

local outdir, n, seed, jobs, resolutions = "out", 1000, 2026, 1, { 10, 15, 20, 30, 60 }
for _, a in ipairs(arg) do
    local key, value = a:match("^%-%-([%w_%-]+)=(.+)$")
    if key == "n" then n = math.tointeger(tonumber(value)) or error("--n needs an integer")
    elseif key == "seed" then seed = math.tointeger(tonumber(value)) or error("--seed needs an integer")
    elseif key == "jobs" then jobs = math.tointeger(tonumber(value)) or error("--jobs needs an integer")
    elseif key == "resolutions" then
        resolutions = {}
        for v in value:gmatch("[^,]+") do resolutions[#resolutions + 1] = tonumber(v) or error("--resolutions: numbers") end
    elseif a:match("^%-%-") then error("unknown option " .. a .. " (--n=, --seed=, --resolutions=, --jobs=)")
    else outdir = a end
end
talus.mkdir(outdir)

-- The example's slope: rockfall_nejati.lua beside this script.
local here = debug.getinfo(1, "S").source:match("^@(.*)[/\\][^/\\]*$") or "."
local nejati = dofile(here .. "/rockfall_nejati.lua")

local rows, per_rock = {}, {}
local function ci(v, lo, hi) return string.format("%.2f [%.2f, %.2f]", v, lo, hi) end
print(string.format("| resolution | CPU [s] | steps/rock | median end x [m] | q90 [m] | q95 [m] | reach 50 m | "
    .. "fence q95 energy [kJ] | width for 95 %% [m] | Rn bedrock | Rn talus |"))
print("|---|---|---|---|---|---|---|---|---|---|---|")
for _, res in ipairs(resolutions) do
    local options = nejati(seed, n)
    options.timestep = { resolution = res }
    local an = rockfall.analysis(options)
    local clock = os.clock()
    local records = rockfall.monte_carlo(an, { n = n, jobs = jobs, quiet = true, stats = false })
    local cpu = os.clock() - clock
    local desc = rockfall.describe(an)
    local ep = stats.endpoints(records, { percentiles = { 0.5, 0.9, 0.95 }, reach_x = { 50 } })
    local fence = stats.barriers(records, desc, { quantiles = { 0.95 } })[1].stats.energy
    local ret = stats.retention(records, desc, { widths = { 0.95 } })
    local steps = 0
    for _, r in ipairs(records) do steps = steps + r.steps end
    local rnb, nb = C.apparent_rn(records, "bedrock")
    local rnt, nt = C.apparent_rn(records, "talus")
    local p, rch, w = ep.percentiles, ep.reach[1], ret.widths[1]
    print(string.format("| %g | %.1f | %.0f | %s | %s | %s | %s | %s | %s | %.3f | %.3f |", res, cpu, steps / #records,
        ci(p[1].x, p[1].lo, p[1].hi), ci(p[2].x, p[2].lo, p[2].hi), ci(p[3].x, p[3].lo, p[3].hi),
        string.format("%.3f [%.3f, %.3f]", rch.reach, rch.lo, rch.hi),
        ci(fence.q95 / 1e3, fence.q95_lo / 1e3, fence.q95_hi / 1e3), ci(w.width, w.lo, w.hi), rnb, rnt))
    local ends = {}
    for _, r in ipairs(records) do ends[r.rock] = r.end_x end
    per_rock[#per_rock + 1] = ends
    rows[#rows + 1] = { res, cpu, steps / #records, p[1].x, p[1].lo, p[1].hi, p[2].x, p[2].lo, p[2].hi,
        p[3].x, p[3].lo, p[3].hi, rch.reach, rch.lo, rch.hi, fence.q95, fence.q95_lo, fence.q95_hi,
        w.width, w.lo, w.hi, rnb, nb, rnt, nt }
end
local ok, why = Csv.write(outdir .. "/rockfall_resolution.csv", { "resolution", "cpu", "steps_per_rock",
    "median", "median_lo", "median_hi", "q90", "q90_lo", "q90_hi", "q95", "q95_lo", "q95_hi", "reach50",
    "reach50_lo", "reach50_hi", "fence_q95", "fence_q95_lo", "fence_q95_hi", "width95", "width95_lo",
    "width95_hi", "rn_bedrock", "impacts_bedrock", "rn_talus", "impacts_talus" }, rows, { digits = 6 })
if not ok then error(why) end
-- Rock by rock against the finest resolution: mean change of end x and its standard error, and
-- the share of rocks that end on another bench or the toe flat (x below / above 26.2 and 46 m).
local finest = per_rock[#per_rock]
local function zone(x) return x < 26.2 and 1 or (x < 46 and 2 or 3) end
print(string.format("\nrock by rock against resolution %g:", resolutions[#resolutions]))
print("| resolution | mean change of end x [m] (standard error) | rocks ending in another zone |")
print("|---|---|---|")
local cells = {}
for i = 1, n do cells[i] = { i } end
for k, ends in ipairs(per_rock) do
    local sum, sum2, m, moved = 0, 0, 0, 0
    for i = 1, n do
        cells[i][k + 1] = ends[i]
        if ends[i] and finest[i] then
            local d = ends[i] - finest[i]
            sum, sum2, m = sum + d, sum2 + d * d, m + 1
            if zone(ends[i]) ~= zone(finest[i]) then moved = moved + 1 end
        end
    end
    local mean = sum / m
    local se = math.sqrt((sum2 / m - mean * mean) / (m - 1))
    print(string.format("| %g | %+.3f (%.3f) | %d of %d |", resolutions[k], mean, se, moved, m))
end
local header = { "rock" }
for _, r in ipairs(resolutions) do header[#header + 1] = "end_x_" .. r end
ok, why = Csv.write(outdir .. "/rockfall_resolution_rocks.csv", header, cells, { digits = 8 })
if not ok then error(why) end
print("wrote " .. outdir .. "/rockfall_resolution.csv and rockfall_resolution_rocks.csv")
