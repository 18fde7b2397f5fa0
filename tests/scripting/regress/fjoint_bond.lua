-- SPDX-License-Identifier: MIT
-- fjoint installed with m:bond (docs/models/fjoint.md, "Installation"): strengths drawn per
-- contact, the installation states (bonded, unbonded, slit), properties read by name (the
-- per-element ones through fj_elem), bad input refused with the property's name and the
-- script's line, and m:unbond.
local T = require("testlib")

local R, RHO = 0.05, 2600
-- A 10 x 6 grid of balls overlapping their neighbours by 1e-6 m, held at rest by the grid
-- (no gravity): 60 balls, 9 x 6 + 10 x 5 = 104 contacts.
local function grid()
    local m = talus.model{ gravity = {0, 0} }
    m:contact_model("linear", { kn = 1e8, ks = 5e7, fric = 0.5 })
    m:on_warning(function() end) -- the overlapping placement is meant
    for i = 0, 9 do
        for j = 0, 5 do
            m:ball{ pos = {i * (2 * R - 1e-6), j * (2 * R - 1e-6)}, radius = R, density = RHO,
                    group = "rock" }
        end
    end
    m:cycle(1)
    T.check(m:contact_count{} == 104, "104 contacts, got " .. m:contact_count{})
    return m
end

local FJ = { fj_emod = 5e10, fj_kratio = 2.5, fj_nr = 3, fj_fa = 30, fj_fric = 0.4 }
local function with(extra)
    local p = {}
    for k, v in pairs(FJ) do p[k] = v end
    for k, v in pairs(extra) do p[k] = v end
    return p
end

