-- SPDX-License-Identifier: MIT
-- A Monte Carlo keeps its finished items when some fail: talus.map's default on_error =
-- "record" gives nil for a failed item, lists it in results.failed (index, message) and runs
-- the rest, whatever the jobs; a worker that dies loses only the item it was running (a new
-- worker takes the rest of its block); with `checkpoint`, a rerun takes the finished items
-- from disk and runs only the others; rockfall.monte_carlo records failed rocks (index, seed,
-- message) and skips the rocks a previous run wrote.
local T = require("testlib")
local out = (arg and arg[1] or ".") .. "/map_failures"
os.execute("rm -rf '" .. out .. "'")
talus.mkdir(out)

local function boom(i)
    if i == 5 or i == 9 then error("boom " .. i) end
    return { i = i, sq = i * i }
end

for _, jobs in ipairs({ 1, 2, 3 }) do
    local r = talus.map(12, boom, { jobs = jobs })
    local what = "jobs = " .. jobs
    for i = 1, 12 do
        if i == 5 or i == 9 then
            T.check(r[i] == nil, what .. ": a failed item is nil")
        else
            T.check(r[i] and r[i].sq == i * i, what .. ": item " .. i .. " kept")
        end
    end
    T.check(r.failed and #r.failed == 2, what .. ": two failures listed")
    T.check(r.failed[1].index == 5 and r.failed[2].index == 9, what .. ": in index order")
    T.check(r.failed[1].message:find("fn(5) failed: ", 1, true)
        and r.failed[1].message:find("boom 5", 1, true), what .. ": " .. r.failed[1].message)
end
T.check(talus.map(3, function(i) return i end).failed == nil, "no failure: no `failed` field")

-- A worker killed while running item 4 loses item 4 only.
local r = talus.map(6, function(i)
    if i == 4 then os.execute("kill -KILL $PPID") end -- the shell's parent is the worker
    return i * 10
end, { jobs = 2 })
T.check(r[4] == nil and r[5] == 50 and r[6] == 60 and r[1] == 10, "the rest of the block ran")
T.check(r.failed and #r.failed == 1 and r.failed[1].index == 4
    and r.failed[1].message:find("was killed by signal 9", 1, true), "the dead worker's item")

-- A checkpoint: finished items are stored as they arrive; a rerun runs only the others.
local ckpt = out .. "/ckpt"
local runs = out .. "/runs.log"
local function logged(i)
    local f = io.open(runs, "a")
    f:write(i, "\n")
    f:close()
end
local flaky = true
local function item(i)
    logged(i)
    if flaky and i == 3 then error("transient") end
    return { i = i, x = i / 7 }
end
local first = talus.map(8, item, { jobs = 2, checkpoint = ckpt, key = "v1" })
T.check(first[3] == nil and #first.failed == 1, "first run: item 3 failed")
os.remove(runs)
flaky = false
local second = talus.map(8, item, { jobs = 2, checkpoint = ckpt, key = "v1" })
local ran = {}
for line in io.lines(runs) do ran[#ran + 1] = tonumber(line) end
T.check(#ran == 1 and ran[1] == 3, "the rerun ran only item 3 (ran " .. table.concat(ran, ",") .. ")")
T.check(second.failed == nil, "nothing failed in the rerun")
for i = 1, 8 do
    T.check(second[i] and second[i].x == i / 7 and math.type(second[i].i) == "integer",
        "item " .. i .. " exact after the checkpoint")
end
-- Another key (another analysis in the same directory): everything runs again.
os.remove(runs)
talus.map(8, item, { jobs = 1, checkpoint = ckpt, key = "v2" })
local n = 0
for _ in io.lines(runs) do n = n + 1 end
T.check(n == 8, "another key: all 8 items run again (ran " .. n .. ")")

-- on_error = "raise" stops at the lowest failure (map.lua has the details).
T.fails(function() talus.map(12, boom, { on_error = "raise" }) end, { "map: fn(5) failed" }, "raise")
T.fails(function() talus.map(2, boom, { on_error = "ignore" }) end,
    { "map: 'on_error' must be one of \"record\", \"raise\"" }, "bad on_error")
T.fails(function() talus.map(2, boom, { key = "x" }) end, { "'key' goes with 'checkpoint'" }, "key")

-- rockfall.monte_carlo: a rock that fails is recorded with its seed; the others are written;
-- a rerun into the same outdir runs only the rocks not written yet.
local rockfall = require("rockfall")
local an = rockfall.analysis{
    profile = { { 0, 5 }, { 5, 0 }, { 20, 0 } },
    materials = { slope = { model = "linear", props = { kn = 1e7, ks = 5e6, fric = 0.5,
        dp_nratio = 0.3 } } },
    seeders = { { kind = "point", at = { 0.5, 5.6 }, rock = { shape = "ball", radius = 0.3 } } },
    t_max = 0.05, seed = 11,
}
local real_run = rockfall.run_rock
local calls = {}
rockfall.monte_carlo_run_rock_for_test = nil
local saved_print, printed = print, {}
print = function(...) printed[#printed + 1] = table.concat({ ... }, " ") end
local stderr, said = io.stderr, {}
io.stderr = { write = function(_, text) said[#said + 1] = text end }
-- Rock 2 fails: a callback on its model raises (the failure any rock could meet).
local ok, recs, info = pcall(rockfall.monte_carlo, an, { n = 4, outdir = out .. "/rf", jobs = 2,
    on_model = function(m, rock) if rock.rock == 2 then error("rock 2 broke") end end })
print, io.stderr = saved_print, stderr
T.check(ok, tostring(recs))
T.check(#recs == 3, "three rocks recorded (got " .. #recs .. ")")
T.check(info.failed and #info.failed == 1 and info.failed[1].rock == 2
    and info.failed[1].seed == rockfall.rock_seed(11, 2)
    and info.failed[1].message:find("rock 2 broke", 1, true), "the failed rock, its seed and message")
local f = io.open(out .. "/rf/rock_failed.csv")
T.check(f and f:read("a"):find("2," .. rockfall.rock_seed(11, 2) .. ",", 1, true), "rock_failed.csv")
if f then f:close() end
T.check(table.concat(printed, "\n"):find("1 of 4 rocks failed", 1, true), table.concat(printed, "\n"))
-- The rerun: only rock 2 runs.
local again = {}
local ok2, recs2, info2 = pcall(rockfall.monte_carlo, an, { n = 4, outdir = out .. "/rf", jobs = 1,
    quiet = true, on_model = function(m, rock) again[#again + 1] = rock.rock end })
T.check(ok2, tostring(recs2))
T.check(#again == 1 and again[1] == 2, "the rerun ran rock 2 only (ran " .. table.concat(again, ",") .. ")")
T.check(#recs2 == 4 and info2.failed == nil, "all four rocks now")
for i = 1, 4 do T.check(recs2[i].rock == i, "record " .. i .. " in order") end
T.check(recs2[1].end_x == recs[1].end_x, "rock 1 from the checkpoint is the same record")

T.done("map_failures")
