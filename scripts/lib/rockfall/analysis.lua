-- SPDX-License-Identifier: MIT
-- rockfall/analysis.lua: an analysis built and checked from the user's options: profile, materials,
-- zones, roughness, seeders, collectors, barriers, envelope, end rules; and the description the
-- statistics receive. docs/rockfall.md lists every option.
local P = require("rockfall.profile")
local Shapes = require("rockfall.shapes")
local Dist = require("rockfall.distributions")
local K = require("rockfall.check")
local fail, check_keys, num, point, hint, sorted_keys = K.fail, K.check_keys, K.num, K.point, K.hint, K.sorted_keys
local read_csv, check_points, zone_profile = P.read_csv, P.check_points, P.zone_profile
local check_rock = Shapes.check_rock
local check_dist = Dist.check_dist

local MATERIAL_KEYS = { "model", "props" }

-- The time-step settings of an independent rock (run_rock, monte_carlo) when the analysis gives
-- none: 20 steps per contact duration instead of the engine's 30. The example's run-out,
-- reach, barrier energy and catchment statistics from 2000 rocks do not move beyond their
-- sampling error from 10 to 90 steps, and from 20 steps on the energy books keep within the
-- engine's 1 % (docs/rockfall.md, "Contact resolution"; scripts/examples/rockfall_resolution.lua).
local ROCK_TIMESTEP = { resolution = 20 }
local SEEDER_KEYS = { "kind", "name", "at", "from", "to", "weight", "rock", "vx", "vy", "spin" }
local ANALYSIS_KEYS = {
    "profile", "materials", "zones", "material", "roughness", "seeders", "collectors", "barriers",
    "seed", "n", "envelope", "gravity", "margin", "rest_speed", "rest_ke", "rest_time", "t_max",
    "impact_min_vn", "path_every", "rock_contact", "timestep", "clearance", "shadow_apex",
    "shadow_steep", "shadow_talus", "toe", "catchments",
}

