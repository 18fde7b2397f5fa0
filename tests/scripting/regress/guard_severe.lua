-- SPDX-License-Identifier: MIT
-- Severe findings stop the run by default (docs/physics/guard.md, "Severe findings"): energy
-- created beyond 10% of the throughput or of the scene's energy, a contact with fewer than 3
-- steps per contact duration. What the run wrote stays written; m:guard{severe = "warn"} makes
-- them warnings again; a talus.map item that stops so is a failed item.
-- Before: the scene below (a fixed step of 0.01 s for a 1e7 N/m contact) printed four warnings
-- and ran on, the ball ending 7.5 m up after a drop from 0.5 m, with exit status 0.
local T = require("testlib")
local out = arg[1] or os.getenv("TMPDIR") or "/tmp"

local function broken(opts)
    opts = opts or {}
    local m = talus.model{ gravity = { 0, -9.81 } }
    local warnings = {}
    m:on_warning(function(text) warnings[#warnings + 1] = text end)
    m:contact_model("linear", { kn = 1e7, ks = 1e7, fric = 0.5 })
    m:wall{ points = { { -5, 0 }, { 5, 0 } } }
    local b = m:ball{ pos = { 0, 0.5 }, radius = 0.1, density = 2600 }
    m:timestep{ fixed = 0.01 }
    if opts.energy then m:energy{ on = true } end
    if opts.guard then m:guard(opts.guard) end
    return m, b, warnings
end

-- 1. It stops at the impact, at the solve line, naming the contact and why it is severe; the
-- history has every row up to the stop, the ParaView series every frame.
do
    local m, b = broken()
    local csv = out .. "/guard_severe.csv"
    local h = m:history{ file = csv, every = 1, columns = { "time", { "y", function() return b.pos[2] end } } }
    local series = m:vtk{ dir = out .. "/guard_severe_vtk", every = 5 }
    local l = T.line(); local err = T.fails(function() m:solve{ time = 5 } end,
        { ":" .. l .. ":", "impact under-resolved", "contact ball 1 - wall 1", "0.518383 steps per contact duration",
          "a severe finding (fewer than 3 steps per contact duration, severe_min_steps)",
          "m:guard{severe = \"warn\"}" }, "the broken run stops")
    T.check(m:step() == 30, "stopped at the impact's end, step " .. m:step())
    local rows = 0
    for line in io.lines(csv) do rows = rows + 1 end
    T.check(rows == 1 + 30, "history rows up to the stop: " .. rows)
    local pvd = io.open(series.file)
    local text = pvd:read("a")
    pvd:close()
    local frames = select(2, text:gsub("<DataSet ", ""))
    T.check(frames == series.frames and frames >= 6, "the .pvd lists the frames written: " .. frames)
    h:close()
    print("stopped: " .. err:sub(1, 120))
end

-- 2. With tracing on the energy check stops it too (the contact gave back 18 kJ of a scene
-- holding 1.8 kJ); severe = "warn" lowers every severe finding to a warning: the old behaviour.
do
    local m = broken{ energy = true, guard = { resolution = "off" } }
    T.fails(function() m:solve{ time = 5 } end,
        { "energy created: contact ball 1 - wall 1", "a severe finding (more than 10% of the scene's energy" },
        "the energy check stops it")
    local w, b, warnings = broken{ energy = true, guard = { severe = "warn" } }
    T.check(w:guard().severe == "warn", "m:guard returns the setting")
    w:solve{ time = 5 }
    T.check(b.pos[2] > 2, "with severe = 'warn' the run goes on (the ball flew up to " .. b.pos[2] .. " m)")
    local kinds = table.concat(warnings, "\n")
    T.check(kinds:find("energy balance", 1, true) and kinds:find("fewer than 10 steps", 1, true)
        and kinds:find("gave back more energy", 1, true), "the findings are warnings: " .. #warnings)
end

-- 3. The run-level balance: energy put into a contact behind the engine's back (a resting ball
-- pushed 2 mm into the floor: 96% of the throughput created) stops the run with `balance` at its
-- default "warn"; severe_created = 0.99 leaves it a warning.
for _, created in ipairs({ 0.1, 0.99 }) do
    local m = talus.model{ gravity = { 0, -9.81 } }
    local warnings = {}
    m:on_warning(function(text) warnings[#warnings + 1] = text end)
    m:contact_model("linear", { kn = 1e6 })
    m:wall{ points = { { -1, 0 }, { 1, 0 } } }
    local b = m:ball{ pos = { 0, 0.1 }, radius = 0.1, density = 1000 }
    m:energy{ on = true }
    m:guard{ severe_created = created, energy = "off" }
    m:timestep{ fixed = 1e-4 }
    m:cycle(100)
    b.pos = { 0, b.pos[2] - 0.002 }
    if created < 0.5 then
        T.fails(function() m:cycle(10) end, { "energy balance: 2.752 J created", "95.73% of the throughput",
            "the most kinetic energy: ball 1", "more than 10% of the throughput created, severe_created" },
            "the balance check stops it")
    else
        m:cycle(10)
        T.check(#warnings == 1 and warnings[1]:find("energy balance", 1, true), "a warning below severe_created")
    end
end

-- 4. A sound scene is untouched: a ball dropped at the automatic step bounces with no finding.
do
    local m = talus.model{ gravity = { 0, -9.81 } }
    local warnings = {}
    m:on_warning(function(text) warnings[#warnings + 1] = text end)
    m:contact_model("linear", { kn = 1e7, ks = 1e7, fric = 0.5, dp_nratio = 0.2 })
    m:wall{ points = { { -5, 0 }, { 5, 0 } } }
    m:ball{ pos = { 0, 0.5 }, radius = 0.1, density = 2600 }
    m:energy{ on = true }
    m:solve{ time = 3 }
    T.check(#warnings == 0, "no finding at the automatic step: " .. (warnings[1] or ""))
end

-- 5. talus.map: an item stopped by a severe finding is a failed item, the others are kept.
do
    local results = talus.map(3, function(i)
        local m, b = broken()
        if i ~= 2 then m:timestep{ fixed = false } end
        m:solve{ time = 1 }
        return b.pos[2]
    end, { jobs = 2 })
    T.check(results[1] and results[3] and results[2] == nil, "items 1 and 3 ran, item 2 failed")
    T.check(results.failed and #results.failed == 1 and results.failed[1].index == 2
        and results.failed[1].message:find("a severe finding", 1, true), "results.failed names item 2 and why")
end
T.done("guard_severe")
