-- SPDX-License-Identifier: MIT
-- material/loading.lua: the platen loading loop shared by the UCS, biaxial and Brazilian tests,
-- and the columns of its history.
local U = require("material.util")
local Wl = require("material.walls")
local Cr = require("material.cracks")
local E = require("material.equilibrium")

local L = {}

-- History columns: names with units for scripts/plot_history.py.
L.columns = { "step", "time", "strain_axial", "stress_axial [Pa]", "strain_lateral",
    "stress_lateral [Pa]", "breaks_tension", "breaks_shear", "energy_bond [J]",
    "energy_strain [J]", "energy_released [J]", "energy_slip [J]", "energy_damping [J]",
    "energy_boundary [J]", "energy_kinetic [J]", "cracks", "strain_volumetric" }

-- Shared platen loading loop of the UCS, biaxial and Brazilian tests. Platens move toward
-- each other at +-v/2 each... (velocity of each platen = v), ramped linearly over ramp_steps
-- (P&C: ramp to the final velocity so the specimen is not hit), rows every `every` steps.
-- `measure(h0, h)` gives a row's ea, sa, el (sl, strain_volumetric) for the platen gap h. The
-- result has the rows, the peak, the break counts and the crack list (cracks.lua).
function L.load_platens(sp, opts, measure)
    local m = sp.model
    local t0 = U.clock()
    local every = opts.every or 50
    local post = opts.post_peak or 0.8
    local ramp = opts.ramp_steps or 2000
    -- a cap against a specimen that never fails, not a stop rule: 30 000 (the old default) ended
    -- the LdB and 5 000-ball tests before their peak (the result's `stop` says which rule ended it)
    local max_steps = opts.max_steps or 200000
    local v = opts.velocity
    local h0 = -Wl.pos(sp.top) - Wl.pos(sp.bottom)
    if not v then
        -- default rate: the axial strain per P-wave crossing of the specimen is 2e-5
        -- (c = sqrt(E/rho), E estimated by the 2D contact stiffness kn per unit thickness)
        local c = math.sqrt(sp.mat.kn / (sp.mat.density or 2600))
        local rate = opts.rate or 2e-5 * c / h0
        v = 0.5 * rate * h0
    end
    local breaks = { tension = 0, shear = 0 }
    local cracks = {}
    local s0 = m:step()
    -- its own handler beside any the caller has (handlers chain), removed by its handle; each
    -- break is a crack with the axial strain at that step
    local handler = m:on_event("bond_break", function(ev)
        if ev.mode == "tension" then breaks.tension = breaks.tension + 1
        elseif ev.mode == "shear" then breaks.shear = breaks.shear + 1 end
        local h = -Wl.pos(sp.top) - Wl.pos(sp.bottom)
        cracks[#cracks + 1] = Cr.record(ev, s0, (h0 - h) / h0)
    end)
    local energy_on = m:energy{}
    local rows = {}
    local peak, ipeak = -math.huge, 0
    local stop_reason = "max_steps"
    local function row()
        local h = -Wl.pos(sp.top) - Wl.pos(sp.bottom)
        local r = measure(h0, h)
        r.step = m:step() - s0
        r.time = m:time()
        r.breaks_tension, r.breaks_shear = breaks.tension, breaks.shear
        r.cracks = #cracks
        if energy_on then
            local e = m:energies()
            r["energy_bond [J]"], r["energy_strain [J]"] = e.bond, e.strain
            r["energy_released [J]"], r["energy_slip [J]"] = e.released, e.slip
            r["energy_boundary [J]"], r["energy_kinetic [J]"] = e.boundary, e.kinetic
            r["energy_damping [J]"] = e.damping
        end
        r.strain_axial, r["stress_axial [Pa]"] = r.ea, r.sa
        r.strain_lateral, r["stress_lateral [Pa]"] = r.el, r.sl
        rows[#rows + 1] = r
        return r
    end
    -- With opts.hold_step the step is held at the automatic step (E.hold_step), re-held every
    -- `hold_every` (1 000) steps: a bonded specimen loaded quasi-statically keeps its contacts,
    -- and the automatic rule's work per cycle (its pass over the bodies and the limits the force
    -- loop gathers per pair) was a fifth of a UCS test step (1 250 balls: 142 against 184 us per
    -- step, the same UCS to 0.05%, E and nu to the digits shown). Without it, the automatic step
    -- every cycle.
    local stepper = E.held_stepper(m, opts.hold_step and (opts.hold_every or 1000) or nil)
    row()
    while true do
        local k = m:step() - s0
        local f = math.min(1, (k + 0.5 * every) / ramp)
        sp.top.wall.vel = { 0, -v * f }
        sp.bottom.wall.vel = { 0, v * f }
        stepper.cycle(every)
        local r = row()
        if r.sa > peak then peak, ipeak = r.sa, #rows end
        -- post-peak stop only once bonds broke: before the platens touch, a noise "peak" of a
        -- fraction of a newton followed by a smaller value would stop the test (seen on a
        -- Brazilian disk whose platens start at the ball extent, not pressed)
        local failing = (breaks.tension + breaks.shear > 0) or (sp.bonds or 0) == 0
        -- `confirm`: the drop counts only once the strain is (1 + confirm) x the peak's, so a
        -- load that comes back is not cut (Brazilian: one break under a platen halves the force
        -- for a while; the split comes later)
        local confirmed = r.ea >= (1 + (opts.confirm or 0)) * rows[ipeak].ea
        if failing and #rows > ipeak and r.sa < post * peak and peak > 0 and confirmed then
            stop_reason = "post_peak"; break
        end
        if opts.max_strain and r.ea > opts.max_strain then stop_reason = "max_strain"; break end
        if m:step() - s0 >= max_steps then break end
    end
    sp.top.wall.vel, sp.bottom.wall.vel = { 0, 0 }, { 0, 0 }
    stepper.release()
    m:remove_on_event(handler)
    return {
        rows = rows, peak = peak, ipeak = ipeak, steps = m:step() - s0, velocity = v,
        rate = 2 * v / h0, stop = stop_reason, breaks = breaks, cracks = cracks, time = U.clock() - t0,
    }
end

-- The balls whose outer edge lies within `band` of the specimen's left or right side, for the

return L
