-- SPDX-License-Identifier: MIT
--
-- rockfall_analysis.lua: a small rockfall analysis with scripts/lib/rockfall.lua (docs/rockfall.md).
-- Clump rocks from a line seeder at the crest of Nejati's (2008) stepped profile, two slope
-- materials, a barrier line near the toe and two collectors; a Monte Carlo
-- of independent rocks (all cores when talus.map exists), per-rock CSVs and, when the module
-- rockfall_stats is present, the statistics and their plots.
--
--   talus run scripts/examples/rockfall_analysis.lua [outdir] [--n=300] [--seed=2026]
--                                                    [--jobs=J] [--impacts] [--paths=20]
--                                                    [--mass-release=N]
--
-- Inputs:
--   profile   (0,60) (7.3,40) (19.3,40) (26.2,20) (38.6,20) (46,0) (170,0) [m];
--             roughness: vertices every 2 m, each moved up to 0.05 m across the slope, a
--             different perturbation per rock (RocFall-style).
--   materials bedrock on the three cliff faces, talus on the benches and the toe flat.
--             Restitution: bedrock Rn = 0.53 ("clean hard bedrock", RocFall defaults,
--             RocFall's classic default materials); talus Rn = 0.45 with rolling friction tan(beta) = 0.35
--             (STONE's "loosely packed clastic deposits"); bedrock tan(beta) = 0.30 (STONE).
--             Each Rn is the damping ratio of a linear dashpot with that restitution,
--             dp_nratio = -ln Rn / sqrt(pi^2 + ln^2 Rn) = 0.198 / 0.246. Friction 0.5 (bedrock)
--             and 0.6 (talus). kn = 1e8 N/m (Nejati 2008 used 1e6-1e7 N/m for walls; for 1-2 t
--             rocks 1e8 keeps a 20 m/s impact's overlap near 8 cm), ks = kn/2.
--             Rolling resistance: with the rrlinear plugin, rr_fric = (1 + kappa) tan(beta),
--             kappa = I / (m R^2) = 1/2 for a disk, so that a rolling disk decelerates at
--             g tan(beta) (rrlinear's run-out v^2 (1 + kappa) / (2 rr_fric g)). Without rrlinear
--             the script falls back to linear and says so (rounded rocks then roll farther).
--   rocks     An's (2006) rock (three equal balls in mutual contact) and rounded hexagons, half
--             each; mass lognormal, mean 1500 kg, sd 500 kg, truncated to 300-5000 kg (2D,
--             unit thickness, density 2600 kg/m^3: r_eq about 0.43 m at 1500 kg); random angle.
--   seeder    a line from (0.5, 61) to (2.5, 61): vx uniform 0.5-3 m/s, vy 0, spin 0.
--   lines     collectors at x = 30 m (second bench) and x = 50 m (toe flat); a barrier at
--             x = 52 m with capacity 30 kJ and height 2 m.
-- Outputs in <outdir> (default out/rockfall_analysis): per rock rock_endpoints.csv,
-- rock_crossings.csv, rock_barriers.csv, rock_profile.csv, rock_impacts.csv (--impacts),
-- rock_paths.csv (the first --paths rocks), and the statistics files of rockfall_stats when
-- present (scripts/plot_rockfall.py plots those), and rockfall_endpoints.png: where each rock
-- stopped, drawn with m:picture (docs/output.md). Prints a summary.

local rockfall = require("rockfall")

local outdir, n, seed, jobs, impacts, paths, mass_n = "out/rockfall_analysis", 300, 2026, nil, false, 20, nil
for _, a in ipairs(arg) do
    local key, value = a:match("^%-%-([%w_%-]+)=(.+)$")
    if key == "n" then n = math.tointeger(tonumber(value)) or error("--n needs an integer")
    elseif key == "seed" then seed = math.tointeger(tonumber(value)) or error("--seed needs an integer")
    elseif key == "jobs" then jobs = math.tointeger(tonumber(value)) or error("--jobs needs an integer")
    elseif key == "paths" then paths = math.tointeger(tonumber(value)) or error("--paths needs an integer")
    elseif key == "mass-release" then mass_n = math.tointeger(tonumber(value)) or error("--mass-release needs an integer")
    elseif a == "--impacts" then impacts = true
    elseif a:match("^%-%-") then
        error("unknown option " .. a .. " (--n=, --seed=, --jobs=, --impacts, --paths=, --mass-release=)")
    else outdir = a end
end

-- Contact model of the slope: rrlinear when the plugin is available, else linear.
local model = "linear"
if pcall(talus.contact_model_info, "rrlinear") then
    model = "rrlinear"
else
    print("rockfall_analysis: the rrlinear contact model is not available; using linear "
        .. "(no rolling resistance: rounded rocks roll farther than they should)")
end
local function material(rn, fric, tan_beta)
    local props = { kn = 1e8, ks = 5e7, fric = fric, dp_nratio = rockfall.dp_nratio(rn), dp_mode = "full" }
    if model == "rrlinear" then props.rr_fric = 1.5 * tan_beta end
    return { model = model, props = props }
end

local an = rockfall.analysis{
    profile = { {0, 60}, {7.3, 40}, {19.3, 40}, {26.2, 20}, {38.6, 20}, {46, 0}, {170, 0} },
    materials = {
        bedrock = material(0.53, 0.5, 0.30),
        talus = material(0.45, 0.6, 0.35),
    },
    zones = {
        { material = "bedrock", x_from = 0, x_to = 7.3 },
        { material = "talus", x_from = 7.3, x_to = 19.3 },
        { material = "bedrock", x_from = 19.3, x_to = 26.2 },
        { material = "talus", x_from = 26.2, x_to = 38.6 },
        { material = "bedrock", x_from = 38.6, x_to = 46 },
        { material = "talus", x_from = 46, x_to = 170 },
    },
    roughness = { amplitude = 0.05, spacing = 2 },
    seeders = { {
        kind = "line", from = {0.5, 61}, to = {2.5, 61},
        vx = { dist = "uniform", min = 0.5, max = 3 }, vy = 0, spin = 0,
        rock = {
            { shape = "three_balls", weight = 1, mass = { dist = "lognormal", mean = 1500, sd = 500, min = 300, max = 5000 } },
            { shape = "ngon", n = 6, name = "hexagon", weight = 1,
              mass = { dist = "lognormal", mean = 1500, sd = 500, min = 300, max = 5000 } },
        },
    } },
    collectors = { { name = "bench2", x = 30 }, { name = "toe", x = 50 } },
    barriers = { { name = "fence", x = 52, energy = 30e3, height = 2 } },
    envelope = { x0 = 0, x1 = 170, dx = 2 },
    seed = seed, n = n,
}

local wall = os.time()
local clock = os.clock()
local records, info
if mass_n then
    records = rockfall.mass_release(an, { n = mass_n })
    rockfall.write_csv(records, an, outdir, { impacts = impacts })
else
    records, info = rockfall.monte_carlo(an, { n = n, outdir = outdir, jobs = jobs, impacts = impacts,
        trajectories = paths })
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
