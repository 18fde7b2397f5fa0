-- SPDX-License-Identifier: MIT
-- The crack list of M.compress and M.brazilian (PFC's crack.fis habit; docs/material.md
-- "Cracks"): every bond that broke during the test, where (the contact point, on the line of
-- the two balls' centres), when (step, time, and the axial strain then), how (tension/shear),
-- the two balls, the bond's size (a contact bond: the smaller ball's radius) and orientation
-- (across the bond); the history counts them against the axial strain beside the volumetric
-- strain, and both go to CSV files.
local T = require("testlib")
local M = require("material")
local out = assert(arg[1], "usage: material_cracks.lua OUTDIR")
talus.mkdir(out)

local pk = M.genesis{ width = 0.01, height = 0.02, rmin = 0.5e-3, rmax = 0.83e-3, porosity = 0.16,
                      kn = 6.4e10, ks = 9.6e9, seed = 3 }
local mat = { model = "cbond", kn = 6.4e10, ks = 9.6e9, fric = 0.5, density = 2600,
              bond = { cb_tenf = 4.6e4, cb_shearf = 6e4 } }
local sp = M.specimen(pk, mat)
-- a recorder of our own beside the test's: the balls as they are at each break
local seen = {}
sp.model:on_event("bond_break", function(ev)
    local c = ev.contact
    local b1, b2 = c.ball1, c.ball2
    seen[#seen + 1] = { pos = ev.pos, mode = ev.mode, step = sp.model:step(), time = sp.model:time(),
                        p1 = b1.pos, p2 = b2.pos, r1 = b1.radius, r2 = b2.radius, id1 = b1.id, id2 = b2.id,
                        top = sp.top.wall.points[1][2], bottom = sp.bottom.wall.points[1][2] }
end)
local s0 = sp.model:step()
local h0 = sp.top.wall.points[1][2] - sp.bottom.wall.points[1][2]
local csv = out .. "/cracks_ucs.csv"
local r = M.compress(sp, { post_peak = 0.3, csv = csv, strain_per_crossing = 2e-5 })

