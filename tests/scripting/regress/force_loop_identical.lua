-- SPDX-License-Identifier: MIT
-- The force loop's ways of running give the same bits (docs/architecture.md, "Force
-- loop" and "Threads"): the batched FDlaw against FDlaw per contact (`m:batched_law`), the
-- host's kernel of linear's law on its lane rows (`m:kernels`, docs/plugin-abi.md "Kernels"), the
-- lanes (`m:lanes`: linear's lane law on host-owned state, docs/plugin-abi.md "Lanes"), and 1, 2
-- or 3 threads (`m:threads`; 3 on a machine with 2 cores runs a thread more than there are
-- cores, and grain 1 makes even this scene's few hundred pairs use them). One scene with what the
-- loop does beyond the plain contact: `linear` with every dashpot mode (normal and shear
-- dashpots, no tension, no shear dashpot while sliding) and without dashpots, another model
-- (hertz, which has no batched law), the automatic step (stability, resolution and approach
-- notes, the latter from the step's complete forces), cbond bonds that break on impact, clumps,
-- and a wall chain with convex vertices the balls roll over (contact hand-over between segments,
-- done in the threads' serial part). Three ways to trace energy: per group (the whole model and
-- every group: one thread, the threads request falls back), off, and without groups (the whole
-- model's books: threads, each contact's items added in pair order afterwards).
-- The states must agree to the bit: positions, velocities, spins, every contact's forces and
-- moment, the wall forces, every energy item traced, the steps. No tolerance: every path runs
-- the same inline law on the same inputs, and every sum takes the same terms in the same order
-- (threads: per-pair actions that each ball gathers in pair order).
local T = require("testlib")

-- energy: "groups" (traced, with groups), "off", "plain" (traced, a scene without groups:
-- one contact rule with dashpots, every bond installed before the loose balls are made), or
-- "bare" (off, and no clumps: the law of motion's plain loop, which threads share too)
local function scene(batched, threads, energy, lanes, kernels)
    local m = talus.model{ gravity = {0, -9.81} }
    T.check(m:batched_law(batched) == batched, "m:batched_law(on) returns the setting")
    T.check(m:kernels(kernels == true) == (kernels == true), "m:kernels(on) returns the setting")
    T.check(m:lanes(lanes == true) == (lanes == true), "m:lanes(on) returns the setting")
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

local function batchedLaws(m)
    return tonumber(m:profile():match("batched laws (%d+)"))
end

local m
for _, energy in ipairs({"groups", "off", "plain", "bare"}) do
    local ref_m, ref_breaks = scene(false, 1, energy)
    local ref, ref_contacts = digest(ref_m, energy)
    -- The scene must exercise what it claims, and the reference must not have used the batch.
    T.check(ref_contacts > 100, energy .. ": a pile in contact: " .. ref_contacts .. " contacts")
    T.check(ref_breaks > 0 and ref_breaks < 40, energy .. ": some bonds broke: " .. ref_breaks)
    T.check(ref_m:clump_count() == (energy == "bare" and 0 or 6), "clumps present")
    T.check(ref_m:timestep().rule ~= "fixed", "automatic step")
    T.check(batchedLaws(ref_m) == 0, "m:batched_law(false): no batched call")
    for _, case in ipairs({{true, 1}, {true, 2}, {true, 3}, {false, 2}, {true, 1, true},
                           {true, 2, true}, {true, 3, true}, {true, 1, false, true},
                           {true, 2, false, true}, {true, 3, false, true},
                           {false, 1, false, true}}) do
        local batched, threads, lanes, kernels = case[1], case[2], case[3], case[4]
        local what = energy .. ", " .. (batched and "batched" or "per contact") ..
                     (lanes and " with lanes" or "") .. (kernels and " with kernels" or "") ..
                     ", " .. threads .. " thread(s)"
        local breaks
        m, breaks = scene(batched, threads, energy, lanes, kernels)
        local d, contacts = digest(m, energy)
        -- The lanes (or the kernels) ran linear's contacts, and some left them for FDlaw
        -- (separations); the rest of the contacts went through the batch or FDlaw.
        local lane_steps, declined = m:profile():match("lane steps (%d+) %(declined (%d+)%)")
        lane_steps, declined = tonumber(lane_steps), tonumber(declined)
        local kernel_steps, kernel_declined =
            m:profile():match("kernel steps (%d+) %(declined (%d+)%)")
        kernel_steps, kernel_declined = tonumber(kernel_steps), tonumber(kernel_declined)
        if lanes then
            T.check(lane_steps > 10 * m:step() and declined > 0,
                    what .. ": lane steps " .. lane_steps .. " (declined " .. declined .. ") over " ..
                    m:step() .. " steps")
        else
            T.check(lane_steps == 0, what .. ": no lane steps (" .. lane_steps .. ")")
        end
        if kernels and not lanes then
            T.check(kernel_steps > 10 * m:step() and kernel_declined > 0,
                    what .. ": kernel steps " .. kernel_steps .. " (declined " ..
                    kernel_declined .. ") over " .. m:step() .. " steps")
        else
            T.check(kernel_steps == 0, what .. ": no kernel steps (" .. kernel_steps .. ")")
        end
        if batched and not lanes and not kernels then
            -- The pile settles into ~200 contacts, most of them linear: the batch was the usual
            -- path (at least ten contacts per step on average, over a run that starts in flight).
            T.check(batchedLaws(m) > 10 * m:step(),
                    what .. ": batched laws " .. batchedLaws(m) .. " over " .. m:step() .. " steps")
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

T.fails(function() m:batched_law(1) end, {"batched_law: expected true or false"}, "not a boolean")
T.fails(function() m:lanes("yes") end, {"lanes: expected true or false"}, "not a boolean")
T.fails(function() m:threads(0) end, {"threads: the thread count must be from 1 to 1024"},
        "zero threads")
T.fails(function() m:threads(1.5) end, {"must be an integer"}, "a fraction")
T.fails(function() m:threads(2, 0) end, {"grain", ">= 1"}, "grain 0")

T.done("force_loop_identical")
