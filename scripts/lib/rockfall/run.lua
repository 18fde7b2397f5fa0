-- SPDX-License-Identifier: MIT
-- rockfall/run.lua: one rock run alone on its own slope.
local Draw = require("rockfall.draw")
local Model = require("rockfall.model")
local Tr = require("rockfall.tracking")
local K = require("rockfall.check")
local An = require("rockfall.analysis")
local fail, check_keys, need_analysis, check_hook = K.fail, K.check_keys, K.need_analysis, K.check_hook
local sample = Draw.sample
local new_model, build_slope, place_rock = Model.new_model, Model.build_slope, Model.place_rock
local rock_lines, track_rock = Tr.rock_lines, Tr.track_rock
local ended_at_start, collect_rock = Tr.ended_at_start, Tr.collect_rock

--- Runs rock i of the analysis alone on its own slope; returns its record.
--- opts: trajectory = true records the path every analysis.path_every samples; on_model(m,
--- info) is called once the model is built, before the first step (attach m:vtk, m:picture,
--- m:history there), info = {rock =, seed =, body =}; on_end(m, record) once the rock ended.
local function run_rock(an, i, opts)
    need_analysis(an)
    opts = opts or {}
    check_keys(opts, { "trajectory", "chunk", "on_model", "on_end" }, "run_rock options")
    check_hook(opts, "on_model", "run_rock options")
    check_hook(opts, "on_end", "run_rock options")
    if math.type(i) ~= "integer" or i < 1 then fail("rock index must be an integer >= 1 (got %s)", tostring(i)) end
    local s = sample(an, i)
    if s.breakable then return require("rockfall.breakable").run_rock(an, i, s, opts) end
    -- A margin of the rock's size: free-flight steps grow until the rock would leave its fat box
    -- (the kinematic rule), so a wide box means few steps in flight; a rock has only the slope's
    -- few segments as candidates, so the wider box costs nothing measurable.
    local warnings = {}
    local m = new_model(an, an.margin or math.max(s.rock.r_eq, 1e-3), warnings, An.ROCK_TIMESTEP)
    local wall_material = build_slope(m, an, s.points, s.materials)
    Tr.add_barriers(m, an, s.points)
    local body = place_rock(m, s)
    m:energy{ on = true }
    if opts.on_model then opts.on_model(m, { rock = i, seed = s.seed, body = body }) end
    -- The tracker comes after on_model, so that the hook may save the model (a model with
    -- trackers is not saved); its first sample is the state the first step starts from.
    local lines = rock_lines(an)
    local rt = track_rock(m, an, i, s, body, lines, opts)
    ended_at_start(rt)
    local chunk = opts.chunk or 50
    while not rt.done do m:cycle(chunk) end
    collect_rock(rt, lines, wall_material)
    m:clear_trackers() -- its records are read; on_end may save the model
    local rec = rt.record
    local e = m:energies()
    rec.energy = { input = e.input, kinetic = e.kinetic, body = e.body, slip = e.slip,
        dashpot = e.dashpot, strain = e.strain, barrier = e.barrier, balance_error = e.balance_error }
    rec.steps = m:step()
    if #warnings > 0 then rec.warnings = warnings end
    if opts.on_end then opts.on_end(m, rec) end
    return rec
end

return { run_rock = run_rock }
