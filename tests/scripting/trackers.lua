-- SPDX-License-Identifier: MIT
-- Trackers from Lua (m:track, docs/lua-api.md "Trackers"): the records a script reads (impacts,
-- crossings, envelope, path, status), events (a line crossing that the handler acts on, a
-- tracker that ended), and bad input with the script line. The closed forms are checked in C++
-- (tests/core/test_trackers.cpp); here the numbers that cross the binding must be the same ones.
local T = require("testlib")
local script = T.script()
local g, r, dt = 9.81, 0.1, 1e-4

local function floor_model(props)
    local m = talus.model{ gravity = { 0, -g } }
    m:contact_model("linear", props or { kn = 1e7 })
    m:timestep{ fixed = dt }
    m:wall{ points = { { -50, 0 }, { 50, 0 } }, group = "floor" }
    return m
end

-- ---------------------------------------------------------------- a drop: impact and rest
do
    local m = floor_model{ kn = 1e7, ks = 5e6, fric = 0.5, dp_nratio = 0.5 }
    local h = 1.0
    local b = m:ball{ pos = { 0.25, h + r }, radius = r, density = 2600 }
    local ended = {}
    local tr
    tr = m:track(b, {
        impacts = { with = "walls", min_speed = 0.5 },
        rest = { speed = 0.01, time = 0.1 },
        envelope = { ground = { { -50, 0 }, { 50, 0 } }, x0 = 0, dx = 0.5, bins = 4 },
        path = 100,
        on_event = function(t, ev)
            T.check(t == tr, "the event's tracker is the tracker")
            ended[#ended + 1] = ev
        end,
    })
    T.check(tr.id == 1 and tr.state == "tracking" and tr.samples == 1, "first sample at creation")
    T.check(tr.body == b, "the tracked body")
    m:solve{ time = 3 }
    T.check(tr.state == "rest", "came to rest: " .. tr.state)
    T.check(#ended == 1 and ended[1].kind == "end" and ended[1].state == "rest", "one end event")
    local imps = tr:impacts()
    T.check(#imps >= 1, "an impact")
    local im = imps[1]
    local t_touch = math.sqrt(2 * h / g)
    T.check(im.t > t_touch and im.t <= t_touch + dt * (1 + 1e-9), "impact at the first step after the touch")
    T.near(im.approach, g * (im.t - dt / 2), 1e-12, "incoming speed: the half-step velocity")
    T.near(-im.vel[2], im.approach, 1e-15, "approach = -vel . normal")
    T.near(im.normal[2], 1, 1e-15, "normal from the floor toward the ball")
    T.check(im.wall ~= nil and im.wall.id == 1 and im.segment == 1, "what it hit: wall 1, segment 1")
    T.check(im.groups[1] == "floor", "the floor's group")
    T.check(im.ended == true and im.t_end > im.t and im.vel_end[2] > 0, "the touch ended, going up")
    for k = 2, #imps do
        T.check(imps[k].approach >= 0.5, "impacts slower than min_speed are not recorded")
    end
    local st = tr:status()
    T.check(st.state == "rest" and st.rest_since and st.t >= st.rest_since + 0.1, "rest status")
    T.near(st.pos[1], 0.25, 1e-9, "rests where it fell")
    local env = tr:envelope()
    T.check(env.height[1] ~= nil and env.height[2] == nil, "envelope: only the bin it was in (sparse)")
    T.near(env.height[1], h + r, 1e-12, "greatest height: the release")
    local path = tr:path()
    T.check(#path == math.floor((st.t / dt) / 100) + 1 or #path == math.floor((st.t / dt) / 100),
        "a path point every 100 samples: " .. #path)
    T.check(path[1][1] == 0 and path[1][3] == h + r, "the path starts at the release")
    m:cycle(10)
    T.check(tr.samples == st.samples, "an ended tracker takes no sample")
end

-- ---------------------------------------------------------------- a clump crossing event lines
do
    local m = talus.model{ gravity = { 0, 0 } }
    m:contact_model("linear", { kn = 1e7 })
    m:timestep{ fixed = 1e-3 }
    local c = m:clump{ pebbles = { { -0.1, 0, 0.1 }, { 0.1, 0, 0.1 } }, pos = { 0, 0 }, density = 2600,
        vel = { 2, 0 } }
    local seen = {}
    local tr = m:track(c, {
        lines = {
            { from = { 1, -5 }, to = { 1, 5 }, event = true },   -- the barrier: the rock slows down
            { from = { 2, -5 }, to = { 2, 5 } },                 -- a collector, no event
            { from = { 3, -5 }, to = { 3, 5 }, event = true },   -- stops the tracker
        },
        region = { lo = { -1, -1 }, hi = { 10, math.huge } },
        on_event = function(t, ev)
            seen[#seen + 1] = ev
            if ev.kind ~= "crossing" then return end
            if ev.line == 1 then
                T.near(ev.crossing.t, 0.5, 1e-12, "crossing time at constant velocity")
                T.near(ev.crossing.pos[1], 1, 1e-12, "crossing on the line")
                c.vel = { 1, 0 } -- the handler acts before the next step
            elseif ev.line == 3 then
                t:stop()
            end
        end,
    })
    m:cycle(5000)
    local cs = tr:crossings()
    T.check(#cs == 3, "three crossings: " .. #cs)
    T.check(cs[2].line == 2 and cs[2].vel[1] < 1 + 1e-9, "the collector after the slow-down")
    T.near(cs[2].t, 0.5 + 1.0, 1e-9, "crossed the collector 1 m later at 1 m/s")
    T.near(cs[2].ke_trans, 0.5 * c.mass * 1, 1e-12, "kinetic energy at the collector")
    T.check(#seen == 2 and seen[2].line == 3, "events of the event lines only")
    T.check(tr.state == "stopped", "stopped by its handler: " .. tr.state)
end

-- ---------------------------------------------------------------- a deleted body, an exit
do
    local m = floor_model()
    local b = m:ball{ pos = { 0, 0.5 }, radius = r, density = 2600 }
    local tr = m:track(b, { impacts = true })
    m:cycle(10)
    b:delete()
    m:cycle(1)
    T.check(tr.state == "deleted", "a deleted body ends its tracker")
    local line = T.line() + 1
    T.fails(function() m:track(b, {}) end, { script .. ":" .. line .. ":", "ball 1 was deleted" },
        "tracking a deleted ball")
    local b2 = m:ball{ pos = { 0, 5 }, radius = r, density = 2600, vel = { 3, 0 } }
    local events = {}
    local tr2 = m:track(b2, { region = { lo = { -1, -1 }, hi = { 1, 100 } },
        on_event = function(_, ev) events[#events + 1] = ev.state end })
    m:solve{ time = 1 }
    T.check(tr2.state == "exit" and events[1] == "exit", "left the region")
    T.check(tr2:status().pos[1] > 1, "ended at the first sample outside")
end

-- ---------------------------------------------------------------- bad input, save
do
    local m = floor_model()
    local b = m:ball{ pos = { 0, 1 }, radius = r, density = 2600 }
    local line = T.line() + 1
    T.fails(function() m:track(b, { impact = true }) end,
        { script .. ":" .. line .. ":", "track: unknown option 'impact'", "impacts" }, "unknown option")
    T.fails(function() m:track(b, { lines = { { from = { 1, 1 }, to = { 1, 1 } } } }) end,
        { "lines[1] has zero length" }, "a line of zero length")
    T.fails(function() m:track(b, { lines = { { from = { 1, 1 } } } }) end,
        { "lines[1] needs from", "and to" }, "a line without its end")
    T.fails(function() m:track(b, { impacts = "floors" }) end, { "must be one of", "walls" }, "bad kind")
    T.fails(function() m:track(b, { rest = { time = 1 } }) end, { "rest needs energy" }, "rest without a level")
    T.fails(function() m:track(b, { envelope = { x0 = 0, dx = 1, bins = 3 } }) end,
        { "envelope needs ground" }, "envelope without ground")
    T.fails(function() m:track(b, { path = 0 }) end, { "'path' must be" }, "path 0")
    T.fails(function() m:track(b, { on_event = 3 }) end, { "'on_event' must be a function" }, "handler")
    T.fails(function() m:track({}, {}) end, { "argument 1 must be a ball or a clump" }, "not a body")
    local tr = m:track(b)
    T.fails(function() m:track(b) end, { "already has a live tracker (tracker 1)" }, "two trackers")
    T.fails(function() return tr.bogus end, { "unknown field 'bogus'", "impacts()" }, "unknown field")
    T.fails(function() tr.state = "rest" end, { "read-only" }, "fields are read-only")
    local file = os.tmpname()
    T.fails(function() m:save(file) end, { "tracker(s), which are not saved", "clear_trackers" },
        "save refused while trackers are set")
    m:clear_trackers()
    T.check(#m:trackers() == 0, "cleared")
    m:save(file)
    os.remove(file)
    -- An error in a handler names its own line.
    local b2 = m:ball{ pos = { 5, 1 }, radius = r, density = 2600, vel = { 1, 0 } }
    m:track(b2, { lines = { { from = { 5.05, -1 }, to = { 5.05, 3 }, event = true } },
        on_event = function() error("handler failed here") end })
    T.fails(function() m:cycle(2000) end, { "handler failed here" }, "a failing handler stops the run")
end

T.done("trackers")
