-- SPDX-License-Identifier: MIT
-- More impact energy, more fragments. A disk rock of 100 bonded balls (Lac du Bonnet parallel
-- bonds, softened as by default) hits a flat slope at 8, 16 and 32 m/s (32, 128 and 512 J/kg),
-- for two packings (seeds 1 and 2). For each packing the number of pieces must grow and the
-- largest piece's mass share fall strictly from each speed to the next, and the slowest impact
-- must leave most of the rock in one piece (largest share > 0.5) while the fastest leaves none
-- above a third. The bonds' strength decides: a law that breaks by energy alone would also pass,
-- a rock that never breaks or that shatters whatever the speed fails.
local T = require("testlib")
local rf = require("rockfall")

local function drop(v, seed)
    local an = rf.analysis{
        profile = { { -10, 0 }, { 10, 0 } },
        materials = { slope = { model = "linear", props = { kn = 1e8, ks = 5e7, fric = 0.5, dp_nratio = 0.3 } } },
        seeders = { { kind = "point", at = { 0, 0.6 }, vy = -v,
            rock = { shape = "ball", radius = 0.5 }, breakable = { balls = 100, seed = seed } } },
        t_max = 0.25, seed = 5,
    }
    return rf.run_rock(an, 1)
end

for _, seed in ipairs({ 1, 2 }) do
    local prev
    for k, v in ipairs({ 8, 16, 32 }) do
        local r = drop(v, seed)
        local b = r.breakage
        print(string.format("packing %d: %2d m/s (%4d J/kg): %3d of %3d bonds broken, %3d pieces, largest share %.3f",
            seed, v, math.floor(0.5 * v * v), r.broken, r.bonds, b.pieces, b.largest_share))
        if k == 1 then T.check(b.largest_share > 0.5, "a slow impact leaves most of the rock whole") end
        if k == 3 then T.check(b.largest_share < 1 / 3, "a fast impact leaves no piece above a third") end
        if prev then
            T.check(b.pieces > prev.pieces, string.format("more pieces at %g m/s than at the speed before", v))
            T.check(b.largest_share < prev.largest_share, string.format("a smaller largest piece at %g m/s", v))
        end
        prev = b
    end
end
T.done("rockfall_breakable_energy_trend")
