-- SPDX-License-Identifier: MIT
-- material/loading.lua: the platen loading loop shared by the UCS, biaxial and Brazilian tests,
-- the columns of its history, and how far from quasi-static a test ran.
local U = require("material.util")
local Wl = require("material.walls")
local Cr = require("material.cracks")
local E = require("material.equilibrium")

local L = {}

-- History columns: names with units for scripts/plot_history.py.
L.columns = { "step", "time", "strain_axial", "stress_axial [Pa]", "strain_lateral",
    "stress_lateral [Pa]", "breaks_tension", "breaks_shear", "energy_bond [J]",
    "energy_strain [J]", "energy_released [J]", "energy_slip [J]", "energy_damping [J]",
    "energy_boundary [J]", "energy_kinetic [J]", "cracks", "strain_volumetric",
    "platen_difference", "ratio", "held" }

--- The default loading rate: the axial strain applied per P-wave crossing of the specimen (c =
--- sqrt(kn / rho), kn the material's contact modulus). docs/material.md, "Loading rate".
L.strain_per_crossing = 5e-6

--- The equilibrium hold of the platens' servo (docs/material.md, "Loading rate"): the platens
--- stop when PFC's mechanical ratio rises above `ratio` (a crack cascade; the loading itself
--- keeps it near 1e-4 at the default rate) and move on once it has fallen to `resume` (the
--- cascade has run its course); a hold lasts at most `crossings` P-wave crossings of the
--- specimen (a relaxation takes 20-45, docs/results/material.md). A test uses it when its
--- opts.hold is true or a table of these fields, or when opts.hold is nil and L.hold_default.
L.hold = { ratio = 1e-2, resume = 1e-4, crossings = 100 }
L.hold_default = false

