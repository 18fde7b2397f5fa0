-- SPDX-License-Identifier: MIT
-- The balls' memory order from Lua (docs/lua-api.md, "Force loop"): m:sort_interval reads and
-- sets it ("auto" by default: every 1000 steps from 4096 balls), sorts at the first step and
-- every n steps after, and refuses what is not a step count, naming the script line. The
-- physics of a sorted run against an unsorted one is the core test's (core.determinism).
local T = require("testlib")

local function pile(every)
    local m = talus.model{ gravity = {0, -9.81} }
    m:contact_model("linear", { kn = 1e6, ks = 5e5, fric = 0.5 })
    m:wall{ points = {{0, 1}, {0, 0}, {0.5, 0}, {0.5, 1}} }
    for k = 0, 99 do
        m:ball{ pos = {0.02 + 0.045 * (k % 10), 0.02 + 0.045 * (k // 10)}, radius = 0.02,
                density = 2600 }
    end
    if every ~= nil then T.check(m:sort_interval(every) == every, "returns the setting") end
    return m
end

local function sorts(m)
    return tonumber(m:profile():match("memory sorts (%d+)"))
end

local m = pile()
T.check(m:sort_interval() == "auto", "the default is automatic")
m:cycle(120)
T.check(sorts(m) == 0, "automatic: no sort below 4096 balls")
local every = pile(50)
every:cycle(120)
T.check(sorts(every) == 3, "every 50 steps: at steps 1, 51 and 101 (" .. sorts(every) .. ")")
local off = pile(0)
off:cycle(120)
T.check(sorts(off) == 0, "0: never")
T.check(m:sort_interval("auto") == "auto", "auto again")

local err = T.fails(function() m:sort_interval(-3) end,
                    {"sort_interval: expected a step count >= 0 or \"auto\"", "-3"}, "negative")
T.check(err:find("memory_sort.lua:%d+"), "the message names the script line: " .. err)
T.fails(function() m:sort_interval(2.5) end, {"sort_interval", "2.5"}, "a fraction")
T.fails(function() m:sort_interval("often") end, {"sort_interval", "often"}, "a word")

T.done("memory_sort")
