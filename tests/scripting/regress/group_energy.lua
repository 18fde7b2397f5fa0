-- SPDX-License-Identifier: MIT
-- Energy per group from Lua (docs/physics/energy.md "Energy per group",
-- docs/lua-api.md): m:energies("rock"), the exchanged item, wall groups, and history columns
-- {"kinetic", "rock"} / "kinetic@rock".
local T = require("testlib")

-- A ball ("bullet") hits a row of three balls ("row") resting on a floor that moves ("belt").
local m = talus.model{ gravity = {0, -9.81} }
m:contact_model("linear", { kn = 1e7, ks = 5e6, fric = 0.3, dp_nratio = 0.1 })
local floor = m:wall{ points = {{-2, 0}, {2, 0}}, vel = {0.05, 0} }
floor:add_group("belt")
T.check(floor.groups[1] == "belt", "wall groups read back")
for i = 0, 2 do m:ball{ pos = {i * 0.1, 0.05}, radius = 0.05, density = 2600, group = "row" } end
local b = m:ball{ pos = {-0.4, 0.05}, radius = 0.05, density = 2600, vel = {3, 0},
                  group = "bullet" }

T.fails(function() m:energies("row") end, {"tracing is off"}, "group energies need tracing")
m:energy{ on = true }
T.fails(function() m:energies("rock") end, {"unknown group 'rock'", "belt", "row", "bullet"},
        "unknown group lists the groups")
local path = os.tmpname()
local h = m:history{ file = path, every = 10,
                     columns = {"time", {"kinetic", "bullet"}, "exchanged@row",
                                {"bal", {"balance_error", "row"}}} }
T.fails(function() m:history{ file = path .. "x", columns = {"kinetic@rock"} } end,
        {"unknown group 'rock'"}, "history column with an unknown group")
m:cycle(3000)
h:close()

-- Over the partition {belt, row, bullet} every item sums to the whole model's (round-off:
-- 1e-12 of the energy put in), and the exchanged items sum to 0.
local e = m:energies()
T.check(e.exchanged == 0, "whole-model exchanged is 0")
for _, item in ipairs({"kinetic", "strain", "body", "boundary", "slip", "dashpot", "damping",
                       "initial_kinetic", "placement", "exchanged", "balance_error"}) do
    local sum = 0
    for _, g in ipairs({"belt", "row", "bullet"}) do sum = sum + m:energies(g)[item] end
    T.near(sum, e[item], 1e-12 * e.input, "partition sum of " .. item)
end
local eb, er = m:energies("bullet"), m:energies("row")
T.check(eb.exchanged < -0.1 * eb.initial_kinetic, "the bullet gave work to the others")
-- Each group's balance closes to the step's second-order error (~1e-3 of the energy in at the
-- default step, docs/physics/energy.md); bound 3e-3 of the whole model's input.
for _, g in ipairs({"belt", "row", "bullet"}) do
    T.check(math.abs(m:energies(g).balance_error) < 3e-3 * e.input,
            g .. " balance " .. m:energies(g).balance_error)
end

-- The CSV: header names and the row values of the last row.
local f = assert(io.open(path))
local header = f:read("l")
T.check(header == "time,kinetic@bullet,exchanged@row,bal", "header: " .. header)
local last
for line in f:lines() do last = line end
f:close()
os.remove(path)
local cells = {}
for c in last:gmatch("[^,]+") do cells[#cells + 1] = tonumber(c) end
T.near(cells[2], eb.kinetic, 1e-9 * e.input, "history kinetic@bullet")
T.near(cells[3], er.exchanged, 1e-9 * e.input, "history exchanged@row")
T.near(cells[4], er.balance_error, 1e-9 * e.input, "history balance_error of row")
T.check(b.groups[1] == "bullet", "ball groups")

T.done("group_energy")