-- 1. Bonded, strengths drawn per contact: fj_ten normal (mean 5 MPa, sd 1 MPa), fj_coh
-- uniform (mean 10 MPa, sd 2 MPa: [6.54, 13.46] MPa). Every contact gets its own value for the
-- whole interface; the same seed draws the same values.
local function drawn(seed)
    local m = grid()
    local n = m:bond{ model = "fjoint", group = "rock", reset = true, seed = seed,
                      props = with{ fj_ten = { mean = 5e6, sd = 1e6, dist = "normal" },
                                    fj_coh = { mean = 1e7, sd = 2e6, dist = "uniform" } } }
    T.check(n == 104, "every contact bonded")
    local ten, coh = {}, {}
    for c in m:contacts{} do
        T.check(c.model == "fjoint" and c:prop("bonded") == 1 and c:prop("fj_nbond") == 3,
            "installed bonded, three elements")
        T.check(c.normal_force == 0 and c.shear_force == 0 and c.moment == 0, "reset: force-free")
        T.near(c:prop("fj_kn"), 5e10 / (2 * R), 1e-15, "fj_kn = fj_emod / (R_A + R_B)")
        T.near(c:prop("fj_radius"), R, 1e-15, "R = fj_rmul min(R_A, R_B)")
        T.near(c:prop("fj_area"), 2 * R / 3, 1e-15, "element area 2R/N")
        ten[#ten + 1] = c:prop("fj_ten")
        coh[#coh + 1] = c:prop("fj_coh")
    end
    return ten, coh
end
local ten, coh = drawn(5)
local mean, var = 0, 0
for _, v in ipairs(ten) do mean = mean + v / #ten end
for _, v in ipairs(ten) do var = var + (v - mean) ^ 2 / (#ten - 1) end
-- 104 draws: the sample mean is within 4 standard errors (4 x 1e6 / sqrt(104) = 0.39 MPa) and
-- the sample sd within 30% of 1 MPa (its relative standard error is 1/sqrt(2 x 103) = 7%).
T.check(math.abs(mean - 5e6) < 4e6 / math.sqrt(#ten), "fj_ten mean " .. mean)
T.check(math.abs(math.sqrt(var) - 1e6) < 0.3e6, "fj_ten sd " .. math.sqrt(var))
local lo, hi = 1e7 - 2e6 * math.sqrt(3), 1e7 + 2e6 * math.sqrt(3)
local distinct = {}
for _, v in ipairs(coh) do
    T.check(v >= lo and v <= hi, "fj_coh within the uniform range")
    distinct[v] = true
end
local k = 0
for _ in pairs(distinct) do k = k + 1 end
T.check(k == #coh, "every contact its own cohesion")
local ten2 = drawn(5)
local ten3 = drawn(6)
T.check(ten2[1] == ten[1] and ten2[50] == ten[50], "the same seed draws the same values")
T.check(ten3[1] ~= ten[1], "another seed draws others")

-- 2. The installation states. Without reset the contacts' forces are adopted (bonded: both
-- signs; unbonded: compression, shear within friction); slit: force-free, open by fj_gap0.
do
    local m = grid()
    -- squeeze the grid a little so that its contacts carry compression
    for b in m:balls{} do b.pos = {b.pos[1] * (1 - 2e-5), b.pos[2] * (1 - 2e-5)} end
    m:cycle(1)
    local before = {}
    for c in m:contacts{} do before[c.key] = c.normal_force end
    m:bond{ model = "fjoint", props = with{ fj_mtype = "unbonded", fj_ten = 5e6, fj_coh = 1e7 } }
    local loaded = 0
    for c in m:contacts{} do
        T.check(c:prop("fj_nbond") == 0 and c:prop("bonded") == 0, "unbonded")
        T.check(c:prop("fj_mtype") == 1, "fj_mtype by name")
        T.near(c.normal_force, before[c.key], 1e-12, "compression adopted")
        if c.normal_force > 0 then loaded = loaded + 1 end
    end
    T.check(loaded > 50, "the squeezed grid is loaded")
end
do
    local m = grid()
    m:bond{ model = "fjoint", props = with{ fj_mtype = 2, fj_gap0 = 2e-7, fj_ten = 5e6,
                                           fj_coh = 1e7 } }
    for c in m:contacts{} do
        T.check(c:prop("fj_nbond") == 0 and c.normal_force == 0, "slit: unbonded, force-free")
        T.near(c:prop("fj_gap"), 2e-7, 1e-12, "open by fj_gap0")
        c:set_prop("fj_elem", 2)
        T.near(c:prop("fj_egap"), 2e-7, 1e-12, "element 2's centre too")
        T.check(c:prop("fj_state") == 0, "element state unbonded")
    end
end

-- 3. Per-element readouts, a partial break, and m:unbond: a pair bonded with three elements,
-- bent by opposite spins held fixed (no slip at the contact point) until the opening side's
-- element breaks, at theta = fj_ten / (fj_kn 2R/3) = 6e-5 rad (the middle element's centre does
-- not move in bending, the closing side's is compressed).
do
    local m = talus.model{ gravity = {0, 0} }
    m:contact_model("linear", { kn = 1e8, ks = 5e7, fric = 0.5 })
    local a = m:ball{ pos = {-R + 0.5e-9, 0}, radius = R, density = RHO }
    local b = m:ball{ pos = {R - 0.5e-9, 0}, radius = R, density = RHO }
    m:cycle(1)
    T.check(m:bond{ model = "fjoint", props = with{ fj_ten = 1e6, fj_coh = 1e7 } } == 1, "bonded")
    local events = {}
    m:on_event("bond_break", function(ev) events[#events + 1] = ev end)
    a.spin, b.spin = -0.01, 0.01
    a.fix, b.fix = true, true
    while m:time() < 1e-2 do m:cycle(100) end
    T.check(#events == 1 and events[1].mode == "tension", "one element broke in tension")
    T.near(events[1].sigma, 1e6, 1e-9, "at fj_ten")
    for c in m:contacts{} do
        T.check(c:prop("fj_nbond") == 2 and c:prop("bonded") == 1, "two left")
        local states = {}
        for e = 1, 3 do
            c:set_prop("fj_elem", e)
            states[e] = c:prop("fj_state")
        end
        -- the relative rotation is +: the side x < 0 (element 1) opens
        T.check(c:prop("fj_relbr") > 0, "theta > 0")
        T.check(states[1] == 1 and states[2] == 3 and states[3] == 3,
            "element 1 broken in tension, 2 and 3 bonded: " .. table.concat(states, " "))
        c:set_prop("fj_elem", 1)
        T.check(c:prop("fj_egap") > 0 and c:prop("fj_sigma") == 0, "element 1 open, no stress")
        c:set_prop("fj_elem", 3)
        T.check(c:prop("fj_sigma") < 0, "element 3 in compression")
        T.near(c:prop("fj_shear"), 1e7 - c:prop("fj_sigma") * math.tan(math.rad(30)), 1e-12,
            "its cohesive strength fj_coh - sigma tan fj_fa")
    end
    T.check(m:unbond{} == 1, "m:unbond")
    m:cycle(1)
    for c in m:contacts{} do T.check(c:prop("fj_nbond") == 0, "unbonded") end
    T.check(#events == 1, "no event from m:unbond")
end

-- 4. Bad input: refused with the property's name and the line of the script.
do
    local m = grid()
    local line = T.line() + 1
    T.fails(function() m:contact_model("fjoint", { fj_emod = -1, fj_kratio = 2 }) end,
        { T.script() .. ":" .. line, "fj_emod", ">= 0", "-1" }, "negative fj_emod")
    T.fails(function() m:contact_model("fjoint", { fj_nr = 0 }) end, { "fj_nr", "[1, 16]" },
        "fj_nr < 1")
    T.fails(function() m:contact_model("fjoint", { fj_elem = 0 }) end, { "fj_elem" }, "fj_elem < 1")
    T.fails(function() m:contact_model("fjoint", { fj_emod = 1e9 }) end, { "fj_kratio" },
        "fj_emod without fj_kratio")
    T.fails(function() m:contact_model("fjoint", { fj_tne = 1e6 }) end, { "fj_tne" },
        "unknown property")
    T.fails(function() m:bond{ model = "fjoint", props = { fj_tne = 1e6 } } end,
        { "bond: unknown property 'fj_tne' for model 'fjoint'", "fj_ten" }, "unknown in m:bond")
    T.fails(function() m:bond{ model = "fjoint", props = { fj_mtype = "cracked" } } end,
        { "fj_mtype", "\"slit\"" }, "unknown installation state")
    T.fails(function() m:bond{ model = "fjoint", props = { fj_nbond = 2 } } end, { "read-only" },
        "a read-only property")
    T.fails(function()
        m:bond{ model = "fjoint", props = { fj_ten = { mean = 1e6, sd = 1e6, dist = "uniform" } } }
    end, { "fj_ten", "below zero" }, "a uniform range below zero")
end

T.done("fjoint_bond")
