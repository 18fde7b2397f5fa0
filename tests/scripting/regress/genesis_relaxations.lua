-- SPDX-License-Identifier: MIT
-- How the genesis' relaxations stop (docs/material.md "Genesis"): at their ratio, or when the
-- ratio has stalled (no new low below 0.9 of its best for a window of steps), the radius
-- scalings never by running to their cap; and E.solve_ratio's stall criterion itself: a scene that cannot
-- settle (no damping: it oscillates for ever) is stopped as "stalled" about one window after its
-- last new low, far before its cap, while the same scene damped stops at its ratio.
local T = require("testlib")
local M = require("material")
local E = require("material.equilibrium")

-- 1. E.solve_ratio on three balls pressed between two fixed walls. Undamped, the overlaps
-- oscillate for ever (energy is conserved: no damping, no friction work), the ratio sampled
-- every 50 steps never gets below 1e-9; with the window the relaxation stops "stalled", without
-- it runs to the cap. Damped (PFC local damping 0.7) it reaches 1e-6: "ratio".
local function rig(damp)
    local m = talus.model{}
    m:timestep{ resolution = 0 }
    m:damping{ damp = damp }
    m:guard{ energy = "off", resolution = "off" }
    m:placement_warning(false)
    m:contact_model("linear", { kn = 1e8, ks = 1e8, fric = 0 })
    m:wall{ points = {{0, -1}, {0, 1}} }
    m:wall{ points = {{0.586, 1}, {0.586, -1}} }
    -- overlaps 3, 5, 3 and 3 mm: unbalanced from the start; undamped, no contact opens (the
    -- strain energy of the deviations from the mean overlap, 3.5 mm, is 4 times too small)
    m:ball{ pos = {0.097, 0}, radius = 0.1, density = 2600 }
    m:ball{ pos = {0.292, 0}, radius = 0.1, density = 2600 }
    m:ball{ pos = {0.489, 0}, radius = 0.1, density = 2600 }
    return m
end
do
    local cap, window = 200000, 2000
    local n, r, why = E.solve_ratio(rig(0), 1e-9, cap, 50, window)
    T.check(why == "stalled", "undamped: stops stalled, got " .. tostring(why) .. " after " .. n .. " steps")
    T.check(n >= window and n < cap / 4, "undamped: stalled after " .. n .. " steps (window " .. window .. ")")
    T.check(r > 1e-9 and r < math.huge, "undamped: ratio " .. r .. " above its target, finite")
    local n2, _, why2 = E.solve_ratio(rig(0), 1e-9, 20000, 50)
    T.check(why2 == "max_steps" and n2 == 20000, "undamped, no window: to the cap (" .. tostring(why2) .. ")")
    local n3, r3, why3 = E.solve_ratio(rig(0.7), 1e-6, cap, 50, window)
    T.check(why3 == "ratio" and r3 <= 1e-6, "damped: stops at the ratio (" .. tostring(why3) .. ", " .. r3 .. ")")
    T.check(n3 < cap / 4, "damped: " .. n3 .. " steps")
    -- the held step is given back: automatic again after the relaxation
    local m = rig(0.7)
    local _, _, why4 = E.solve_ratio(m, 1e-6, cap, 50, window, 1000)
    T.check(why4 == "ratio", "damped with the step held: " .. tostring(why4))
end

-- 2. A small genesis: every radius scaling (step 2) ends at its ratio (3e-3) or stalled, none
-- at its cap of 5 000 steps; seed 3 has both (measured: scalings 1-4 "ratio", 5-7 "stalled").
local pk = M.genesis{ width = 0.01, height = 0.02, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16,
                      kn = 6.4e10, ks = 9.6e9, seed = 3 }
T.check(#pk.relaxations > 8, "relaxations recorded: " .. #pk.relaxations)
local seen = { ratio = 0, stalled = 0 }
for _, x in ipairs(pk.relaxations) do
    T.check(x.steps >= 0 and type(x.stop) == "string", "relaxation " .. x.phase)
    if x.phase:find("^scaling") then
        T.check(x.stop == "ratio" or x.stop == "stalled",
            string.format("%s: %d steps, ratio %.3g, stop %s", x.phase, x.steps, x.ratio, x.stop))
        T.check(x.stop ~= "ratio" or x.ratio <= 3e-3, x.phase .. ": stop ratio at " .. x.ratio)
        T.check(x.steps < 5000, x.phase .. ": " .. x.steps .. " steps")
        seen[x.stop] = seen[x.stop] + 1
    end
end
T.check(seen.ratio >= 1 and seen.stalled >= 1, "scalings: " .. seen.ratio .. " at the ratio, " .. seen.stalled .. " stalled")
local last = pk.relaxations[#pk.relaxations]
T.check(last.phase == "final servo", "the last relaxation is the final servo: " .. last.phase)
-- the packing file keeps the record (a ratio may be math.huge: written as 1/0)
local f = os.tmpname()
M.save_packing(pk, f)
local back = M.load_packing(f)
os.remove(f)
T.check(#back.relaxations == #pk.relaxations and back.relaxations[1].ratio == pk.relaxations[1].ratio,
    "relaxations round trip")
T.done()
