-- SPDX-License-Identifier: MIT
-- Kernel rows (docs/plugin-abi.md, "Kernels"): while the host's kernel runs `linear`'s
-- contacts, their state lives in the host's rows and their objects are out of date. Everything
-- that reads or writes a contact's object must see what FDlaw alone would have: reading a state
-- property (lin_fs, dp_fn, ...) mid-run, writing a property (the contact leaves its row and comes
-- back), m:save and talus.restore, switching the kernels off mid-run, energy tracing (the
-- kernel's energies). Each run is compared with the same script on FDlaw per contact
-- (m:kernels(false)), to the bit: positions, velocities, spins, every contact's forces and state
-- properties, the energies.
local T = require("testlib")

local save = os.tmpname()

-- A pile of ~150 balls of three sizes poured into a box with a sloped floor: persistent
-- contacts (the rows), separations (declined steps) and new touches, normal and shear dashpots
-- with no-tension, and energy traced over the whole model.
local function scene(kernels)
    local m = talus.model{ gravity = {0, -9.81} }
    T.check(m:kernels(kernels) == kernels, "m:kernels returns the setting")
    m:on_warning(function() end)
    m:contact_model("linear", { kn = 4e6, ks = 2e6, fric = 0.5, dp_nratio = 0.3,
                                dp_sratio = 0.2, dp_mode = 1 })
    m:wall{ points = {{0, 1.5}, {0, 0.1}, {0.6, 0}, {1.2, 0.12}, {1.2, 1.5}} }
    local rnd = T.lcg(4242)
    for j = 0, 9 do
        for i = 0, 14 do
            m:ball{ pos = {0.06 + 0.074 * i + 0.01 * rnd(), 0.2 + 0.075 * j},
                    radius = 0.025 + 0.012 * rnd(), density = 2600,
                    vel = {rnd() - 0.5, -rnd()}, spin = 2 * (rnd() - 0.5) }
        end
    end
    m:energy{ on = true }
    m:solve{ time = 0.35 }  -- poured: landed, still moving
    return m
end

local STATE = {"lin_fn", "lin_fs", "dp_fn", "dp_fs", "lin_slip"}

local ENERGIES = {"body", "kinetic", "strain", "slip", "dashpot", "released", "balance_error"}

local function digest(m)
    return T.state_text(m, { props = STATE, energies = ENERGIES })
end

local function kernelSteps(m)
    local n, d = m:profile():match("kernel steps (%d+) %(declined (%d+)%)")
    return tonumber(n), tonumber(d)
end

-- The script both runs follow: cycles, state reads, a property written on the contacts of one
-- ball, more cycles. `after` runs in the middle (save and restore, kernels off, ...).
local function run(kernels, after)
    local m = scene(kernels)
    m:cycle(600)
    local reads = digest(m)  -- reads every contact's state properties mid-run
    m:cycle(200)
    local first = m:balls{}().id
    for c in m:contacts{} do
        if c.ball1.id == first or (c.ball2 and c.ball2.id == first) then
            c:set_prop("fric", 0.2)
        end
    end
    m:cycle(200)
    if after then m = after(m) end
    m:cycle(400)
    return m, reads .. " | " .. digest(m)
end

local ref_m, ref = run(false)
T.check(kernelSteps(ref_m) == 0, "m:kernels(false): no kernel steps")
T.check(ref_m:contact_count{} > 150, "a pile in contact: " .. ref_m:contact_count{})

local m, d = run(true)
local steps, declined = kernelSteps(m)
T.check(steps > 50 * m:step() and declined > 0,
        "the kernel ran: " .. steps .. " kernel steps, " .. declined .. " declined, " .. m:step() ..
        " steps")
T.check(d == ref, "kernel rows: the same bits as FDlaw per contact, property reads and writes " ..
        "included")

-- Saved with contacts on rows, restored (no rows until their next FDlaw), continued.
local saved = nil
m, d = run(true, function(mm)
    mm:save(save)
    saved = digest(mm)
    local r = talus.restore(save, { quiet = true })
    r:energy{ on = true }
    T.check(r:kernels() == true, "kernels are a run setting: a restored model runs them")
    return r
end)
T.check(saved ~= nil, "saved mid-run")
T.check(d == ref, "kernel rows: saved and restored mid-run, the same bits")

-- The kernels switched off mid-run: every contact goes back to its object, which is up to date.
m, d = run(true, function(mm)
    mm:kernels(false)
    return mm
end)
T.check(d == ref, "kernels switched off mid-run: the same bits")
os.remove(save)

T.done("kernel_rows")
