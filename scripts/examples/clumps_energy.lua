-- SPDX-License-Identifier: MIT
--
-- clumps_energy.lua: An's (2006) chapter 3 scene, rebuilt. Two rigid rocks (clumps of three
-- pebbles) roll and bounce down a segmented slope; energy is traced per rock and for the whole
-- model (An 2006, chapter 3; docs/physics/energy.md "Energy per group").
--
--   talus run scripts/examples/clumps_energy.lua [outdir] [--time=8]
--   python3 scripts/plot_history.py OUT/clumps_energy.csv -o OUT/clumps_energy_rock1.png \
--       --columns body@rock1,kinetic@rock1,strain@rock1,slip@rock1
--
-- Writes <outdir>/clumps_energy.csv: time and, per rock and in total, body work, kinetic,
-- strain and friction (slip) energy, plus the items that close each rock's books: dashpot work,
-- the work exchanged with the other bodies (`exchanged`), and the balance error. Prints a
-- summary that checks what An (2006) checked: the rocks' items sum to the totals.
--
-- Scene (An's 2006 "random mountain"): a chain of ten segments with
-- varying run and drop, then a flat landing zone. Rock 1 is An's (2006) rock, three equal balls
-- in contact in a triangle (R = 0.15 m); rock 2 three overlapping balls in a row (R = 0.12 m,
-- spacing 0.15 m); density 2600 kg/m^3 (2D disks, unit thickness). Contacts: linear,
-- kn = 1e8 N/m, ks = 3e7 N/m, fric = 0.5, normal dashpot ratio 0.2 (restitution 0.53). The two
-- rocks can hit each other: their exchanged items are then equal and opposite.

local outdir, duration = "out", 8.0
for _, a in ipairs(arg) do
    local key, value = a:match("^%-%-([%w_]+)=(.+)$")
    if key == "time" then duration = assert(tonumber(value), "--time needs a number")
    elseif a:match("^%-%-") then error("unknown option " .. a .. " (--time=)")
    else outdir = a end
end
talus.mkdir(outdir)

local profile = {
    {0, 10}, {2.0, 8.6}, {3.5, 8.3}, {5.0, 6.9}, {7.0, 6.2}, {8.5, 4.8},
    {10.5, 4.3}, {12.0, 3.0}, {14.5, 2.2}, {16.0, 1.0}, {19.0, 0.6}, {40.0, 0.0},
}

local m = talus.model{ gravity = {0, -9.81}, mass = "disk" }
m:contact_model("linear", { kn = 1e8, ks = 3e7, fric = 0.5, dp_nratio = 0.2, dp_mode = "full" })
m:wall{ points = profile, group = "slope" }

local R1, R2 = 0.15, 0.12
local h = R1 * math.sqrt(3) / 3  -- centroid of an equilateral triangle of side 2 R1
local rock1 = m:clump{
    pebbles = { {-R1, -h, R1}, {R1, -h, R1}, {0, 2 * h, R1} },
    pos = {0.6, 10.0 + 0.45}, angle = 0.2, density = 2600, vel = {2, 0}, group = "rock1",
}
local rock2 = m:clump{
    pebbles = { {-0.15, 0, R2}, {0, 0, R2}, {0.15, 0, R2} },
    pos = {4.2, 8.3}, angle = -0.7, density = 2600, vel = {1.5, -1}, group = "rock2",
}
m:broadphase{ margin = 0.1 }
m:energy{ on = true }

local items = { "body", "kinetic", "strain", "slip", "dashpot", "exchanged", "balance_error" }
local columns = { "time" }
for _, g in ipairs({ "rock1", "rock2" }) do
    for _, item in ipairs(items) do columns[#columns + 1] = item .. "@" .. g end
end
for _, item in ipairs({ "body", "kinetic", "strain", "slip", "dashpot", "balance_error" }) do
    columns[#columns + 1] = item
end
local csv = outdir .. "/clumps_energy.csv"
m:history{ file = csv, every = 20, columns = columns }

m:solve{ time = duration }
m:close_history()

-- ------------------------------------------------------------------ summary
local total = m:energies()
local e1, e2, es = m:energies("rock1"), m:energies("rock2"), m:energies("slope")
print(string.format("t = %.3f s, %d steps", m:time(), m:step()))
for _, r in ipairs({ { "rock1", rock1, e1 }, { "rock2", rock2, e2 } }) do
    local name, c, e = r[1], r[2], r[3]
    print(string.format("%s: at x = %.2f m, mass %.1f kg, body %.1f J, kinetic %.2f J, slip %.1f J, "
        .. "dashpot %.1f J, exchanged %.3g J, balance error %.3g J (%.2g of its input)",
        name, c.pos[1], c.mass, e.body, e.kinetic, e.slip, e.dashpot, e.exchanged, e.balance_error,
        e.balance_error / e.input))
end
-- An's (2006) check: the groups partition the model, so their items sum to the totals.
local worst = 0
for _, item in ipairs({ "body", "kinetic", "strain", "slip", "dashpot", "balance_error" }) do
    local sum = e1[item] + e2[item] + es[item]
    worst = math.max(worst, math.abs(sum - total[item]))
end
print(string.format("sum over rock1, rock2, slope - total: largest difference %.3g J (input %.4g J)",
    worst, total.input))
print(string.format("exchanged: rock1 %.4g + rock2 %.4g + slope %.4g = %.3g J",
    e1.exchanged, e2.exchanged, es.exchanged, e1.exchanged + e2.exchanged + es.exchanged))
print(string.format("whole model: balance error %.3g J = %.2g of the input", total.balance_error,
    total.balance_error / total.input))
-- The example checks itself (it runs in the test suite): group sums are the totals to round-off
-- (1e-12 of the input), the exchanged items cancel, and every group's books close to the
-- integration's own accuracy (1% of the group's input; measured 2e-4 and 3e-6 here).
assert(worst <= 1e-12 * total.input, "group sums differ from the totals")
assert(math.abs(e1.exchanged + e2.exchanged + es.exchanged) <= 1e-12 * total.input,
    "exchanged items do not cancel")
for _, e in ipairs({ e1, e2, total }) do
    assert(math.abs(e.balance_error) <= 0.01 * e.input, "a group's balance does not close")
end
print("wrote " .. csv)
