-- SPDX-License-Identifier: MIT
-- A contact whose law the host runs as a kernel (docs/plugin-abi.md, "Kernels") takes its
-- effective mass from its row and reads the pair's only for the shear dashpot; a change of a
-- ball's mass or radius mid-run (b.density, b.radius, a clump made of touching balls) must take
-- its contacts out of the rows, so that the next step sees the new mass, as FDlaw does. Each run
-- is compared with the same script through FDlaw per contact (m:kernels(false)), to the bit.
-- Without the hand-back the kernel keeps solving the dashpots with the old mass, and the states
-- part at the first step after the change.
local T = require("testlib")

local function scene(kernels, shear_dashpot)
    local m = talus.model{ gravity = {0, -9.81} }
    T.check(m:kernels(kernels) == kernels, "m:kernels returns the setting")
    m:on_warning(function() end)
    m:contact_model("linear", { kn = 4e6, ks = 2e6, fric = 0.5, dp_nratio = 0.4,
                                dp_sratio = shear_dashpot and 0.3 or 0.0 })
    m:wall{ points = {{0, 1}, {0, 0}, {0.8, 0}, {0.8, 1}} }
    local balls = {}
    local rnd = T.lcg(777)
    for j = 0, 5 do
        for i = 0, 9 do
            balls[#balls + 1] = m:ball{ pos = {0.05 + 0.075 * i + 0.005 * rnd(), 0.05 + 0.07 * j},
                                        radius = 0.03 + 0.005 * rnd(), density = 2600 }
        end
    end
    m:solve{ time = 0.4 }  -- settled into persistent contacts (the kernel's)
    local steps_before = tonumber(m:profile():match("kernel steps (%d+)"))
    -- Heavier and lighter balls inside the pile, one grown and one shrunk.
    balls[15].density = 8000
    balls[26].density = 900
    balls[33].radius = balls[33].radius * 1.05
    balls[44].radius = balls[44].radius * 0.97
    m:solve{ time = 0.1 }
    -- Two touching balls made into a clump (their pebbles take the clump's mass).
    m:clump{ balls = {balls[21], balls[22]} }
    m:solve{ time = 0.1 }
    return m, steps_before
end

local function digest(m)
    return T.state_text(m, { props = {"dp_fn", "dp_fs"} })
end

for _, shear in ipairs({false, true}) do
    local what = shear and "with a shear dashpot" or "normal dashpot only"
    local ref = digest((scene(false, shear)))
    local m, before = scene(true, shear)
    local kernel_steps = tonumber(m:profile():match("kernel steps (%d+)"))
    -- The kernel ran the pile before the change and again after it.
    T.check(before > 50 * 200 and kernel_steps > 2 * before,
            what .. ": kernel steps " .. before .. " before the change, " .. kernel_steps .. " in all")
    T.check(digest(m) == ref, what .. ": the state after the mass changes differs from FDlaw's")
end
T.done("kernel_mass_change")
