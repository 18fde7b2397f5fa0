-- SPDX-License-Identifier: MIT
-- "Did you mean" on unknown names: contact models (with the models that can be loaded, not
-- only the loaded ones, and no plugin-path advice for a typo), properties, options, fields and
-- methods; the Lua libraries through talus.did_you_mean.
local T = require("testlib")
local S = T.script()

local function refused(fn, parts, what)
    local line = debug.getinfo(2, "l").currentline
    table.insert(parts, 1, S .. ":" .. line .. ":")
    return T.fails(fn, parts, what)
end

local m = talus.model{}
-- A model name: the close one, and every model on the plugin path (hertz is not loaded yet).
local err = refused(function() m:contact_model("linaer", { kn = 1e8 }) end,
    { "unknown contact model 'linaer'; did you mean 'linear'", "models that can be loaded: ",
        "hertz", "rrlinear" }, "a misspelt model")
T.check(not err:find("TALUS_PLUGIN_PATH", 1, true), "no plugin-path advice for a typo: " .. err)
err = refused(function() m:contact_model("granite_law", {}) end,
    { "unknown contact model 'granite_law' (models that can be loaded: ", "TALUS_PLUGIN_PATH" },
    "a name far from every model keeps the advice")
-- Properties, options, fields, methods.
refused(function() m:contact_model("linear", { dp_nratoi = 0.2 }) end,
    { "contact_model: unknown property 'dp_nratoi' for model 'linear'; did you mean 'dp_nratio'",
        "(known: kn, ks, fric" }, "a property")
refused(function() m:ball{ pos = { 0, 0 }, radius = 0.1, density = 1000, desnity = 1 } end,
    { "ball: unknown option 'desnity'; did you mean 'density'? (known: " }, "an option")
local b = m:ball{ pos = { 0, 0 }, radius = 0.1, density = 1000 }
refused(function() return b.posi end, { "ball: unknown field 'posi'; did you mean 'pos'?" },
    "a field")
refused(function() b.vell = { 1, 0 } end, { "ball: unknown field 'vell'; did you mean 'vel'?" },
    "a field set")
refused(function() m:sovle{ time = 1 } end,
    { "model: unknown method or field 'sovle'; did you mean 'solve'?" }, "a method")
refused(function() m:history{ file = "x.csv", columns = { "time" }, evry = 10 } end,
    { "history: unknown option 'evry'; did you mean 'every'?" }, "history option")
-- Nothing close: no suggestion, the list as before.
err = refused(function() m:ball{ pos = { 0, 0 }, radius = 0.1, density = 1000, colour = 1 } end,
    { "ball: unknown option 'colour' (known: " }, "no close name")

-- The helper the Lua libraries use.
T.check(talus.did_you_mean("linaer", { "hertz", "linear" }) == "; did you mean 'linear'?",
    "talus.did_you_mean")
T.check(talus.did_you_mean("zzz", { "hertz", "linear" }) == "", "nothing close")
local rockfall = require("rockfall")
refused(function() rockfall.analysis{ profile = { { 0, 1 }, { 1, 0 } }, seeders = {}, sead = 1 } end,
    { "rockfall.analysis: unknown option 'sead' in analysis; did you mean 'seed'? (known: " },
    "rockfall option")
local materials = { slope = { model = "linear", props = { knn = 1 } } }
refused(function() rockfall.analysis{ profile = { { 0, 1 }, { 1, 0 } }, materials = materials } end,
    { "unknown property 'knn' for model 'linear'; did you mean 'kn'?" }, "rockfall property")

T.done("did_you_mean")
