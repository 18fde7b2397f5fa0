-- SPDX-License-Identifier: MIT
-- Speed-up of talus.map on independent DEM items (docs/results/benchmarks-history.md, "Independent runs on all
-- cores"). Each item pours 200 balls of seed-dependent sizes and positions into a box and lets
-- them settle for 1.2 s (about 0.3 s of wall time on one core); the map runs 16 items with
-- jobs = 1 and jobs = J, checks that the results are identical and prints the wall times.
--   talus run scripts/bench/map_speedup.lua [items=16] [jobs=2]
--   mpirun -n 2 talus run scripts/bench/map_speedup.lua 16 1     (2 ranks, 1 process each)
local items = tonumber(arg[1]) or 16
local jobs = tonumber(arg[2]) or 2

local function pile(i)
    math.randomseed(7919 * i)
    local m = talus.model{ gravity = { 0, -9.81 } }
    m:contact_model("linear", { kn = 1e6, ks = 1e6, fric = 0.5, dp_nratio = 0.3 })
    m:wall{ points = { { -1, 2 }, { -1, 0 }, { 1, 0 }, { 1, 2 } } }
    local balls = {}
    for k = 1, 200 do
        local r = 0.02 + 0.015 * math.random()
        local col, row = (k - 1) % 15, (k - 1) // 15
        balls[k] = m:ball{ pos = { -0.9 + 0.12 * col + 0.01 * math.random(), 0.1 + 0.1 * row },
            radius = r, density = 2600 }
    end
    m:solve{ time = 1.2 }
    local top = 0
    for _, b in ipairs(balls) do top = math.max(top, b.pos[2] + b.radius) end
    return { top = top, steps = m:step() }
end

-- Wall time with a sub-second clock: `date +%s.%N` through io.popen (Lua has none of its own).
local function now()
    local f = io.popen("date +%s.%N")
    local t = tonumber(f:read("l"))
    f:close()
    return t
end

local t0 = now()
local serial = talus.map(items, pile, { jobs = 1 })
local t1 = now()
local parallel = talus.map(items, pile, { jobs = jobs })
local t2 = now()
for i = 1, items do
    assert(serial[i].top == parallel[i].top and serial[i].steps == parallel[i].steps,
        "item " .. i .. " differs between jobs = 1 and jobs = " .. jobs)
end
local steps = 0
for i = 1, items do steps = steps + serial[i].steps end
-- Under mpirun the items are shared among the ranks in both maps (jobs counts workers per rank).
if talus.rank() == 0 then
    print(string.format("%d items (%d steps each on average), %d rank(s): jobs = 1 %.2f s "
        .. "(%.3f s per item), jobs = %d %.2f s, speed-up %.2f; results identical", items,
        steps // items, talus.ranks(), t1 - t0, (t1 - t0) / items, jobs, t2 - t1,
        (t1 - t0) / (t2 - t1)))
end
