-- SPDX-License-Identifier: MIT
--
-- rockfall_analysis.lua: a small rockfall analysis with the rockfall library, scripts/lib/rockfall/ (docs/rockfall.md).
-- Clump rocks from a line seeder at the crest of Nejati's (2008) stepped profile, two slope
-- materials, a barrier line near the toe and two collectors; a Monte Carlo
-- of independent rocks (all cores when talus.map exists), per-rock CSVs and, when the module
-- rockfall_stats is present, the statistics and their plots.
--
--   talus run scripts/examples/rockfall_analysis.lua [outdir] [--n=300] [--seed=2026]
--                                                    [--jobs=J] [--impacts] [--paths=20]
--                                                    [--mass-release=N] [--runout95=H]
--
-- --runout95=H runs until the 95 % run-out is known to +-H m (95 % confidence), in batches of
-- 100, 200, 400, ... rocks (docs/rockfall.md, "Rockfall by the answer"), instead of --n rocks.
--
-- Inputs: scripts/examples/rockfall_nejati.lua (the slope, its materials, the rocks, the seeder,
-- the collectors, the barrier and the catchment).
-- Outputs in <outdir> (default out/rockfall_analysis): per rock rock_endpoints.csv,
-- rock_crossings.csv, rock_barriers.csv, rock_profile.csv, rock_impacts.csv (--impacts),
-- rock_paths.csv (the first --paths rocks), and the statistics files of rockfall_stats when
-- present (scripts/plot_rockfall.py plots those), and rockfall_endpoints.png: where each rock
-- stopped, drawn with m:picture (docs/output.md). Prints a summary.

local rockfall = require("rockfall")

local outdir, n, seed, jobs, impacts, paths, mass_n = "out/rockfall_analysis", 300, 2026, nil, false, 20, nil
local runout95
for _, a in ipairs(arg) do
    local key, value = a:match("^%-%-([%w_%-]+)=(.+)$")
    if key == "n" then n = math.tointeger(tonumber(value)) or error("--n needs an integer")
    elseif key == "seed" then seed = math.tointeger(tonumber(value)) or error("--seed needs an integer")
    elseif key == "jobs" then jobs = math.tointeger(tonumber(value)) or error("--jobs needs an integer")
    elseif key == "paths" then paths = math.tointeger(tonumber(value)) or error("--paths needs an integer")
    elseif key == "mass-release" then mass_n = math.tointeger(tonumber(value)) or error("--mass-release needs an integer")
    elseif key == "runout95" then runout95 = tonumber(value) or error("--runout95 needs a number (m)")
    elseif a == "--impacts" then impacts = true
    elseif a:match("^%-%-") then
        error("unknown option " .. a .. " (--n=, --seed=, --jobs=, --impacts, --paths=, --mass-release=, --runout95=)")
    else outdir = a end
end

-- The slope, its materials and rocks: rockfall_nejati.lua beside this script (found from its path,
-- so that the script runs from any directory and through dofile).
local here = debug.getinfo(1, "S").source:match("^@(.*)[/\\][^/\\]*$") or "."
local options, model = dofile(here .. "/rockfall_nejati.lua")(seed, n)
local an = rockfall.analysis(options)

local wall = os.time()
local clock = os.clock()
local records, info
if mass_n then
    records = rockfall.mass_release(an, { n = mass_n })
    rockfall.write_csv(records, an, outdir, { impacts = impacts })
else
    local precision = runout95 and { { stat = "run_out", p = 0.95, within = runout95 } } or nil
    records, info = rockfall.monte_carlo(an, { n = not precision and n or nil, outdir = outdir, jobs = jobs,
        impacts = impacts, trajectories = paths, precision = precision })
end
local cpu = os.clock() - clock

if (talus.rank and talus.rank() or 0) == 0 then
    print(string.format("rockfall_analysis: %d %s rocks on Nejati's (2008) profile, model %s, seed %d",
        #records, mass_n and "mass-released" or "independent", model, seed))
    print("  " .. rockfall.summary(records, an))
    local steps, passed, above = 0, {}, {}
    for _, r in ipairs(records) do
        steps = steps + (r.steps or 0)
        for _, c in ipairs(r.crossings) do
            passed[c.line] = (passed[c.line] or 0) + 1
            above[c.line] = above[c.line] or {}
            table.insert(above[c.line], c.ke)
        end
    end
    for _, c in ipairs(an.collectors) do
        local ke = above[c.name] or {}
        table.sort(ke)
        print(string.format("  collector %s (x = %g m): %d of %d rocks crossed; kinetic energy median %.3g J, "
            .. "95%% %.3g J", c.name, c.x, passed[c.name] or 0, #records,
            ke[math.max(1, math.ceil(0.5 * #ke))] or 0, ke[math.max(1, math.ceil(0.95 * #ke))] or 0))
    end
    local ret = info and info.summary and info.summary.retention
    if ret then
        local w = ret.widths[2]
        print(string.format("  catchment: %.1f%% of the rocks stopped above the toe (x = %g m); 95%% within "
            .. "%.3g m of it [%.3g, %.3g]", 100 * ret.curve[1].fraction, ret.toe.x, w.width, w.lo, w.hi))
        for _, c in ipairs(ret.catchments) do
            print(string.format("  catchment %s (x = %g..%g m): retained %.1f%% of the rocks [%.1f, %.1f], "
                .. "%.1f%% of the %d that reached it", c.name, c.x_from, c.x_to, 100 * c.fraction, 100 * c.lo,
                100 * c.hi, 100 * c.of_reached, c.reached))
        end
    end
    print(string.format("  CPU %.2f s in this process (%.3f s per rock%s); wall about %d s",
        cpu, cpu / #records, (info and info.parallel) and ", workers not counted" or "", os.time() - wall))
    print("  wrote " .. outdir .. "/rock_endpoints.csv, rock_crossings.csv, rock_barriers.csv, rock_profile.csv"
        .. (impacts and ", rock_impacts.csv" or "") .. ((not mass_n and paths > 0) and ", rock_paths.csv" or "")
        .. ((info and info.stats) and " and the statistics (rockfall_stats)" or ""))

    -- One picture of the outcome (m:picture, docs/output.md): the profile, the fence, and each
    -- rock as a disk of its equivalent radius where it stopped (up to x = 92 m), coloured by
    -- its mass. A model built only to be drawn: it is never cycled.
    local ok_pic, why = pcall(function()
        local pic = talus.model{}
        pic:wall{ points = an.nominal }
        pic:wall{ points = { {52, 0}, {52, 2} } }
        for _, r in ipairs(records) do
            if r.end_x and r.end_x >= -2 and r.end_x <= 92 then  -- in the view
                -- (a rock the fence stopped is recorded where it met the fence's line: drawn in
                -- front of it, as a ball is not placed with its centre on a wall)
                local x = r.stop == "barrier" and r.end_x - r.r_eq or r.end_x
                pic:ball{ pos = { x, r.end_y }, radius = r.r_eq, mass = r.mass }
            end
        end
        pic:picture{ file = outdir .. "/rockfall_endpoints.png", size = {1200, 900},
                     view = { -2, -3, 92, 63 }, color = function(b) return b.mass end,
                     label = "rock mass [kg]",
                     title = string.format("Where %d rocks stopped (Nejati 2008 profile, fence at x = 52 m)",
                         #records) }
    end)
    print(ok_pic and ("  wrote " .. outdir .. "/rockfall_endpoints.png")
        or ("  no picture: " .. tostring(why)))
end
