-- SPDX-License-Identifier: MIT
-- m:placement_warning: a routine that overlaps bodies on purpose switches the engine's warning
-- about contacts that start overlapping off, says so itself, and the energy is booked all the
-- same. The genesis of a bonded specimen grows its balls into each other in eight stages: it
-- printed eight such warnings (a 1 200-ball packing: 119 to 2 013 contacts each) and now one line
-- of its own (ctest fails this test if "started overlapping" reaches the output).
local T = require("testlib")
local M = require("material")

-- The switch. Two balls of R = 10 mm created 2 mm into each other: kn = 1e6 N/m holds
-- kn u^2 / 2 = 2 J, all of it placed (the balls were at rest). (Two cycles: m:energies() is
-- the snapshot at the last whole step, one step behind.)
local m = talus.model{}
m:contact_model("linear", { kn = 1e6 })
local warnings = {}
m:on_warning(function(text) warnings[#warnings + 1] = text end)
m:energy{ on = true }
T.check(m:placement_warning() == true, "on by default")
local function pair(x)
    m:ball{ pos = { x, 0 }, radius = 0.01, density = 2600 }
    m:ball{ pos = { x + 0.018, 0 }, radius = 0.01, density = 2600 }
end
pair(0)
T.check(m:placement_warning(false) == true, "returns the setting before the call")
T.check(m:placement_warning() == false, "reads the setting")
m:cycle(2)
T.check(#warnings == 0, "not reported while off: " .. tostring(warnings[1]))
T.near(m:energies().placement, 2.0, 1e-12, "booked while off")
T.check(m:placement_warning(true) == false, "returns the setting before the call")
pair(1)
m:cycle(2)
T.check(#warnings == 1 and warnings[1]:find("1 contact(s) started overlapping", 1, true) ~= nil,
    "reported when on: " .. tostring(warnings[1]))
T.near(m:energies().placement, 4.0, 1e-12, "booked when on")
local l = T.line(); T.fails(function() m:placement_warning("no") end,
    { "placement_warning.lua:" .. l .. ":", "placement_warning: expected true or false (got string)" },
    "a non-boolean")

-- The genesis says it once, in its own words (verbose), and the engine says nothing: every
-- model it makes is watched (talus.model wrapped), and its output is read (print wrapped).
local make, print0 = talus.model, print
local engine, said = {}, {}
talus.model = function(...)
    local mm = make(...)
    mm:on_warning(function(text) engine[#engine + 1] = text end)
    return mm
end
print = function(...) said[#said + 1] = table.concat({ ... }, "\t") end
local ok, err = pcall(M.genesis, { width = 0.01, height = 0.02, rmin = 0.5e-3, rmax = 0.83e-3,
    porosity = 0.16, kn = 6.4e10, ks = 9.6e9, stress = 1e5, seed = 3, verbose = true })
talus.model, print = make, print0
T.check(ok, tostring(err))
T.check(#engine == 0, "the engine warned during the genesis: " .. tostring(engine[1]))
local own = 0
for _, line in ipairs(said) do
    if line:find("into each other on purpose", 1, true) then own = own + 1 end
end
T.check(own == 1, "the genesis says it once (" .. own .. " times)")
T.check(#said > 5, "the genesis was verbose")
print(string.format("placement_warning: %d checks passed", T.checks))
