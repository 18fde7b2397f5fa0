-- SPDX-License-Identifier: MIT
-- Every error is a Lua error that names the script line of the call and says what was wrong.
local T = require("testlib")
local s = T.script()
local function at(line) return s .. ":" .. line .. ":" end

local m = talus.model{ gravity = {0, -9.81} }
local l

l = T.line(); T.fails(function() m:ball{ pos = {0, 1}, radius = -0.1, density = 2600 } end,
    { at(l) .. " ball: radius must be > 0 (got -0.1)" }, "core InputError with the line")
l = T.line(); T.fails(function() m:ball{ pos = {0, 1}, radius = 0.1 } end,
    { at(l) .. " ball: 'density' or 'mass' is required" }, "missing option")
l = T.line(); T.fails(function() m:ball{ pos = {0, 1}, radius = 0.1, density = 1, colour = 1 } end,
    { at(l) .. " ball: unknown option 'colour' (known: angle, density, fix" }, "unknown option")
l = T.line(); T.fails(function() m:ball{ pos = "up", radius = 0.1, density = 1 } end,
    { at(l) .. " ball: 'pos' must be a vector {x, y} (got string)" }, "type error")
l = T.line(); T.fails(function() m:contact_model("linear", { knn = 1e8 }) end,
    { at(l), "contact_model: unknown property 'knn' for model 'linear'; did you mean 'kn'? (known: kn, ks, fric, dp_nratio" },
    "unknown property lists the known ones")
l = T.line(); T.fails(function() m:contact_model("linear", { dp_nratio = 2 }) end,
    { at(l), "dp_nratio" }, "property range")
l = T.line(); T.fails(function() m:contact_model("linear", { dp_mode = "soft" }) end,
    { at(l), "'dp_mode' must be one of \"full\", \"no_tension\"" }, "enum property by name")
l = T.line(); T.fails(function() m:contact_model("no_such_model", {}) end,
    { at(l), "unknown contact model 'no_such_model'" }, "unknown model")
l = T.line(); T.fails(function() talus.load_plugin("/nonexistent/libtalus_x.so") end,
    { at(l), "load_plugin: no such file '/nonexistent/libtalus_x.so'" }, "missing plugin")
l = T.line(); T.fails(function() m:timestep{ safety = 0 } end,
    { at(l), "timestep: 'safety' must be > 0 (got 0)" }, "timestep validation")
l = T.line(); T.fails(function() m:guard{ energy = "loud" } end,
    { at(l), "guard: 'energy' must be one of \"warn\", \"error\", \"off\" (got \"loud\")" }, "enum")
T.check(m:guard{ stiffness = "error" }.stiffness == "error", "guard{stiffness} is settable")
T.check(m:guard{ balance = "error", balance_tolerance = 0.02 }.balance_tolerance == 0.02, "guard{balance} is settable")
l = T.line(); T.fails(function() m:guard{ balance_tolerance = 0 / 0 } end,
    { at(l), "guard: 'balance_tolerance' must be a number (got nan)" }, "NaN balance tolerance")
l = T.line(); T.fails(function() m:guard{ balance_every = 0 } end,
    { at(l), "guard: 'balance_every' must be >= 1 step (got 0)" }, "empty balance window")
l = T.line(); T.fails(function() m:guard{ stifness = "off" } end,
    { at(l), "guard: unknown option 'stifness'; did you mean 'stiffness'? (known: balance, balance_every, balance_tolerance, energy, energy_tolerance, memory_limit, min_steps, resolution, severe, severe_created, severe_min_steps, stiffness)" },
    "misspelt guard option")
l = T.line(); T.fails(function() m.cycle(10) end,
    { at(l), "cycle: call it as a method, m:cycle(...)" }, "dot instead of colon")
l = T.line(); T.fails(function() m:cycle(2.5) end,
    { at(l), "cycle: number of steps must be an integer (got 2.5)" }, "integer")
l = T.line(); T.fails(function() m:cylce(10) end,
    { at(l), "model: unknown method or field 'cylce'; did you mean 'cycle'? (known: ball, ball_by_id, ball_count" }, "misspelt method")
l = T.line(); T.fails(function() m:energies() end,
    { at(l), "energies: energy tracing is off" }, "energies off")
l = T.line(); T.fails(function() m:solve{ ratoi = 1e-5 } end,
    { at(l), "solve: unknown option 'ratoi'; did you mean 'ratio'? (known: " }, "misspelt solve option")
-- through pcall directly (no Lua frame in between): the nearest Lua line is used
l = T.line(); local ok, err = pcall(m.cycle, m, -1)
T.check(not ok and err:find(at(l) .. " cycle: number of steps must be >= 0 (got -1)", 1, true),
    "error through pcall names the calling line: " .. tostring(err))

-- a numerical error during cycle: an impact resolved in too few steps, guard set to "error"
local n = talus.model{ gravity = {0, -9.81} }
n:contact_model("linear", { kn = 1e8 })
n:wall{ points = { {-1, 0}, {1, 0} } }
n:ball{ pos = {0, 0.11}, radius = 0.1, density = 2600, vel = {0, -2} }
n:timestep{ fixed = 1e-3 }
n:guard{ resolution = "error", min_steps = 10 }
l = T.line(); T.fails(function() n:cycle(200) end,
    { at(l), "impact under-resolved" }, "NumericalError from cycle")

-- an error inside a callback keeps the callback's own line and stops the run
local c = talus.model{}
c:ball{ pos = {0, 0}, radius = 0.1, density = 1 }
local cb_line = T.line() + 1
c:on_cycle(function(model, step) if step == 3 then error("stop here") end end)
T.fails(function() c:cycle(10) end, { at(cb_line) .. " stop here" }, "callback error")
T.check(c:step() == 3, "the run stopped at the failing step")

-- a callback that runs the model again is refused with its own line (before: the hook ran the
-- inner cycle, whose hook ran another, until "C stack overflow" with no position)
local r = talus.model{}
r:ball{ pos = {0, 0}, radius = 0.1, density = 1 }
local re_line = T.line() + 1
r:on_cycle(function() r:cycle(1) end, 1)
T.fails(function() r:cycle(10) end, { at(re_line) .. " cycle: the model is already running",
    "at step 1" }, "cycle inside on_cycle")
T.check(r:step() == 1, "the run stopped at the step whose callback re-entered")
local r2 = talus.model{}
r2:ball{ pos = {0, 0}, radius = 0.1, density = 1 }
local re2_line = T.line() + 1
T.fails(function() r2:solve{ steps = 5, ["until"] = function(mm) mm:solve{ steps = 1 } end } end,
    { at(re2_line) .. " solve: the model is already running" }, "solve inside solve's until")
r2:cycle(2)  -- the lock is released after a refused run
T.check(r2:step() == 3, "the model runs again after the refusal")

-- warnings go to on_warning when set
local w = talus.model{}
local warnings = {}
w:on_warning(function(text) warnings[#warnings + 1] = text end)
w:ball{ pos = {0, 0}, radius = 0.1, density = 1 }
w:cycle(1)
T.check(#warnings == 1 and warnings[1]:find("no contact model is set", 1, true), "on_warning")
T.done("errors")
