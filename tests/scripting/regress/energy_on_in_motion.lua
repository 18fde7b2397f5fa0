-- SPDX-License-Identifier: MIT
-- Energy tracing switched on while bodies move: the books open at a whole step, where the
-- kinetic energy and what the contacts hold are both known (docs/physics/energy.md, "Switching
-- tracing on"). A ball falling for 10 (or 100) steps, then traced for 10: the balance closed to
-- -1.01 J, 1.7% of the throughput, and the guard warned of energy created; a two-pebble clump
-- thrown with spin: 0.9% of the throughput. Free flight is integrated exactly, so now both close
-- to round-off (bound 1e-12 of the throughput), with no warning.
local T = require("testlib")

local function traced(m, before, after)
    local warnings = {}
    m:on_warning(function(text) warnings[#warnings + 1] = text end)
    m:cycle(before)
    m:energy{ on = true }
    m:cycle(after)
    local e = m:energies()
    local through = math.max(e.input, e.kinetic + e.strain + e.bond)
    return e, math.abs(e.balance_error) / through, warnings
end

for _, before in ipairs({ 10, 100 }) do
    local m = talus.model{ gravity = { 0, -9.81 } }
    m:contact_model("linear", { kn = 1e6 })
    m:ball{ pos = { 0, 10 }, radius = 0.1, density = 2600 }
    local e, rel, warnings = traced(m, before, 10)
    print(string.format("free fall, tracing on after %d steps: balance_error %.3g J, %.2g of %.4g J",
        before, e.balance_error, rel, e.input))
    T.check(rel < 1e-12, "free fall after " .. before .. " steps: " .. rel)
    T.check(#warnings == 0, "no warning: " .. tostring(warnings[1]))
    T.check(e.initial_kinetic > 0 and e.initial_kinetic < e.kinetic, "started in motion")
end

do
    local m = talus.model{ gravity = { 0, -9.81 } }
    m:contact_model("linear", { kn = 1e6 })
    m:clump{ pebbles = { { -0.03, 0, 0.05 }, { 0.03, 0, 0.05 } }, pos = { 0, 2 }, density = 2600,
             vel = { 3, 5 }, spin = 20 }
    local e, rel, warnings = traced(m, 50, 100)
    print(string.format("clump thrown with spin: balance_error %.3g J, %.2g of %.4g J", e.balance_error,
        rel, e.input))
    T.check(rel < 1e-12, "clump: " .. rel)
    T.check(#warnings == 0, "no warning: " .. tostring(warnings[1]))
end
print(string.format("energy_on_in_motion: %d checks passed", T.checks))