local function check_model(name, props, where)
    if type(name) ~= "string" then fail("%s.model must be a contact model name", where) end
    local ok, info = pcall(talus.contact_model_info, name)
    if not ok then fail("%s: contact model '%s' is not available (%s)", where, name, tostring(info)) end
    if props ~= nil then
        if type(props) ~= "table" then fail("%s.props must be a table", where) end
        local known, names = {}, {}
        for _, p in ipairs(info.properties) do
            known[p.name:lower()] = true
            if not p.read_only then names[#names + 1] = p.name end
        end
        for k in pairs(props) do
            if type(k) ~= "string" or not known[k:lower()] then
                fail("%s: unknown property '%s' for model '%s'%s (known: %s)", where, tostring(k), name,
                    hint(k, names), table.concat(names, ", "))
            end
        end
        -- A friction angle typed as a coefficient (RocFall gives angles): said once here, not
        -- by every rock's model (run_rock collects the engine's warnings in the record).
        local implausible = {}
        for _, k in ipairs(sorted_keys(props)) do
            local v, key = props[k], k:lower()
            if type(v) == "number" and v > 2 and (key == "fric" or key:match("_fric$")) then
                implausible[#implausible + 1] = v < 90
                    and string.format("%s = %g is a friction coefficient (tan of the friction angle), "
                        .. "not an angle: for a friction angle of %g\u{b0} use %s = tan(%g\u{b0}) = %.3g",
                        k, v, v, k, v, math.tan(math.rad(v)))
                    or string.format("%s = %g is a friction coefficient; above 2 it is not plausible", k, v)
            end
        end
        if #implausible > 0 then
            io.stderr:write(string.format("warning: rockfall.analysis: %s: %s\n", where,
                table.concat(implausible, "; ")))
        end
    end
end

local W = "analysis"

--- The profile, its materials, their zones and the roughness.
local function ground_options(opts, an)
    local prof = opts.profile
    if type(prof) == "string" then prof = read_csv(prof) end
    an.points = check_points(prof, W .. ".profile")
    local materials = opts.materials or { slope = { model = "linear", props = {} } }
    if type(materials) ~= "table" or next(materials) == nil then fail("%s.materials must be a non-empty table", W) end
    for name, mat in pairs(materials) do
        local w = string.format("%s.materials.%s", W, tostring(name))
        if type(name) ~= "string" then fail("%s: material names must be strings", W) end
        if name == "rock" then fail("%s: 'rock' is the rocks' group; choose another name", w) end
        check_keys(mat, MATERIAL_KEYS, w)
        check_model(mat.model or "linear", mat.props, w)
    end
    an.materials = materials
    if opts.material ~= nil and not materials[opts.material] then
        fail("%s.material: unknown material '%s'", W, tostring(opts.material))
    end
    an.nominal, an.segment_material = zone_profile(an.points, opts.zones, materials, opts.material, W)
    -- Roughness.
    if opts.roughness ~= nil then
        local r = opts.roughness
        check_keys(r, { "amplitude", "spacing", "per_rock" }, W .. ".roughness")
        num(r.amplitude, W .. ".roughness.amplitude", 0)
        if r.spacing ~= nil then num(r.spacing, W .. ".roughness.spacing", 1e-6) end
        an.roughness = { amplitude = r.amplitude, spacing = r.spacing, per_rock = r.per_rock ~= false }
    end
end

--- The seed, the number of rocks and the seeders with their rocks and release velocities.
local function seeder_options(opts, an)
    an.seed = opts.seed or 1
    if math.type(an.seed) ~= "integer" then
        if type(an.seed) == "number" and an.seed == math.floor(an.seed) then an.seed = math.tointeger(an.seed)
        else fail("%s.seed must be an integer (got %s)", W, tostring(opts.seed)) end
    end
    an.n = opts.n and math.tointeger(num(opts.n, W .. ".n", 1)) or 100
    -- Seeders.
    if type(opts.seeders) ~= "table" or #opts.seeders == 0 then
        fail("%s.seeders must be a non-empty list of seeders", W)
    end
    an.seeders, an.seeder_weight = {}, 0
    for k, s in ipairs(opts.seeders) do
        local w = string.format("%s.seeders[%d]", W, k)
        check_keys(s, SEEDER_KEYS, w)
        local sd = { name = s.name or ("seeder" .. k), weight = s.weight or 1 }
        num(sd.weight, w .. ".weight", 0)
        local kind = s.kind or (s.at and "point") or "line"
        if kind == "point" then
            sd.from = point(s.at, w .. ".at")
            sd.to = sd.from
        elseif kind == "line" then
            sd.from, sd.to = point(s.from, w .. ".from"), point(s.to, w .. ".to")
        else
            fail("%s.kind must be \"point\" or \"line\" (got %s)", w, tostring(kind))
        end
        sd.kind = kind
        local rocks = s.rock or { shape = "ball", radius = 0.5 }
        if rocks.shape or rocks.name or rocks.radius or rocks.pebbles or #rocks == 0 then rocks = { rocks } end
        sd.rocks, sd.rock_weight = {}, 0
        for j, rk in ipairs(rocks) do
            sd.rocks[j] = check_rock(rk, string.format("%s.rock[%d]", w, j))
            sd.rock_weight = sd.rock_weight + (rk.weight or 1)
        end
        sd.vx = check_dist(s.vx or 0, w .. ".vx")
        sd.vy = check_dist(s.vy or 0, w .. ".vy")
        sd.spin = check_dist(s.spin or 0, w .. ".spin")
        an.seeders[k] = sd
        an.seeder_weight = an.seeder_weight + sd.weight
    end
    if an.seeder_weight <= 0 then fail("%s.seeders: the weights sum to 0", W) end
end

--- The collector and barrier lines (within the profile's x range) and the envelope's bins.
local function line_options(opts, an)
    local x0, x1 = an.points[1][1], an.points[#an.points][1]
    an.collectors = {}
    for k, c in ipairs(opts.collectors or {}) do
        local w = string.format("%s.collectors[%d]", W, k)
        check_keys(c, { "name", "x" }, w)
        num(c.x, w .. ".x", x0, x1)
        an.collectors[k] = { name = c.name or ("collector" .. k), x = c.x }
    end
    an.barriers = {}
    for k, b in ipairs(opts.barriers or {}) do
        local w = string.format("%s.barriers[%d]", W, k)
        check_keys(b, { "name", "x", "energy", "height" }, w)
        num(b.x, w .. ".x", x0, x1)
        num(b.energy, w .. ".energy", 0)
        num(b.height, w .. ".height", 0)
        an.barriers[k] = { name = b.name or ("barrier" .. k), x = b.x, energy = b.energy, height = b.height }
    end
    table.sort(an.barriers, function(a, b) return a.x < b.x end)
    -- Catchments: the toe the retention distances start from, and named catchment areas.
    if opts.toe ~= nil then an.toe = num(opts.toe, W .. ".toe", x0, x1) end
    an.catchments = opts.catchments and {} or nil
    local names = {}
    for k, c in ipairs(opts.catchments or {}) do
        local w = string.format("%s.catchments[%d]", W, k)
        check_keys(c, { "name", "x_from", "x_to" }, w)
        local name = c.name or ("catchment" .. k)
        if names[name] then fail("%s: the name '%s' is taken by catchments[%d]", w, name, names[name]) end
        names[name] = k
        num(c.x_from, w .. ".x_from", x0, x1)
        num(c.x_to, w .. ".x_to", c.x_from + 1e-9, x1)
        an.catchments[k] = { name = name, x_from = c.x_from, x_to = c.x_to }
    end
    local env = opts.envelope or { x0 = x0, x1 = x1, dx = 1 }
    check_keys(env, { "x0", "x1", "dx" }, W .. ".envelope")
    an.envelope = { x0 = num(env.x0 or x0, W .. ".envelope.x0"), x1 = num(env.x1 or x1, W .. ".envelope.x1"),
        dx = num(env.dx or 1, W .. ".envelope.dx", 1e-9) }
    an.envelope.nbins = math.max(1, math.ceil((an.envelope.x1 - an.envelope.x0) / an.envelope.dx - 1e-9))
end

--- The engine's settings, the end rules, rock-rock contact and the shadow-angle apex.
local function engine_options(opts, an)
    an.gravity = opts.gravity and point(opts.gravity, W .. ".gravity") or { 0, -9.81 }
    an.margin = opts.margin and num(opts.margin, W .. ".margin", 1e-9)
    an.rest_speed = num(opts.rest_speed or 0.1, W .. ".rest_speed", 0)
    an.rest_ke = opts.rest_ke and num(opts.rest_ke, W .. ".rest_ke", 0)
    an.rest_time = num(opts.rest_time or 0.5, W .. ".rest_time", 0)
    an.t_max = num(opts.t_max or 120, W .. ".t_max", 1e-9)
    an.impact_min_vn = num(opts.impact_min_vn or 0.5, W .. ".impact_min_vn", 0)
    an.path_every = opts.path_every and math.tointeger(num(opts.path_every, W .. ".path_every", 1)) or 10
    an.clearance = num(opts.clearance or 1e-3, W .. ".clearance", 0)
    if opts.timestep ~= nil and type(opts.timestep) ~= "table" then fail("%s.timestep must be a table", W) end
    an.timestep = opts.timestep -- nil: ROCK_TIMESTEP for independent rocks, the engine's for a mass release
    local rc = opts.rock_contact or {}
    check_keys(rc, MATERIAL_KEYS, W .. ".rock_contact")
    an.rock_contact = { model = rc.model or "linear",
        props = rc.props or { kn = 1e9, ks = 5e8, fric = 0.5, dp_nratio = 0.3 } }
    check_model(an.rock_contact.model, an.rock_contact.props, W .. ".rock_contact")
    -- Shadow angles (rockfall.stats): the apex, or the steepness from which a downslope
    -- segment counts as the cliff whose toe is the apex.
    if opts.shadow_apex ~= nil then an.shadow_apex = point(opts.shadow_apex, W .. ".shadow_apex") end
    if opts.shadow_steep ~= nil then
        an.shadow_steep = num(opts.shadow_steep, W .. ".shadow_steep", 1e-9, 90)
    end
    if opts.shadow_talus ~= nil then
        an.shadow_talus = num(opts.shadow_talus, W .. ".shadow_talus", 1e-9, 90)
    end
end

--- Builds and checks an analysis. See docs/rockfall.md for every option and its default.
local function analysis(opts)
    check_keys(opts, ANALYSIS_KEYS, W)
    local an = {}
    ground_options(opts, an)
    seeder_options(opts, an)
    line_options(opts, an)
    engine_options(opts, an)
    an.y_min = math.huge
    for _, p in ipairs(an.points) do an.y_min = math.min(an.y_min, p[2]) end
    an.is_analysis = true
    return an
end

--- The analysis description the statistics module (rockfall_stats) receives.
local function describe(an)
    local cols, bars = {}, {}
    for k, c in ipairs(an.collectors) do cols[k] = { name = c.name, x = c.x } end
    for k, b in ipairs(an.barriers) do
        bars[k] = { name = b.name, x = b.x, energy = b.energy, height = b.height }
    end
    -- Each material's nominal Rn: a disk's, head on, for a linear dashpot with its dp_nratio
    -- (the closed form dp_nratio inverts; dp_mode full only).
    local mats = {}
    for name, mat in pairs(an.materials) do
        local props, model = mat.props or {}, mat.model or "linear"
        local beta, mode = props.dp_nratio, props.dp_mode
        local rn
        if (model == "linear" or model == "rrlinear") and type(beta) == "number"
            and (mode == nil or mode == 0 or mode == "full") then
            rn = beta < 1 and math.exp(-math.pi * beta / math.sqrt(1 - beta * beta)) or 0
        end
        mats[name] = { model = model, rn = rn }
    end
    local catch = {}
    for k, c in ipairs(an.catchments or {}) do catch[k] = { name = c.name, x_from = c.x_from, x_to = c.x_to } end
    local sx, sy, sw = 0, 0, 0
    for _, s in ipairs(an.seeders) do
        sx = sx + s.weight * 0.5 * (s.from[1] + s.to[1])
        sy = sy + s.weight * 0.5 * (s.from[2] + s.to[2])
        sw = sw + s.weight
    end
    local prof = {}
    for k, p in ipairs(an.points) do prof[k] = { p[1], p[2] } end
    return {
        profile = prof, envelope = { x0 = an.envelope.x0, x1 = an.envelope.x1, dx = an.envelope.dx },
        collectors = cols, barriers = bars, release = { x = sx / sw, y = sy / sw }, seed = an.seed, n = an.n,
        shadow_apex = an.shadow_apex and { an.shadow_apex[1], an.shadow_apex[2] } or nil,
        shadow_steep = an.shadow_steep, shadow_talus = an.shadow_talus,
        toe = an.toe, catchments = catch, materials = mats,
    }
end

--- Damping ratio of a linear dashpot that gives normal restitution e for a contact that lasts
--- until the overlap is back to zero: e = exp(-pi beta / sqrt(1 - beta^2)), inverted.
local function dp_nratio(e)
    if type(e) ~= "number" or e <= 0 or e > 1 then
        require("talus_util.errors").raise("rockfall.dp_nratio: e must be in (0, 1] (got %s)", tostring(e))
    end
    local l = math.log(e)
    return -l / math.sqrt(math.pi * math.pi + l * l)
end

return { check_model = check_model, analysis = analysis, describe = describe, dp_nratio = dp_nratio,
    ROCK_TIMESTEP = ROCK_TIMESTEP }