--- A hold's fields over L.hold's (the caller's table untouched), or false for none.
function L.hold_of(hold)
    if hold == nil then hold = L.hold_default end
    if not hold then return false end
    hold = hold == true and {} or hold
    return { ratio = hold.ratio or L.hold.ratio, resume = hold.resume or L.hold.resume,
             crossings = hold.crossings or L.hold.crossings }
end

--- The servo's hold = {ratio, resume, max_steps} of a test (opts.hold, L.hold_of), for the
--- crossing time `crossing` [s] and the step `dt` [s]; false for none.
function L.hold_settings(opts, crossing, dt)
    local h = L.hold_of(opts.hold)
    if not h then return false end
    return { ratio = h.ratio, resume = math.min(h.resume, h.ratio),
             max_steps = math.max(1, math.ceil(h.crossings * crossing / dt)) }
end

--- The hold as text, for a checkpoint's key (a test rerun with another hold is made again).
function L.hold_key(hold)
    local h = L.hold_of(hold)
    if not h then return "off" end
    return string.format("%g/%g/%g", h.ratio, h.resume, h.crossings)
end

--- The loading rate [1/s] of a test: opts.rate, or opts.strain_per_crossing (L's default) per
--- P-wave crossing of the gauge length h0. Also returns the crossing time [s].
function L.rate(sp, opts, h0)
    local c = math.sqrt(sp.mat.kn / (sp.mat.density or 2600))
    local crossing = h0 / c
    if opts.velocity then return 2 * opts.velocity / h0, crossing end
    return opts.rate or (opts.strain_per_crossing or L.strain_per_crossing) / crossing, crossing
end

--- How far from quasi-static a test ran, from its rows up to the peak (those above half of it)
--- and at the peak: the platen stress difference |F_top - F_bottom| / their mean (the net force
--- that accelerates the specimen as a body), the kinetic over the stored (strain + bond) energy
--- (with energy tracing), and the bond breaks per P-wave crossing over the tenth of the test
--- before the peak, and PFC's mechanical ratio at the peak (the servo's hold measures it). Returns
--- { difference_peak, difference_max, difference_mean, kinetic_peak, kinetic_max,
--- cracks_per_crossing, ratio_peak }.
function L.quasi_static(rows, ipeak, crossing)
    local q = { difference_max = 0, difference_mean = 0 }
    local peak = rows[ipeak]
    if not peak then return q end
    local n, ksum = 0, 0
    for i = 1, ipeak do
        local r = rows[i]
        if r.sa >= 0.5 * peak.sa then
            local d = math.abs(r.platen_difference or 0)
            q.difference_max = math.max(q.difference_max, d)
            q.difference_mean = q.difference_mean + d
            n = n + 1
            local es = (r["energy_strain [J]"] or 0) + (r["energy_bond [J]"] or 0)
            if r["energy_kinetic [J]"] and es > 0 then
                local k = r["energy_kinetic [J]"] / es
                q.kinetic_max = math.max(q.kinetic_max or 0, k)
                ksum = ksum + k
            end
        end
    end
    q.difference_mean = n > 0 and q.difference_mean / n or 0
    q.difference_peak = math.abs(peak.platen_difference or 0)
    q.ratio_peak = peak.ratio
    local es = (peak["energy_strain [J]"] or 0) + (peak["energy_bond [J]"] or 0)
    if peak["energy_kinetic [J]"] and es > 0 then
        q.kinetic_peak = peak["energy_kinetic [J]"] / es
        q.kinetic_mean = ksum / n
    end
    local i0 = math.max(1, ipeak - math.max(1, math.floor(ipeak / 10)))
    local dt = peak.time - rows[i0].time
    if dt > 0 then
        local breaks = (peak.breaks_tension + peak.breaks_shear) - (rows[i0].breaks_tension + rows[i0].breaks_shear)
        q.cracks_per_crossing = breaks / (dt / crossing)
    end
    return q
end

-- Shared platen loading loop of the UCS, biaxial and Brazilian tests. The engine's servo moves
-- the platens toward each other at the strain rate (each at rate h0 / 2), reached over a ramp
-- of ramp_steps (P&C: ramp to the final velocity so the specimen is not hit); rows every `every`
-- steps. `measure(h0, h)` gives a row's ea, sa, el (sl, strain_volumetric) for the platen gap
-- h. `opts.stop(rows, ipeak, cracks)` may end the test (returns the reason). The result has the
-- rows, the peak, the break counts, the crack list (cracks.lua) and how far from quasi-static
-- the test ran (L.quasi_static).
function L.load_platens(sp, opts, measure)
    local m = sp.model
    local t0 = U.clock()
    local every = opts.every or 50
    local post = opts.post_peak or 0.8
    local ramp = opts.ramp_steps or 2000
    local h0 = opts.gauge or (-Wl.pos(sp.top) - Wl.pos(sp.bottom))
    local rate, crossing = L.rate(sp, opts, h0)
    -- With opts.hold_step the step is held at the automatic step (E.hold_step), re-held every
    -- `hold_every` (1 000) steps: a bonded specimen loaded quasi-statically keeps its contacts,
    -- and the automatic rule's work per cycle is a fifth of a test step.
    local stepper = E.held_stepper(m, opts.hold_step and (opts.hold_every or 1000) or nil)
    -- a cap against a specimen that never fails, not a stop rule: the steps that strain the
    -- specimen by cap_strain (2%) at the rate, after the ramp (the result's `stop` says which
    -- rule ended the test)
    local max_steps = opts.max_steps
    if not max_steps then
        -- the specimen's last step (its relaxation's), the test's to a few per cent
        max_steps = ramp + math.ceil((opts.cap_strain or 0.02) / (rate * m:dt()))
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
    local servo -- the platens' (below), nil for the first row
    local function row()
        local h = -Wl.pos(sp.top) - Wl.pos(sp.bottom)
        local r = measure(h0, h)
        r.step = m:step() - s0
        r.time = m:time()
        r.breaks_tension, r.breaks_shear = breaks.tension, breaks.shear
        r.cracks = #cracks
        local ft, fb = Wl.push(sp.top), Wl.push(sp.bottom)
        local mean = 0.5 * (ft + fb)
        r.platen_difference = mean > 0 and (ft - fb) / mean or 0
        if energy_on then
            local e = m:energies()
            r["energy_bond [J]"], r["energy_strain [J]"] = e.bond, e.strain
            r["energy_released [J]"], r["energy_slip [J]"] = e.released, e.slip
            r["energy_boundary [J]"], r["energy_kinetic [J]"] = e.boundary, e.kinetic
            r["energy_damping [J]"] = e.damping
        end
        if servo then
            local st = servo:state()
            r.ratio, r.held = st.ratio, st.held
        end
        r.strain_axial, r["stress_axial [Pa]"] = r.ea, r.sa
        r.strain_lateral, r["stress_lateral [Pa]"] = r.el, r.sl
        rows[#rows + 1] = r
        return r
    end
    row()
    -- the platens' servo: set once, run by the engine every step; with the hold the platens wait
    -- while a crack cascade runs (L.hold)
    local hold = L.hold_settings(opts, crossing, m:dt())
    servo = m:servo{ walls = { sp.top.wall, sp.bottom.wall }, dirs = { sp.top.n, sp.bottom.n },
                     rate = rate, gauge = h0, ramp = ramp, hold = hold }
    while true do
        stepper.cycle(every)
        local r = row()
        if r.sa > peak then peak, ipeak = r.sa, #rows end
        -- post-peak stop only once bonds broke: before the platens touch, a noise "peak" of a
        -- fraction of a newton followed by a smaller value would stop the test (seen on a
        -- Brazilian disk whose platens start at the ball extent, not pressed)
        local failing = (breaks.tension + breaks.shear > 0) or (sp.bonds or 0) == 0
        -- `confirm`: the drop counts only once the strain is (1 + confirm) x the peak's, so a
        -- load that comes back is not cut
        local confirmed = r.ea >= (1 + (opts.confirm or 0)) * rows[ipeak].ea
        if failing and #rows > ipeak and r.sa < post * peak and peak > 0 and confirmed then
            stop_reason = "post_peak"; break
        end
        local why = opts.stop and opts.stop(rows, ipeak, cracks)
        if why then stop_reason = why; break end
        if opts.max_strain and r.ea > opts.max_strain then stop_reason = "max_strain"; break end
        -- the cap counts the steps the platens moved; the held ones have their own cap, the
        -- total (opts.max_held, default 10 x max_steps) so that a test whose holds never end
        -- still does
        if m:step() - s0 - (r.held or 0) >= max_steps then break end
        if (r.held or 0) >= (opts.max_held or 10 * max_steps) then stop_reason = "max_held"; break end
    end
    local sst = servo:state()
    servo:remove()
    stepper.release()
    m:remove_on_event(handler)
    return {
        rows = rows, peak = peak, ipeak = ipeak, steps = m:step() - s0, velocity = 0.5 * rate * h0,
        rate = rate, crossing = crossing, max_steps = max_steps, stop = stop_reason, breaks = breaks,
        cracks = cracks, time = U.clock() - t0, quasi_static = L.quasi_static(rows, ipeak, crossing),
        held = sst.held or 0, holds = sst.holds or 0, holds_capped = sst.holds_capped or 0,
    }
end

return L
