-- SPDX-License-Identifier: MIT
-- m:on_event("bond_break", fn) with the test_breaker plugin (loaded by path), and on_cycle.
local T = require("testlib")
local plugin = assert(arg[1], "usage: events.lua path/to/libtalus_test_breaker.so")

local names = talus.load_plugin(plugin)
T.check(#names == 1 and names[1] == "test_breaker", "load_plugin returns the model names")
local info = talus.contact_model_info("test_breaker")
T.check(info.properties[1].name == "kn" and info.properties[2].read_only, "contact_model_info")
local lin = talus.contact_model_info("linear")
local modes
for _, p in ipairs(lin.properties) do if p.name == "dp_mode" then modes = p.values end end
T.check(modes and modes[2] == "no_tension", "enum names in contact_model_info")

local m = talus.model{ gravity = {0, -9.81} }
m:contact_model("test_breaker", { kn = 1e7 })
m:wall{ points = { {-1, 0}, {1, 0} } }
local b = m:ball{ pos = {0, 0.2}, radius = 0.1, density = 2600 }

local events, in_hook = {}, false
m:on_event("bond_break", function(ev)
    T.check(not in_hook, "events are delivered before the cycle hooks")
    events[#events + 1] = ev
end)
local calls, last_step = 0, -1
m:on_cycle(function(model, step)
    in_hook = true
    calls = calls + 1
    T.check(model:step() == step and step > last_step, "on_cycle gets the model and the step")
    last_step = step
    in_hook = false
end)
local every = 0
local handle = m:on_cycle(function() every = every + 1 end, 10)
m:solve{ time = 0.3 }
T.check(calls == m:step(), "on_cycle every step")
T.check(every == m:step() // 10, "on_cycle every 10 steps")
T.check(#events == 1, "one break event (" .. #events .. ")")
local ev = events[1]
T.check(ev.kind == "bond_break" and ev.mode == "tension" and ev.model == "test_breaker", "event fields")
T.near(ev.pos[2], 0, 1e-3, "event position at the contact point")
T.check(ev.time > 0.1 and ev.time <= m:time(), "event time")
m:remove_on_cycle(handle)
local before = every
m:cycle(20)
T.check(every == before, "remove_on_cycle")
m:on_event("bond_break", nil)

-- a one-shot hook that removes itself does not make the next hook miss that step
local m2 = talus.model{}
m2:on_warning(function() end)
m2:ball{ pos = {0, 0}, radius = 0.1, density = 1 }
local once, runs, count = nil, 0, 0
once = m2:on_cycle(function(model) runs = runs + 1; model:remove_on_cycle(once) end)
m2:on_cycle(function() count = count + 1 end)
m2:cycle(3)
T.check(runs == 1 and count == 3, "self-removing hook (" .. runs .. ", " .. count .. ")")
T.done("events")
