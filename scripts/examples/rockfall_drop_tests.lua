-- SPDX-License-Identifier: MIT
--
-- rockfall_drop_tests.lua: drop tests of a breakable block onto a rock slab, in 2D, over drop
-- heights, for the comparison with the published full-scale tests (docs/results/
-- rockfall-fragmenting.md). A square block of side 1 m (2600 kg per metre of thickness; the
-- material Lac du Bonnet granite with parallel bonds, softened as by default) falls flat from
-- height h onto a horizontal slab (linear contact, restitution 0.5, friction 0.6, its kn 4 times
-- emod, so that the 2.6 t block does not push its first balls through it at 28 m/s): it is
-- released just above the slab at the free-fall speed sqrt(2 g h), the same impact without the
-- flight. For each height and packing seed: bonds broken, pieces, the largest piece's mass
-- share (the survival rate of Ruiz-Carulla & Corominas 2020), the Rosin-Rammler fit of the
-- mass distribution, and the share of the impact's kinetic energy the broken bonds released
-- (Giacomini et al. 2009 report the share of the impact energy spent in fragmentation).
--
--   talus run scripts/examples/rockfall_drop_tests.lua [out.csv] [--balls=200] [--seeds=3]
--                                                      [--heights=5,10,20,40] [--emod=1e8]
local rockfall = require("rockfall")

local out, balls, seeds, emod = nil, 200, 3, 1e8
local heights = { 5, 10, 20, 40 }
for _, a in ipairs(arg or {}) do
    local k, v = a:match("^%-%-([%w_]+)=(.+)$")
    if k == "balls" then balls = math.tointeger(tonumber(v))
    elseif k == "seeds" then seeds = math.tointeger(tonumber(v))
    elseif k == "emod" then emod = tonumber(v)
    elseif k == "heights" then
        heights = {}
        for h in v:gmatch("[^,]+") do heights[#heights + 1] = tonumber(h) end
    elseif k then error("unknown option --" .. k .. " (known: --balls, --seeds, --heights, --emod)")
    else out = a end
end

local g = 9.81
local function drop(h, seed)
    local an = rockfall.analysis{
        profile = { { -20, 0 }, { 20, 0 } },
        materials = { slab = { model = "linear", props = { kn = 1e8, ks = 5e7, fric = 0.6,
            dp_nratio = rockfall.dp_nratio(0.5) } } },
        -- a square: ngon n = 4 with small corners, one face down (angle pi/4), side 1 m
        seeders = { { kind = "point", at = { 0, 0.8 }, vy = -math.sqrt(2 * g * h),
            rock = { shape = "ngon", n = 4, corner = 0.1, volume = 1.0, angle = math.pi / 4 },
            breakable = { material = "lac_du_bonnet", balls = balls, seed = seed, emod = emod, slope_kn = 4 * emod } } },
        t_max = 0.6, seed = 1,
    }
    local c0 = os.clock()
    local r = rockfall.run_rock(an, 1)
    return r, os.clock() - c0
end

local rows = {}
print(string.format("%6s %8s %5s %7s %7s %8s %7s %7s %9s %7s", "h [m]", "E/m J/kg", "seed", "broken", "pieces",
    "largest", "rr_d0", "rr_n", "released", "CPU s"))
for _, h in ipairs(heights) do
    for seed = 1, seeds do
        local r, cpu = drop(h, seed)
        local b = r.breakage
        local ep = b.impacts[1]
        local share = ep and ep.energy.released / ep.energy.ke_before or 0
        rows[#rows + 1] = { h, g * h, seed, r.broken, r.bonds, b.pieces, b.largest_share, b.rr_d0, b.rr_n, share, cpu }
        print(string.format("%6.1f %8.0f %5d %7d %7d %8.3f %7s %7s %8.1f%% %7.1f", h, g * h, seed, r.broken, b.pieces,
            b.largest_share, b.rr_d0 and string.format("%.3f", b.rr_d0) or "-",
            b.rr_n and string.format("%.2f", b.rr_n) or "-", 100 * share, cpu))
    end
end
if out then
    local Csv = require("talus_util.csv")
    assert(Csv.write(out, { "height", "energy_per_mass", "seed", "broken", "bonds", "pieces", "largest_share", "rr_d0",
        "rr_n", "released_share", "cpu" }, rows, { digits = 8 }))
    print("written: " .. out)
end
