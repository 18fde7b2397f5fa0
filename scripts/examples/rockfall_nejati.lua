-- SPDX-License-Identifier: MIT
--
-- rockfall_nejati.lua: the example's analysis options, shared by rockfall_analysis.lua (the
-- main job) and rockfall_resolution.lua (its run-out against the contact resolution):
--   local options, model = dofile(dir .. "/rockfall_nejati.lua")(seed, n)  -- rockfall.analysis's table
--
--   profile   (0,60) (7.3,40) (19.3,40) (26.2,20) (38.6,20) (46,0) (170,0) [m] (Nejati 2008);
--             roughness: vertices every 2 m, each moved up to 0.05 m across the slope, a
--             different perturbation per rock (RocFall-style).
--   materials bedrock on the three cliff faces, talus on the benches and the toe flat.
--             Restitution: bedrock Rn = 0.53 ("clean hard bedrock", RocFall's classic default
--             materials); talus Rn = 0.45 with rolling friction tan(beta) = 0.35 (STONE's
--             "loosely packed clastic deposits"); bedrock tan(beta) = 0.30 (STONE).
--             Each Rn is the damping ratio of a linear dashpot with that restitution,
--             dp_nratio = -ln Rn / sqrt(pi^2 + ln^2 Rn) = 0.198 / 0.246. Friction 0.5 (bedrock)
--             and 0.6 (talus). kn = 1e8 N/m (Nejati 2008 used 1e6-1e7 N/m for walls; for 1-2 t
--             rocks 1e8 keeps a 20 m/s impact's overlap near 8 cm), ks = kn/2.
--             Rolling resistance: with the rrlinear plugin, rr_fric = (1 + kappa) tan(beta),
--             kappa = I / (m R^2) = 1/2 for a disk, so that a rolling disk decelerates at
--             g tan(beta) (rrlinear's run-out v^2 (1 + kappa) / (2 rr_fric g)). Without rrlinear
--             the options fall back to linear and say so (rounded rocks then roll farther).
--   rocks     An's (2006) rock (three equal balls in mutual contact) and rounded hexagons, half
--             each; mass lognormal, mean 1500 kg, sd 500 kg, truncated to 300-5000 kg (2D,
--             unit thickness, density 2600 kg/m^3: r_eq about 0.43 m at 1500 kg); random angle.
--   seeder    a line from (0.5, 61) to (2.5, 61): vx uniform 0.5-3 m/s, vy 0, spin 0.
--   lines     collectors at x = 30 m (second bench) and x = 50 m (toe flat); a barrier at
--             x = 52 m with capacity 30 kJ and height 2 m; the catchment between the toe
--             (x = 46 m) and the barrier, whose retention the statistics report.
local rockfall = require("rockfall")

return function(seed, n)
    -- Contact model of the slope: rrlinear when the plugin is available, else linear.
    local model = "linear"
    if pcall(talus.contact_model_info, "rrlinear") then
        model = "rrlinear"
    else
        print("rockfall_nejati: the rrlinear contact model is not available; using linear "
            .. "(no rolling resistance: rounded rocks roll farther than they should)")
    end
    local function material(rn, fric, tan_beta)
        local props = { kn = 1e8, ks = 5e7, fric = fric, dp_nratio = rockfall.dp_nratio(rn), dp_mode = "full" }
        if model == "rrlinear" then props.rr_fric = 1.5 * tan_beta end
        return { model = model, props = props }
    end
    local mass = { dist = "lognormal", mean = 1500, sd = 500, min = 300, max = 5000 }
    return {
        profile = { { 0, 60 }, { 7.3, 40 }, { 19.3, 40 }, { 26.2, 20 }, { 38.6, 20 }, { 46, 0 }, { 170, 0 } },
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
            kind = "line", from = { 0.5, 61 }, to = { 2.5, 61 },
            vx = { dist = "uniform", min = 0.5, max = 3 }, vy = 0, spin = 0,
            rock = {
                { shape = "three_balls", weight = 1, mass = mass },
                { shape = "ngon", n = 6, name = "hexagon", weight = 1, mass = mass },
            },
        } },
        collectors = { { name = "bench2", x = 30 }, { name = "toe", x = 50 } },
        barriers = { { name = "fence", x = 52, energy = 30e3, height = 2 } },
        catchments = { { name = "toe_area", x_from = 46, x_to = 52 } },
        envelope = { x0 = 0, x1 = 170, dx = 2 },
        seed = seed, n = n,
    }, model
end
