-- SPDX-License-Identifier: MIT
-- A history through a save and a restore when the saving run went on after the save: the rows
-- it wrote past the saved step must not stay in the file, or the restored run's rows repeat
-- their times (the ParaView series of a restore drops those frames in the same way). Also a
-- history opened with append = true: the save counts the rows the file already had.
local T = require("testlib")
local out = (arg and arg[1] or ".") .. "/restore_history_trim"
talus.mkdir(out)
local csv, save = out .. "/h.csv", out .. "/m.talus"

local function rows(file)
    local times = {}
    local header
    for line in io.lines(file) do
        if not header then header = line else times[#times + 1] = tonumber(line:match("^[^,]+")) end
    end
    return header, times
end

local function scene()
    local m = talus.model{ gravity = { 0, -9.81 } }
    m:contact_model("linear", { kn = 1e6, ks = 5e5, fric = 0.5, dp_nratio = 0.3 })
    m:wall{ points = { { -1, 0 }, { 1, 0 } } }
    m:ball{ pos = { 0, 0.5 }, radius = 0.1, density = 2600 }
    m:timestep{ fixed = 1e-4 }
    return m
end

local m = scene()
m:history{ file = csv, every = 10, columns = { "step", "time" } }
m:cycle(100)
m:save(save)           -- rows at steps 0, 10, ..., 100: 11
m:cycle(100)           -- the saving run goes on: 10 more rows, past the save
m:close_history()
local _, before = rows(csv)
T.check(#before == 21, "the saving run wrote 21 rows (got " .. #before .. ")")

local r, notes = talus.restore(save, { quiet = true })
T.check(table.concat(notes, "\n"):find("the 10 row(s) written after the save were dropped", 1, true),
    "the restore says it dropped them: " .. table.concat(notes, " | "))
r:cycle(100)
r:close_history()
local header, steps = rows(csv)
T.check(header == "step,time", "one header: " .. tostring(header))
T.check(#steps == 21, "11 rows up to the save and 10 after it (got " .. #steps .. ")")
for i = 2, #steps do
    T.check(steps[i] == steps[i - 1] + 10, string.format("row %d: step %s after %s (no repeat)", i,
        tostring(steps[i]), tostring(steps[i - 1])))
end

-- append = true over an existing file (what a script does after a restore for a history with a
-- function column): the save must count the file's earlier rows too.
local m2 = scene()
m2:history{ file = csv, every = 10, columns = { "step", "time" } }
m2:cycle(50)           -- rows at 0..50: 6
m2:close_history()
m2:history{ file = csv, every = 10, columns = { "step", "time" }, append = true }
m2:cycle(50)           -- its first row at 50 again (the documented first row), then 60..100: 6
m2:save(save)
m2:cycle(50)
m2:close_history()
local r2 = talus.restore(save, { quiet = true })
r2:cycle(50)
r2:close_history()
local _, s2 = rows(csv)
T.check(#s2 == 12 + 5, "6 + 6 rows up to the save, 5 after (got " .. #s2 .. ")")
T.check(s2[#s2] == 150 and s2[12] == 100, "the file ends at the restored run's step 150")

T.done("restore_history_trim")
