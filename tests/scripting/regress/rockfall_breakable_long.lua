-- SPDX-License-Identifier: MIT
-- A breakable rock from release to rest on Nejati's (2008) profile: the whole run's books close.
-- A hexagon of 2.2 t and 78 balls (the fragmenting example's rock 1, Lac du Bonnet parallel
-- bonds softened as by default) falls the three cliffs, breaks (86 of 131 bonds) and its 45
-- pieces roll, collide and come to rest over 16 s, 280 000 steps, with the engine's balance
-- guard on (it stops a run that creates more than 10 % of its input). Also checked: the pieces
-- at rest leave the run with their stop and end time, and every piece that rests beyond a
-- collector has crossed it (per-fragment crossings).
--
-- Before the fix of pbond's normal increments and dashpot load (pbond_turning.lua) the books of
-- such runs drifted while the fragments spun and came to rest: -43 % of the input for this rock at 80 balls
-- (energy created: the run stopped at t = 8.3 s on the guard's severe finding, or, reported only,
-- ended at -43 %). Now: 0.35 % (measured; five rocks of 80-150 balls 0.23-0.34 %), what the
-- first impact leaves (the leapfrog's impact term at the bonded balls' stability step, 0.2-0.5 %
-- in the drop tests). Bound 1 %, the guard's own tolerance: three times the measured value, and
-- 40 times below the defect.
local T = require("testlib")
local rockfall = require("rockfall")

local here = debug.getinfo(1, "S").source:sub(2):match("(.*/)") or "./"
local opts = dofile(here .. "../../../scripts/examples/rockfall_nejati.lua")(2026, 2)
opts.seeders[1].rock = { shape = "ngon", n = 6, name = "hexagon", mass = { dist = "uniform", min = 1000, max = 2500 } }
opts.seeders[1].breakable = { material = "lac_du_bonnet", balls = 80 }
local an = rockfall.analysis(opts)
local c0 = os.clock()
local rec = rockfall.run_rock(an, 1)
local e = rec.energy
print(string.format("rockfall_breakable_long: %s at t = %.2f s after %d steps (%.1f s CPU): %d balls, %d of %d bonds"
    .. " broken, %d pieces; balance error %.4g J of %.4g J input (%.3f %%)", rec.stop, rec.t_end, rec.steps,
    os.clock() - c0, rec.balls, rec.broken, rec.bonds, rec.breakage.pieces, e.balance_error, e.input,
    100 * e.balance_error / e.input))
T.check(rec.stop == "rest", "the fragments come to rest (stop: " .. tostring(rec.stop) .. ")")
T.check(rec.t_end > 10, "a long run: more than 10 s simulated")
T.check(rec.broken > 20 and rec.breakage.pieces > 10, "the rock broke")
T.near(e.balance_error / e.input, 0, 0.01, "the whole run's books: balance error / input")
-- Fragments at rest leave the run (breakable.settle): each row says how and when it stopped.
local masses, settled = 0, 0
for _, f in ipairs(rec.fragments) do
    masses = masses + f.mass
    T.check(f.stop == "rest" or f.stop == "left", "fragment " .. f.fragment .. " stopped: " .. tostring(f.stop))
    T.check(f.t_end and f.t_end <= rec.t_end, "fragment " .. f.fragment .. " has its end time")
    if f.t_end < rec.t_end then settled = settled + 1 end
end
T.near(masses / rec.mass, 1, 1e-9, "the fragments hold the rock's mass")
T.check(settled > 0, "fragments at rest left the run before its end (" .. settled .. ")")
-- Per-fragment crossings: every fragment that came to rest beyond a collector crossed it.
local crossed = {}
for _, c in ipairs(rec.fragment_crossings) do crossed[c.fragment .. "|" .. c.line] = c end
local beyond = 0
for _, f in ipairs(rec.fragments) do
    for _, line in ipairs(an.collectors) do
        if f.stop == "rest" and f.x > line.x + 1 then
            beyond = beyond + 1
            local c = crossed[f.fragment .. "|" .. line.name]
            T.check(c ~= nil and c.t <= f.t_end, "fragment " .. f.fragment .. " at x = " .. f.x .. " crossed " .. line.name)
        end
    end
end
T.check(beyond > 0, "some fragments came to rest beyond a collector")
T.done("rockfall_breakable_long")
