-- SPDX-License-Identifier: MIT
--
-- rockfall_fragmenting.lua: rocks that break on Nejati's (2008) stepped profile. Each rock is
-- run twice from the same draw (position, size, angle, velocity, roughness): once rigid (a
-- rounded hexagon clump) and once as a breakable rock of bonded balls (Lac du Bonnet granite
-- with parallel bonds, softened for speed: docs/rockfall.md, "Rocks that break"). Printed: the
-- rigid rock's run-out beside the fragments' (the largest fragment's end x, the farthest
-- fragment's), the pieces, the largest piece's share, the Rosin-Rammler fit of the mass
-- distribution, each breakage episode's energy split and the CPU of each run.
--
--   talus run scripts/examples/rockfall_fragmenting.lua [outdir] [--n=2] [--balls=500]
--                                                       [--seed=2026] [--emod=1e8] [--safety=0.5]
--                                                       [--settle=true]
--
-- Writes into outdir (default out/rockfall_fragmenting): rock_endpoints.csv etc. of the rigid
-- rocks in rigid/, of the breakable ones in breakable/ with rock_fragments.csv (one row per
-- fragment at the end) and rock_breakage.csv (one row per breakage episode), fragment_curve.csv
-- (the cumulative mass curve of each breakable rock) and break_rock<i>.png (the broken rock
-- at rest, each fragment its own colour, the broken bonds drawn).
local rockfall = require("rockfall")

local outdir, n, balls, seed, emod, safety, settle = "out/rockfall_fragmenting", 2, 500, 2026, 1e8, nil, true
for _, a in ipairs(arg or {}) do
    local k, v = a:match("^%-%-([%w_]+)=(.+)$")
    if k == "n" then n = math.tointeger(tonumber(v))
    elseif k == "balls" then balls = math.tointeger(tonumber(v))
    elseif k == "seed" then seed = math.tointeger(tonumber(v))
    elseif k == "emod" then emod = tonumber(v)
    elseif k == "safety" then safety = tonumber(v)
    elseif k == "settle" then settle = v ~= "false"
    elseif k then error("unknown option --" .. k .. " (known: --n, --balls, --seed, --emod, --safety, --settle)")
    else outdir = a end
end

local here = debug.getinfo(1, "S").source:sub(2):match("(.*/)") or "./"
local function options()
    local opts = dofile(here .. "rockfall_nejati.lua")(seed, n)
    -- one shape: a rounded hexagon of 1-2.5 t
    opts.seeders[1].rock = { shape = "ngon", n = 6, name = "hexagon",
        mass = { dist = "uniform", min = 1000, max = 2500 } }
    return opts
end
local rigid = rockfall.analysis(options())
local bopts = options()
bopts.seeders[1].breakable = { material = "lac_du_bonnet", balls = balls, emod = emod, safety = safety, settle = settle }
local breakable = rockfall.analysis(bopts)
talus.mkdir(outdir)

local rigid_recs, break_recs, curve_rows = {}, {}, {}
print(string.format("%4s %7s %9s %8s | %9s %9s %6s %7s %8s %8s %7s %7s", "rock", "mass", "rigid x", "CPU",
    "largest x", "farthest", "pieces", "largest", "rr_d0", "rr_n", "balls", "CPU"))
for i = 1, n do
    local c0 = os.clock()
    local r = rockfall.run_rock(rigid, i)
    local c1 = os.clock()
    local ok, b = pcall(rockfall.run_rock, breakable, i, { on_end = function(m, rec)
        -- each fragment its own colour: the record's fragment number of each ball (pieces that
        -- came to rest early are back in the model, fixed, for the picture)
        local index = rec.ball_fragment
        -- the view: 6 m around the largest fragment at rest
        local xc, yc = rec.end_x, rec.end_y
        m:picture{ file = string.format("%s/break_rock%d.png", outdir, i), cracks = true,
            color = function(ball) return (index[ball.id] or 0) % 10 end, label = "fragment (mod 10)",
            view = { xc - 6, yc - 2, xc + 6, yc + 3 }, title = string.format("rock %d at rest: %d pieces", i,
                rec.breakage.pieces) }
    end })
    local c2 = os.clock()
    rigid_recs[i] = r
    if not ok then
        print(string.format("%4d %7.0f %9.2f %7.1fs | breakable rock failed after %.1f s of CPU: %s", i, r.mass, r.end_x,
            c1 - c0, c2 - c1, tostring(b)))
        goto next
    end
    break_recs[#break_recs + 1] = b
    local br = b.breakage
    print(string.format("%4d %7.0f %9.2f %7.1fs | %9.2f %9.2f %6d %7.3f %8s %8s %7d %6.1fs", i, r.mass, r.end_x,
        c1 - c0, b.end_x, b.reach_x, br.pieces, br.largest_share,
        br.rr_d0 and string.format("%.3f", br.rr_d0) or "-", br.rr_n and string.format("%.2f", br.rr_n) or "-",
        b.balls, c2 - c1))
    for k, ep in ipairs(br.impacts) do
        local e = ep.energy
        print(string.format("       impact %d at t = %.2f s, x = %.1f m: %.0f J/kg; %d bonds broke, %d pieces, largest %.3f;"
            .. " kinetic %.0f -> %.0f kJ, gravity %+.0f kJ, bond energy released %.1f kJ, slip %.1f, dashpots %.1f kJ"
            .. " (the books' own error %.2f kJ)",
            k, ep.t_start, ep.x or 0, ep.energy_per_mass, ep.broken, ep.pieces, ep.largest_share, e.ke_before / 1e3,
            e.ke_after / 1e3, e.gravity / 1e3, e.released / 1e3, e.slip / 1e3, e.dashpot / 1e3, e.residual / 1e3))
    end
    for _, p in ipairs(br.curve) do curve_rows[#curve_rows + 1] = { i, p.size, p.passing } end
    ::next::
end
rockfall.write_csv(rigid_recs, rigid, outdir .. "/rigid")
rockfall.write_csv(break_recs, breakable, outdir .. "/breakable")
for _, b in ipairs(break_recs) do
    local e = b.energy
    print(string.format("rock %d: the whole run's books close to %.2f %% of the energy put in", b.rock,
        100 * math.abs(e.balance_error) / e.input))
end
local Csv = require("talus_util.csv")
assert(Csv.write(outdir .. "/fragment_curve.csv", { "rock", "size", "passing" }, curve_rows, { digits = 8 }))
print("written: " .. outdir)
