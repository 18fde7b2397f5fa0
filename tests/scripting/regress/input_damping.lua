-- m:damping{local = 0.7} as the docs wrote it is a Lua syntax error (`local`
-- is a keyword). The option is `damp` now (PFC's name); ['local'] is still accepted.
local T = require("testlib")
local m = talus.model{}
T.check(load("local m = ...; m:damping{local = 0.7}") == nil, "`local =` is a syntax error")
local d = m:damping{ damp = 0.7 }
T.near(d.damp, 0.7, 0, "damp")
T.near(d["local"], 0.7, 0, "the old name reads the same value")
d = m:damping{ ['local'] = 0.3 }
T.near(d.damp, 0.3, 0, "the old name still sets it")
T.fails(function() m:damping{ damp = 0.1, ['local'] = 0.2 } end, { "not both" }, "both names")
T.fails(function() m:damping{ damp = 1 } end, { "damping: 'damp' must be in [0, 1)" }, "range")
T.fails(function() m:damping{ damp = 0 / 0 } end, { "got nan" }, "NaN")
T.done("input_damping")
