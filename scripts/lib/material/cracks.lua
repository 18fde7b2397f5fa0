-- SPDX-License-Identifier: MIT
-- material/cracks.lua: the crack list of a laboratory test, as PFC users keep it with crack.fis:
-- each broken bond with where, when and how it broke, its two balls, the bond's size and
-- orientation, and the axial strain at that moment (the test's history counts the cracks
-- against the same strain).
local U = require("material.util")

local Cr = {}

--- The columns of the crack CSV (names with units for scripts/plot_history.py).
Cr.columns = { "step", "time", "strain_axial", "x", "y", "mode", "ball1", "ball2", "width [m]", "angle [deg]",
    "nx", "ny", "sigma [Pa]", "tau [Pa]" }

--- The crack of a bond_break event `ev` (docs/lua-api.md, "Cracks"): step = steps since `s0`
--- (as the test's history counts them), time, strain_axial = `strain` (the test's axial strain
--- then), x, y = the contact point, mode = "tension" | "shear", ball1, ball2 = the ball ids,
--- radius = the bond's half width (ev.radius) and width = 2 radius, nx, ny = the bond's unit
--- normal (ball 1 toward ball 2), angle = the crack's direction, across the bond (the normal
--- turned by 90 degrees), in degrees from the x axis in [0, 180); sigma, tau = the bond's
--- stresses at failure when its model reports them (pbond).
function Cr.record(ev, s0, strain)
    local n = ev.normal or { 0, 0 }
    local angle = math.deg(math.atan(n[1], -n[2])) % 180
    return {
        step = ev.step and ev.step - s0, time = ev.time, strain_axial = strain, x = ev.pos[1], y = ev.pos[2],
        mode = ev.mode, ball1 = ev.ball1 and ev.ball1.id, ball2 = ev.ball2 and ev.ball2.id,
        radius = ev.radius, width = ev.radius and 2 * ev.radius, angle = angle, nx = n[1], ny = n[2],
        sigma = ev.sigma, tau = ev.tau,
    }
end

--- Writes a crack list as CSV (the columns above, 12 significant digits).
function Cr.write_csv(file, cracks)
    local rows = {}
    for i, c in ipairs(cracks) do
        rows[i] = setmetatable({ ["width [m]"] = c.width, ["angle [deg]"] = c.angle, ["sigma [Pa]"] = c.sigma,
                                 ["tau [Pa]"] = c.tau }, { __index = c })
    end
    U.write_csv(file, rows, Cr.columns)
end

--- Where a test writes its crack list: opts.cracks_csv, else next to its history
--- (opts.csv "out/ucs.csv" -> "out/ucs_cracks.csv"), else nowhere.
function Cr.csv_name(opts)
    if opts.cracks_csv then return opts.cracks_csv end
    if opts.csv then return (opts.csv:gsub("%.csv$", "")) .. "_cracks.csv" end
    return nil
end

return Cr