-- 1. one crack per break, in the order they happened
local n = r.breaks.tension + r.breaks.shear
T.check(n >= 5, "bonds broke (" .. n .. ")")
T.check(#r.cracks == n and #seen == n, string.format("%d cracks, %d breaks, %d events", #r.cracks, n, #seen))
local count = { tension = 0, shear = 0 }
for i, c in ipairs(r.cracks) do
    local s = seen[i]
    count[c.mode] = (count[c.mode] or 0) + 1
    T.check(c.mode == s.mode and c.x == s.pos[1] and c.y == s.pos[2] and c.time == s.time and c.step == s.step - s0,
        "crack " .. i .. ": the event's point, time, step (since the test began) and mode")
    T.check(c.ball1 == s.id1 and c.ball2 == s.id2, "crack " .. i .. ": its two balls")
    -- a contact bond's size: the smaller ball's radius (its half width)
    T.check(c.radius == math.min(s.r1, s.r2) and c.width == 2 * c.radius, "crack " .. i .. ": bond radius")
    -- orientation: the unit normal along the line of centres, the crack across it
    local dx, dy = s.p2[1] - s.p1[1], s.p2[2] - s.p1[2]
    local d = math.sqrt(dx * dx + dy * dy)
    T.near(c.nx, dx / d, 1e-12, "crack " .. i .. ": normal x")
    T.near(c.ny, dy / d, 1e-12, "crack " .. i .. ": normal y")
    local a = math.rad(c.angle)
    T.check(c.angle >= 0 and c.angle < 180, "angle in [0, 180)")
    T.near(math.cos(a) * c.nx + math.sin(a) * c.ny, 0, 1e-12, "crack " .. i .. ": across the bond")
    -- at the contact: on the line of centres, between them (within the overlap or gap)
    local ux, uy = c.x - s.p1[1], c.y - s.p1[2]
    T.near((ux * dy - uy * dx) / d, 0, 1e-9 * s.r1, "crack " .. i .. ": on the line of centres")
    local along = (ux * dx + uy * dy) / d
    T.check(along > 0 and along < d, "crack " .. i .. ": between the centres")
    -- the axial strain then, from the platens at that step
    T.near(c.strain_axial, (h0 - (s.top - s.bottom)) / h0, 1e-12, "crack " .. i .. ": axial strain")
end
T.check(count.tension == r.breaks.tension and count.shear == r.breaks.shear, "modes as counted")

-- 2. the history counts them against the strain, with the volumetric strain beside
local k = 1
for _, row in ipairs(r.rows) do
    local c = 0
    for _, cr in ipairs(r.cracks) do if cr.step <= row.step then c = c + 1 end end
    if row.cracks ~= c then k = 0 end
    T.check(row.strain_volumetric == row.strain_axial - row.strain_lateral, "volumetric = axial - lateral")
end
T.check(k == 1, "every history row counts the cracks up to its step")
T.check(r.rows[#r.rows].cracks == n, "the last row has them all")
-- the crack damage threshold: the largest volumetric strain up to the peak
local cd = r.crack_damage
T.check(cd and cd.row <= r.ipeak and cd.stress <= r.ucs, "crack damage threshold up to the peak")
for i = 1, r.ipeak do
    T.check(r.rows[i].strain_volumetric <= cd.strain_volumetric, "no larger volumetric strain before the peak")
end

-- 3. the files: the history has the new columns, the crack list its own CSV next to it
local function read_csv(file)
    local f = assert(io.open(file))
    local header = f:read("l")
    local rows = {}
    for line in f:lines() do rows[#rows + 1] = line end
    f:close()
    local cols = {}
    for name in header:gmatch("[^,]+") do cols[#cols + 1] = name end
    return cols, rows
end
local hcols = read_csv(csv)
T.check(table.concat(hcols, ",") == table.concat(M.columns, ","), "history columns: M.columns")
T.check(hcols[#hcols - 4] == "cracks" and hcols[#hcols - 3] == "strain_volumetric"
    and hcols[#hcols - 2] == "platen_difference" and hcols[#hcols - 1] == "ratio" and hcols[#hcols] == "held",
    "history columns end with cracks, strain_volumetric, platen_difference, ratio, held")
local ccols, crows = read_csv(out .. "/cracks_ucs_cracks.csv")
T.check(table.concat(ccols, ",") == table.concat(M.crack_columns, ","), "crack CSV columns")
T.check(#crows == n, "one CSV row per crack")
local first = {}
for cell in (crows[1] .. ","):gmatch("([^,]*),") do first[#first + 1] = cell end
T.check(tonumber(first[4]) == tonumber(string.format("%.12g", r.cracks[1].x)) and first[6] == r.cracks[1].mode
    and tonumber(first[9]) == tonumber(string.format("%.12g", r.cracks[1].width)), "first CSV row")

-- 4. the Brazilian test keeps the same list (and its breaks_at from it)
local disk = M.genesis_disk{ diameter = 0.012, rmin = 0.5e-3, rmax = 0.83e-3, kn = 6.4e10, ks = 9.6e9, seed = 2 }
local dsp = M.specimen(disk, { model = "cbond", kn = 6.4e10, ks = 9.6e9, fric = 0.5, density = 2600,
                               platen = { fric = 0.5 }, bond = { cb_tenf = 4.6e4, cb_shearf = 4.6e5 } },
                       { balls = M.disk(disk) })
local b = M.brazilian(dsp, { post_peak = 0.5, strain_per_crossing = 2e-5, cracks_csv = out .. "/cracks_brazilian.csv" })
T.check(#b.cracks == b.breaks.tension + b.breaks.shear and #b.cracks > 0, "Brazilian: a crack per break")
for i, c in ipairs(b.cracks) do
    T.check(b.breaks_at[i][1] == c.x and b.breaks_at[i][2] == c.y and b.breaks_at[i][3] == c.time, "breaks_at")
end
local _, brows = read_csv(out .. "/cracks_brazilian.csv")
T.check(#brows == #b.cracks, "Brazilian crack CSV")
print(string.format("material_cracks: %d cracks in the UCS test (%d tension, %d shear), crack damage at %.3g of peak; %d in the Brazilian",
    n, count.tension, count.shear, cd.stress / r.ucs, #b.cracks))
T.done("material_cracks")
