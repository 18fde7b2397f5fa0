-- SPDX-License-Identifier: MIT
-- The rockfall module's hooks: on_model(m, info) is called with each rock's model once it is
-- built and before its first step, so that m:vtk, m:picture or m:history can be attached (an
-- animation of a mass release for a client); on_end(m, record) when the run is over. For
-- run_rock, mass_release and monte_carlo.
local T = require("testlib")
local rockfall = require("rockfall")
local out = (arg and arg[1] or ".") .. "/rockfall_hooks"
os.execute("rm -rf '" .. out .. "'")
talus.mkdir(out)

local an = rockfall.analysis{
    profile = { { 0, 5 }, { 5, 0 }, { 20, 0 } },
    materials = { slope = { model = "linear", props = { kn = 1e7, ks = 5e6, fric = 0.5,
        dp_nratio = 0.3 } } },
    seeders = { { kind = "line", from = { 0.3, 5.6 }, to = { 1.5, 5.6 },
        rock = { shape = "ball", radius = 0.2 } } },
    t_max = 0.3, seed = 5,
}

local function lines(file)
    local n = 0
    for _ in io.lines(file) do n = n + 1 end
    return n
end

-- One rock: a history of its height every 20 steps, and a ParaView series.
local seen, ended = nil, nil
local rec = rockfall.run_rock(an, 1, {
    on_model = function(m, info)
        T.check(m:step() == 0, "on_model comes before the first step")
        seen = info
        m:history{ file = out .. "/rock1.csv", every = 20,
            columns = { "time", { "y", function() return info.body.pos[2] end } } }
        m:vtk{ dir = out .. "/vtk1", every = 200 }
    end,
    on_end = function(m, r)
        ended = { steps = m:step(), rec = r }
    end,
})
T.check(seen and seen.rock == 1 and seen.seed == rockfall.rock_seed(5, 1) and seen.body,
    "on_model gets the rock's index, seed and body")
T.check(ended and ended.rec == rec and ended.steps == rec.steps, "on_end gets the model and the record")
T.check(lines(out .. "/rock1.csv") == 1 + 1 + rec.steps // 20, "one history row every 20 steps")
local pvd = io.open(out .. "/vtk1/talus.pvd")
T.check(pvd ~= nil, "the ParaView series of the rock")
if pvd then
    local text = pvd:read("a")
    pvd:close()
    local frames = select(2, text:gsub("<DataSet ", ""))
    T.check(frames == 1 + rec.steps // 200, "a frame every 200 steps (" .. frames .. ")")
end

-- The hooks may save the model: run_rock's engine tracker (which a save refuses) is made after
-- on_model and cleared before on_end, once its records are read.
local saved = {}
local ok_save, why = pcall(rockfall.run_rock, an, 1, {
    on_model = function(m) m:save(out .. "/rock1_start.talus"); saved.start = m:step() end,
    on_end = function(m) m:save(out .. "/rock1_end.talus"); saved.finish = m:step() end,
})
T.check(ok_save and saved.start == 0 and saved.finish == rec.steps,
    "on_model and on_end may save the model (" .. tostring(why) .. ")")

-- A mass release: one model with every rock, an animation of it.
local mass_info, mass_end
local recs = rockfall.mass_release(an, { n = 3,
    on_model = function(m, info)
        mass_info = info
        m:vtk{ dir = out .. "/vtk_mass", every = 100 }
    end,
    on_end = function(m, r) mass_end = r end })
T.check(mass_info and mass_info.mass_release and mass_info.rocks == 3 and #mass_info.bodies == 3,
    "on_model of a mass release gets the bodies")
T.check(mass_end == recs, "on_end gets the records")
T.check(io.open(out .. "/vtk_mass/talus.pvd") ~= nil, "the mass release's series")

-- Monte Carlo: the hooks run for every rock (in the workers; a file per rock shows it).
local records = rockfall.monte_carlo(an, { n = 3, jobs = 2, quiet = true,
    on_model = function(m, info)
        m:history{ file = string.format("%s/mc_%d.csv", out, info.rock), every = 50, columns = { "time" } }
    end })
for i = 1, 3 do
    T.check(lines(string.format("%s/mc_%d.csv", out, i)) == 2 + records[i].steps // 50,
        "monte_carlo: rock " .. i .. "'s own history")
end

-- A hook must be a function.
T.fails(function() rockfall.run_rock(an, 1, { on_model = "vtk" }) end,
    { "rockfall.run_rock: run_rock options.on_model must be a function (got string)" }, "bad hook")
T.fails(function() rockfall.mass_release(an, { n = 2, on_end = 1 }) end,
    { "mass_release options.on_end must be a function" }, "bad hook")

T.done("rockfall_hooks")
