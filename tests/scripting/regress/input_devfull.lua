-- A history whose writes fail (/dev/full: every write gets ENOSPC) reported
-- 5001 rows written and exited 0 with nothing on disk. Every write, flush and close is checked
-- now; the run stops with an error naming the file and the script line.
local T = require("testlib")
local f = io.open("/dev/full", "w")
if not f then
    print("input_devfull: /dev/full is missing here; nothing to test")
    return
end
f:close()

local m = talus.model{}
m:ball{ pos = {0, 0}, radius = 0.1, density = 1000, vel = {1, 0} }
local line = T.line() + 1
T.fails(function() return m:history{ file = "/dev/full", every = 1, columns = { "time", "step" } } end,
    { T.script() .. ":" .. line .. ":", "history '/dev/full'", "No space left on device",
      "incomplete" }, "a history on a full disk")
-- the failed history is closed: the model runs on without it
m:cycle(10)
T.check(m:step() == 10, "the model still cycles after the refused history")
T.done("input_devfull")
