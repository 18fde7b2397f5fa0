-- SPDX-License-Identifier: MIT
-- The force loop's ways of running give the same bits (docs/architecture.md, "Force
-- loop" and "Threads"): the host's kernels of linear's and cbond's laws on their rows
-- (`m:kernels`, docs/plugin-abi.md "Kernels") against FDlaw per contact, and 1, 2 or 3 threads
-- (`m:threads`; 3 on a machine with 2 cores runs a thread more than there are cores, and grain 1
-- makes even this scene's few hundred pairs use them). One scene with what the
-- loop does beyond the plain contact: `linear` with every dashpot mode (normal and shear
-- dashpots, no tension, no shear dashpot while sliding) and without dashpots, another model
-- (hertz, which has no kernel: the loop runs a switch per contact), the automatic step (stability, resolution and approach
-- notes, the latter from the step's complete forces), cbond bonds that break on impact, clumps,
-- and a wall chain with convex vertices the balls roll over (contact hand-over between segments,
-- done in the threads' serial part). Three ways to trace energy: per group (the whole model and
-- every group: one thread, the threads request falls back), off, and without groups (the whole
-- model's books: threads, each contact's items added in pair order afterwards).
-- A second scene, of the parallel bond (no kernel), is described at its function.
-- The states must agree to the bit: positions, velocities, spins, every contact's forces and
-- moment, the wall forces, every energy item traced, the steps. No tolerance: every path runs
-- the same inline law on the same inputs, and every sum takes the same terms in the same order
-- (threads: per-pair actions that each ball gathers in pair order).
local T = require("testlib")

-- energy: "groups" (traced, with groups), "off", "plain" (traced, a scene without groups:
-- one contact rule with dashpots, every bond installed before the loose balls are made), or
-- "bare" (off, and no clumps: the law of motion's plain loop, which threads share too)
local function scene(threads, energy, kernels)
    local m = talus.model{ gravity = {0, -9.81} }
    T.check(m:kernels(kernels) == kernels, "m:kernels(on) returns the setting")
    T.check(m:threads(threads, 1) == threads, "m:threads(n) returns the count set")
    m:on_warning(function() end)  -- guard findings of the pour are not this test's topic
    local grouped = energy ~= "plain"
    local function group(name) return grouped and name or nil end
    m:contact_model("linear", { kn = 2e6, ks = 1e6, fric = 0.4, dp_nratio = 0.2,
                                dp_sratio = 0.1 })
    if grouped then
        m:contact_model("linear", { kn = 2e6, ks = 1e6, fric = 0.3, dp_nratio = 0.3, dp_mode = 3 },
                        { groups = {"a", "a"} })
        m:contact_model("linear", { kn = 3e6, ks = 1e6, fric = 0.5, dp_sratio = 0.2, dp_mode = 2 },
                        { groups = {"b", "b"} })
        m:contact_model("hertz", { hz_shear = 3e8, hz_poiss = 0.25, fric = 0.4 }, { groups = {"a", "b"} })
        m:contact_model("linear", { kn = 2e6, ks = 1e6, fric = 0.4 }, { groups = {"bonded"} })
    end
    -- A box whose floor is a saw of convex and concave vertices (hand-over at the crests).
    local floor = {{0, 2}, {0, 0}}
    for k = 1, 8 do
        floor[#floor + 1] = {0.25 * k - 0.125, 0.04 + 0.01 * (k % 3)}
        floor[#floor + 1] = {0.25 * k, 0}
    end
    floor[#floor + 1] = {2, 2}
    m:wall{ points = floor, group = group("box") }
    -- A bonded block of touching balls that hits the pile and breaks up.
    for j = 0, 3 do
        for i = 0, 3 do
            m:ball{ pos = {0.8 + 0.05 * i, 1.5 + 0.05 * j}, radius = 0.025, density = 2600,
                    vel = {0, -2}, groups = grouped and {"bonded", "b"} or nil }
        end
    end
    m:bond{ model = "cbond", group = group("bonded"), gap = 1e-4,
            props = { kn = 2e6, ks = 1e6, fric = 0.4, cb_tenf = 40, cb_shearf = 40 } }
    -- Loose balls, two groups, given velocities and spins (fixed pseudo-random sequence).
    local rnd = T.lcg(12345)
    for j = 0, 7 do
        for i = 0, 17 do
            m:ball{ pos = {0.1 + 0.1 * i + 0.02 * rnd(), 0.2 + 0.1 * j + 0.02 * rnd()},
                    radius = 0.03 + 0.015 * rnd(), density = 2600,
                    vel = {rnd() - 0.5, rnd() - 0.5}, spin = 4 * (rnd() - 0.5),
                    group = group((i + j) % 2 == 0 and "a" or "b") }
        end
    end
    local t = m:clump_template{ pebbles = {{0, 0, 0.04}, {0.05, 0, 0.035}, {0.02, 0.045, 0.03}} }
    for k = 0, 5 do
        if energy ~= "bare" then
            m:clump{ template = t, pos = {0.2 + 0.3 * k, 1.2}, angle = 0.4 * k, density = 2600,
                     group = group("a") }
        end
    end
    if energy == "groups" or energy == "plain" then m:energy{ on = true } end
    local breaks = 0
    m:on_event("bond_break", function() breaks = breaks + 1 end)
    m:solve{ time = 0.5 }
    return m, breaks
end

local function digest(m, energy)
    local out = {}
    local function put(...) for _, v in ipairs({...}) do out[#out + 1] = T.hex(v) end end
    for b in m:balls() do put(b.pos[1], b.pos[2], b.vel[1], b.vel[2], b.spin, b.angle) end
    local contacts = 0
    for c in m:contacts{} do
        contacts = contacts + 1
        out[#out + 1] = tostring(c.key)
        put(c.normal_force, c.shear_force, c.moment, c.overlap)
    end
    for w in m:walls() do put(w.force[1], w.force[2]) end
    local items = {"body", "boundary", "kinetic", "strain", "bond", "slip", "dashpot", "plastic",
                   "damping", "released", "placement", "balance_error"}
    local books = energy == "groups" and {false, "a", "b", "bonded", "box"}
                  or energy == "plain" and {false} or {}
    for _, g in ipairs(books) do
        local e = g and m:energies(g) or m:energies()
        for _, k in ipairs(items) do put(e[k]) end
        if g then put(e.exchanged) end
    end
    put(m:time(), (m:dt()))
    out[#out + 1] = tostring(m:step())
    return table.concat(out, " "), contacts
end

local function kernelSteps(m)
    local n, d = m:profile():match("kernel steps (%d+) %(declined (%d+)%)")
    return tonumber(n), tonumber(d)
end

local m
for _, energy in ipairs({"groups", "off", "plain", "bare"}) do
    local ref_m, ref_breaks = scene(1, energy, false)
    local ref, ref_contacts = digest(ref_m, energy)
    -- The scene must exercise what it claims, and the reference must not have used a kernel.
    T.check(ref_contacts > 100, energy .. ": a pile in contact: " .. ref_contacts .. " contacts")
    T.check(ref_breaks > 0 and ref_breaks < 40, energy .. ": some bonds broke: " .. ref_breaks)
    T.check(ref_m:clump_count() == (energy == "bare" and 0 or 6), "clumps present")
    T.check(ref_m:timestep().rule ~= "fixed", "automatic step")
    T.check(kernelSteps(ref_m) == 0, "m:kernels(false): no kernel step")
    for _, case in ipairs({{2, false}, {3, false}, {1, true}, {2, true}, {3, true}}) do
        local threads, kernels = case[1], case[2]
        local what = energy .. (kernels and ", kernels" or ", FDlaw") .. ", " .. threads ..
                     " thread(s)"
        local breaks
        m, breaks = scene(threads, energy, kernels)
        local d, contacts = digest(m, energy)
        -- The kernels ran linear's contacts, and some left them for FDlaw (separations); the
        -- rest of the contacts went through FDlaw.
        local kernel_steps, kernel_declined = kernelSteps(m)
        if kernels then
            T.check(kernel_steps > 10 * m:step() and kernel_declined > 0,
                    what .. ": kernel steps " .. kernel_steps .. " (declined " ..
                    kernel_declined .. ") over " .. m:step() .. " steps")
        else
            T.check(kernel_steps == 0, what .. ": no kernel steps (" .. kernel_steps .. ")")
        end
        -- More than one thread ran, in a build with OpenMP (GCC's libgomp: .ci's build), except
        -- with energy per group (one thread by design); without OpenMP every step runs on one.
        local threaded = tonumber(m:profile():match("threaded steps (%d+)"))
        local expect = threads > 1 and talus.openmp and energy ~= "groups"
        T.check(expect == (threaded > 0.5 * m:step()) and (expect or threaded == 0),
                what .. ": " .. threaded .. " of " .. m:step() .. " steps on threads")
        T.check(breaks == ref_breaks, what .. ": " .. breaks .. " breaks, reference " .. ref_breaks)
        T.check(m:step() == ref_m:step(), what .. ": same step count")
        T.check(d == ref, what .. ": state differs from the reference (per contact, 1 thread; " ..
                contacts .. " contacts against " .. ref_contacts .. ")")
    end
end

-- The parallel bond (docs/models/pbond.md): a bonded block of pbond (started stress-free:
-- lin_mode 1, with dashpots, a Mohr-Coulomb shear strength and a bending stress) falls onto a
-- pile of loose balls that touch through unbonded pbond (lin_mode 0) and breaks up there, in
-- tension and in shear. Against FDlaw alone on one thread: on 1 to 3 threads with the kernels
-- setting on (pbond has no kernel in the engine: measured no faster than its FDlaw,
-- docs/results/benchmarks-history.md "Kernels: pbond"), energy traced and not.
local function pbondScene(threads, energy, kernels)
    local m = talus.model{ gravity = {0, -9.81} }
    T.check(m:kernels(kernels) == kernels, "m:kernels(on) returns the setting")
    T.check(m:threads(threads, 1) == threads, "m:threads(n) returns the count set")
    m:on_warning(function() end)
    m:contact_model("pbond", { kn = 2e6, ks = 1e6, fric = 0.4, dp_nratio = 0.1 })
    m:wall{ points = {{0, 2}, {0, 0}, {2, 0}, {2, 2}} }
    for j = 0, 4 do
        for i = 0, 4 do
            m:ball{ pos = {0.8 + 0.05 * i, 1.2 + 0.05 * j}, radius = 0.025, density = 2600,
                    vel = {0, -2} }
        end
    end
    m:bond{ model = "pbond", gap = 1e-4, reset = true,
            props = { pb_kn = 8e7, pb_ks = 4e7, pb_ten = 1e5, pb_coh = 5e4, pb_fa = 20,
                      dp_nratio = 0.2, dp_sratio = 0.1 } }
    local rnd = T.lcg(4321)
    for j = 0, 5 do
        for i = 0, 17 do
            m:ball{ pos = {0.1 + 0.1 * i + 0.02 * rnd(), 0.1 + 0.1 * j + 0.02 * rnd()},
                    radius = 0.03 + 0.015 * rnd(), density = 2600,
                    vel = {rnd() - 0.5, rnd() - 0.5}, spin = 4 * (rnd() - 0.5) }
        end
    end
    if energy then m:energy{ on = true } end
    local breaks = { tension = 0, shear = 0 }
    m:on_event("bond_break", function(e) breaks[e.mode] = (breaks[e.mode] or 0) + 1 end)
    m:solve{ time = 0.4 }
    return m, breaks
end

for _, energy in ipairs({true, false}) do
    local mode = energy and "pbond, energy on" or "pbond, energy off"
    local ref_m, ref_breaks = pbondScene(1, energy, false)
    local ref, ref_contacts = digest(ref_m, energy and "plain" or "off")
    T.check(ref_contacts > 60, mode .. ": a pile in contact: " .. ref_contacts .. " contacts")
    T.check(ref_breaks.tension > 0 and ref_breaks.shear > 0 and
            ref_breaks.tension + ref_breaks.shear < 40,
            mode .. ": some bonds broke, in tension (" .. ref_breaks.tension .. ") and in shear (" ..
            ref_breaks.shear .. ")")
    local bonded = 0
    for c in ref_m:contacts{} do
        if c.model == "pbond" and c:prop("bonded") == 1 then bonded = bonded + 1 end
    end
    T.check(bonded > 5, mode .. ": bonds left intact: " .. bonded)
    local kernel_steps = tonumber(ref_m:profile():match("kernel steps (%d+)"))
    T.check(kernel_steps == 0, mode .. ", kernels off: no kernel steps (" .. kernel_steps .. ")")
    for _, case in ipairs({{1, true}, {2, true}, {3, true}, {2, false}}) do
        local threads, kernels = case[1], case[2]
        local what = mode .. (kernels and ", kernels on" or ", FDlaw") .. ", " .. threads ..
                     " thread(s)"
        local mk, breaks = pbondScene(threads, energy, kernels)
        local d, contacts = digest(mk, energy and "plain" or "off")
        local steps, declined = kernelSteps(mk)
        T.check(steps == 0 and declined == 0, what .. ": no kernel steps (" .. steps .. ")")
        T.check(breaks.tension == ref_breaks.tension and breaks.shear == ref_breaks.shear,
                what .. ": the same breaks")
        T.check(mk:step() == ref_m:step(), what .. ": same step count")
        T.check(d == ref, what .. ": state differs from the reference (FDlaw, 1 thread; " ..
                contacts .. " contacts against " .. ref_contacts .. ")")
    end
end

-- A scene of one kernel (the contact bond everywhere): the loop compiled for cbond's rows alone
-- (no switch per contact), against FDlaw, on 1 and 2 threads. A bonded block falls onto a pile
-- of unbonded cbond contacts and breaks up.
local function cbondScene(threads, kernels)
    local m = talus.model{ gravity = {0, -9.81} }
    m:kernels(kernels)
    m:threads(threads, 1)
    m:on_warning(function() end)
    m:contact_model("cbond", { kn = 2e6, ks = 1e6, fric = 0.4 })
    m:wall{ points = {{0, 2}, {0, 0}, {2, 0}, {2, 2}} }
    for j = 0, 3 do
        for i = 0, 3 do
            m:ball{ pos = {0.8 + 0.05 * i, 0.9 + 0.05 * j}, radius = 0.025, density = 2600,
                    vel = {0, -1} }
        end
    end
    m:bond{ model = "cbond", gap = 1e-4,
            props = { kn = 2e6, ks = 1e6, fric = 0.4, cb_tenf = 3000, cb_shearf = 3000 } }
    local rnd = T.lcg(777)
    for j = 0, 5 do
        for i = 0, 17 do
            m:ball{ pos = {0.1 + 0.1 * i + 0.02 * rnd(), 0.1 + 0.1 * j + 0.02 * rnd()},
                    radius = 0.03 + 0.015 * rnd(), density = 2600,
                    vel = {rnd() - 0.5, rnd() - 0.5}, spin = 4 * (rnd() - 0.5) }
        end
    end
    local breaks = 0
    m:on_event("bond_break", function() breaks = breaks + 1 end)
    m:solve{ time = 0.4 }
    return m, breaks
end

do
    local ref_m, ref_breaks = cbondScene(1, false)
    local ref, ref_contacts = digest(ref_m, "off")
    T.check(ref_contacts > 15 and ref_breaks > 0 and ref_breaks < 24, "cbond: in contact (" ..
            ref_contacts .. " contacts), some of the 24 bonds broke (" .. ref_breaks .. ")")
    for _, threads in ipairs({1, 2}) do
        local mk, breaks = cbondScene(threads, true)
        local d = digest(mk, "off")
        local steps = kernelSteps(mk)
        T.check(steps > 10 * mk:step(), "cbond, " .. threads .. " thread(s): kernel steps " .. steps)
        T.check(breaks == ref_breaks and d == ref,
                "cbond, kernels, " .. threads .. " thread(s): the same bits as FDlaw")
    end
end

T.fails(function() m:kernels("yes") end, {"kernels: expected true or false"}, "not a boolean")
T.fails(function() m:threads(0) end, {"threads: the thread count must be from 1 to 1024"},
        "zero threads")
T.fails(function() m:threads(1.5) end, {"must be an integer"}, "a fraction")
T.fails(function() m:threads(2, 0) end, {"grain", ">= 1"}, "grain 0")

T.done("force_loop_identical")
