-- SPDX-License-Identifier: MIT
-- The rockfall workflow module (scripts/lib/rockfall/, docs/rockfall.md): reproducibility,
-- collector interpolation, barrier bookkeeping, the impact table, end rules, seeder
-- distributions, roughness and input errors.
local T = require("testlib")
local rf = require("rockfall")

local lin = { model = "linear", props = { kn = 1e7, ks = 5e6, fric = 0.5, dp_nratio = 0.3, dp_mode = "full" } }
local flat = { {0, 0}, {100, 0} }

-- Deep equality of plain data (records): numbers compared exactly.
local function same(a, b, path)
    if type(a) ~= type(b) then return false, path end
    if type(a) ~= "table" then return a == b or (a ~= a and b ~= b), path end
    for k, v in pairs(a) do
        local ok, p = same(v, b[k], path .. "." .. tostring(k))
        if not ok then return false, p end
    end
    for k in pairs(b) do if a[k] == nil then return false, path .. "." .. tostring(k) end end
    return true
end

-- ---------------------------------------------------------------- reproducibility
do
    local function make(n)
        return rf.analysis{
            profile = { {0, 10}, {5, 5}, {8, 5}, {12, 0}, {40, 0} },
            materials = { rockm = lin, soil = lin },
            zones = { { material = "rockm", x_from = 0, x_to = 5 }, { material = "soil", x_from = 5, x_to = 40 } },
            roughness = { amplitude = 0.02, spacing = 1 },
            seeders = { { kind = "line", from = {0.5, 10.5}, to = {1.5, 10.5}, vx = { dist = "uniform", min = 1, max = 2 },
                rock = { { shape = "three_balls", scale = { dist = "normal", mean = 3, sd = 0.3 } },
                         { shape = "ball", radius = 0.12 } } } },
            collectors = { { name = "c", x = 10 } }, seed = 77, n = n, t_max = 20,
        }
    end
    local a3, a10 = make(3), make(10)
    local fwd = {}
    for i = 1, 3 do fwd[i] = rf.run_rock(a3, i) end
    for i = 3, 1, -1 do
        -- Rock i alone, from an analysis of another size, in reverse order: the same record.
        local ok, where = same(fwd[i], rf.run_rock(a10, i), "record")
        T.check(ok, "record " .. i .. " independent of N and order (differs at " .. tostring(where) .. ")")
    end
    local ok = same(fwd[2], rf.run_rock(a3, 2), "r")
    T.check(ok, "same seed, same record")
    T.check(fwd[1].seed ~= fwd[2].seed, "rocks have their own seeds")
    for i = 1, 3 do
        -- Energy tracing on: the engine's books close (its guard warns beyond 1% of the
        -- throughput, and warnings land in the record).
        T.check(fwd[i].warnings == nil, "no engine warning for rock " .. i)
        T.check(math.abs(fwd[i].energy.balance_error) < 0.01 * fwd[i].energy.input, "energy balance rock " .. i)
    end
    local other = rf.analysis{ profile = flat, materials = { s = lin },
        seeders = { { at = {1, 1}, vx = { dist = "uniform", min = 0, max = 1 } } }, seed = 78 }
    local mine = rf.analysis{ profile = flat, materials = { s = lin },
        seeders = { { at = {1, 1}, vx = { dist = "uniform", min = 0, max = 1 } } }, seed = 77 }
    T.check(rf.sample(other, 1).release.vx ~= rf.sample(mine, 1).release.vx, "another seed, another draw")
end

-- ---------------------------------------------------------------- collector vs ballistic closed form
do
    -- A ball in free flight (profile far below, nothing touched) crosses x = X. Central
    -- differences put the whole-step positions exactly on the parabola under constant gravity,
    -- and the module's interpolation is the exact parabola between two steps, so the crossing
    -- state equals the closed form up to round-off: 1e-9 relative (the steps are ~1e-2 s, the
    -- round-off of a few hundred additions of O(10) numbers is ~1e-13).
    local g, vx0, vy0, x0, y0, R = 9.81, 3.0, 2.0, 1.0, 50.0, 0.2
    local an = rf.analysis{ profile = { {0, 0}, {30, 0} }, materials = { s = lin },
        seeders = { { at = {x0, y0}, vx = vx0, vy = vy0, rock = { shape = "ball", radius = R } } },
        collectors = { { name = "a", x = 2.3 }, { name = "b", x = 7.77 } }, t_max = 2.5, seed = 5 }
    local r = rf.run_rock(an, 1)
    T.check(#r.crossings == 2, "two crossings")
    for _, c in ipairs(r.crossings) do
        local t = (c.x - x0) / vx0
        local y = y0 + vy0 * t - 0.5 * g * t * t
        local vy = vy0 - g * t
        T.near(c.t, t, 1e-9, "crossing time " .. c.line)
        T.near(c.y, y, 1e-9, "crossing height " .. c.line)
        T.near(c.height, y - R, 1e-9, "passing height above the profile " .. c.line)
        T.near(c.vx, vx0, 1e-9, "vx " .. c.line)
        T.near(c.vy, vy, 1e-9, "vy " .. c.line)
        T.near(c.ke_trans, 0.5 * r.mass * (vx0 ^ 2 + vy ^ 2), 1e-9, "ke_trans " .. c.line)
        T.near(c.ke_rot, 0, 1e-12, "no spin")
    end
    T.check(r.stop == "time", "time cap ends a rock still flying (got " .. tostring(r.stop) .. ")")
end

-- ---------------------------------------------------------------- barrier bookkeeping
do
    -- No gravity: the ball flies level at y = 1 with constant speed and spin, so the collector
    -- behind the barrier sees exactly what the barrier left: ke_after = ke_before - E_cap.
    local function run(E, H)
        local an = rf.analysis{ profile = { {0, 0}, {30, 0} }, materials = { s = lin }, gravity = {0, 0},
            seeders = { { at = {1, 1}, vx = 10, vy = 0, spin = 20, rock = { shape = "ball", radius = 0.2 } } },
            barriers = { { name = "net", x = 5, energy = E, height = H } },
            collectors = { { name = "before", x = 4 }, { name = "after", x = 8 } }, seed = 1, t_max = 5 }
        return rf.run_rock(an, 1)
    end
    local probe = run(1e30, 10)
    local ke0 = probe.crossings[1].ke
    T.check(probe.stop == "barrier" and probe.barrier[1].stopped, "a barrier above the rock's energy stops it")
    T.near(probe.end_x, 5, 1e-12, "stopped at the barrier line")
    T.near(probe.barrier[1].energy, ke0, 1e-12, "impact energy recorded")
    T.near(probe.barrier[1].angle, 0, 1e-9, "level flight: angle 0 from the barrier normal")
    local E = 0.3 * ke0
    local r = run(E, 10)
    T.check(not r.barrier[1].stopped, "a rock above capacity passes")
    T.near(r.crossings[2].ke, ke0 - E, 1e-12, "ke after = ke before - E_cap")
    T.near(r.crossings[2].ke_rot / r.crossings[2].ke, probe.crossings[1].ke_rot / ke0, 1e-12,
        "E_cap taken from translation and rotation in proportion")
    T.near(r.barrier_absorbed, E, 1e-12, "absorbed energy booked in the record")
    local over = run(1e30, 0.5) -- passing height 1 - 0.2 = 0.8 m > 0.5 m: flies over
    T.check(not over.barrier[1].stopped and over.barrier[1].over, "a rock above the barrier flies over")
    T.near(over.crossings[2].ke, ke0, 1e-12, "flying over keeps the energy")
    T.check(over.stop == "left", "leaving the profile end ends the rock (got " .. tostring(over.stop) .. ")")
end

-- ---------------------------------------------------------------- impact table vs closed form
do
    -- No gravity: a ball hits the floor at vn = -4 m/s (and vt = 1.5 m/s) and flies off. A
    -- linear spring-dashpot in full mode has e = exp(-pi beta / sqrt(1 - beta^2)) for a contact
    -- that lasts until the overlap is back to zero. The impact table reads the velocity the body
    -- keeps after the first step without overlap; the force of the last step in contact (the
    -- dashpot pulling, c udot with c / m = 2 beta omega) acted for a whole step dt instead of
    -- the fraction left until separation, so |Rn - e| <= 2 beta omega dt e. With
    -- `resolution` steps per contact duration pi / (omega sqrt(1 - beta^2)) that bound is
    -- 2 pi beta / (resolution sqrt(1 - beta^2)) e: 0.2% at beta = 0.3 with 1000 steps (at the
    -- default 30 the apparent Rn is about 1% above e).
    local res = 1000
    for _, beta in ipairs({ 0.1, 0.3, 0.5 }) do
        local m = { model = "linear", props = { kn = 1e7, ks = 1e-9, fric = 0, dp_nratio = beta, dp_mode = "full" } }
        local an = rf.analysis{ profile = { {0, 0}, {10, 0} }, materials = { floor = m }, gravity = {0, 0},
            seeders = { { at = {2, 0.5}, vx = 1.5, vy = -4, rock = { shape = "ball", radius = 0.1 } } },
            t_max = 0.5, seed = 3, timestep = { resolution = res } }
        local r = rf.run_rock(an, 1)
        T.check(#r.impacts == 1, "one impact (got " .. #r.impacts .. ")")
        local im = r.impacts[1]
        local e = math.exp(-math.pi * beta / math.sqrt(1 - beta * beta))
        T.near(im.vn_in, -4, 1e-12, "vn_in")
        T.near(im.vt_in, 1.5, 1e-12, "vt_in")
        local bound = 2 * math.pi * beta / (res * math.sqrt(1 - beta * beta)) * e
        T.near(im.rn, e, bound, "Rn vs the dashpot closed form, beta = " .. beta)
        T.near(im.rt, 1, 1e-6, "frictionless: Rt = 1")
        T.check(im.material == "floor", "material of the impact")
        T.near(im.energy_lost, 0.5 * r.mass * 16 * (1 - im.rn ^ 2), 1e-6 * r.mass * 8, "energy lost")
        T.check(r.stop == "time", "time cap")
    end
end

-- ---------------------------------------------------------------- rest and left
do
    local an = rf.analysis{ profile = { {0, 0}, {10, 0} }, materials = { floor = lin },
        seeders = { { at = {5, 1}, rock = { shape = "ball", radius = 0.1 } } }, t_max = 30, seed = 1 }
    local r = rf.run_rock(an, 1)
    T.check(r.stop == "rest", "a dropped ball comes to rest (got " .. tostring(r.stop) .. ")")
    T.near(r.end_y, 0.1, 0.01, "at rest on the floor (overlap under its weight < 1 cm)")
    T.check(r.t_end < 30, "before the time cap")
    local left = rf.analysis{ profile = { {0, 0}, {10, 0} }, materials = { floor = lin }, gravity = {0, 0},
        seeders = { { at = {5, 1}, vx = -2, rock = { shape = "ball", radius = 0.1 } } }, seed = 1 }
    local l = rf.run_rock(left, 1, { trajectory = true })
    T.check(l.stop == "left" and l.end_x < 0, "left over the profile's start")
    T.check(#l.path >= 2 and l.path[1][2] == 5, "trajectory recorded from the release")
end

-- ---------------------------------------------------------------- seeder distributions
do
    -- N draws; a sample mean lies within 4 standard errors sigma / sqrt(N) of the mean with
    -- probability 0.99994, and the seed is fixed, so the check is deterministic and not loose.
    local N = 4000
    local an = rf.analysis{ profile = flat, materials = { s = lin }, seed = 11,
        seeders = { { kind = "line", from = {10, 20}, to = {30, 30},
            vx = { dist = "uniform", min = 1, max = 3 },
            vy = { dist = "normal", mean = 0, sd = 1, min = -1, max = 2 },
            spin = { dist = "lognormal", mean = 2, sd = 0.5 },
            rock = { shape = "ball", radius = 0.1 } } } }
    local sx, svx, svy, ssp, ssp2 = 0, 0, 0, 0, 0
    local lo, hi = math.huge, -math.huge
    for i = 1, N do
        local rel = rf.sample(an, i).release
        sx, svx, svy, ssp = sx + rel.x, svx + rel.vx, svy + rel.vy, ssp + rel.spin
        ssp2 = ssp2 + rel.spin ^ 2
        lo, hi = math.min(lo, rel.vy), math.max(hi, rel.vy)
        T.check(rel.vx >= 1 and rel.vx <= 3, "uniform within its range")
        T.near((rel.y - 20) / (rel.x - 10), 0.5, 1e-9, "on the seeder line (round-off near the line start)")
    end
    T.near(sx / N, 20, 4 * (20 / math.sqrt(12)) / math.sqrt(N), "position uniform along the line: mean")
    T.near(svx / N, 2, 4 * (2 / math.sqrt(12)) / math.sqrt(N), "uniform mean")
    -- Truncated normal on [a, b] = [-1, 2]: mean = (phi(a) - phi(b)) / (Phi(b) - Phi(a)).
    local function phi(z) return math.exp(-z * z / 2) / math.sqrt(2 * math.pi) end
    local function Phi(z) -- Abramowitz-Stegun 7.1.26 erf, error < 1.5e-7
        local x = math.abs(z) / math.sqrt(2)
        local t = 1 / (1 + 0.3275911 * x)
        local y = 1 - (((((1.061405429 * t - 1.453152027) * t) + 1.421413741) * t - 0.284496736) * t + 0.254829592) * t * math.exp(-x * x)
        return z >= 0 and 0.5 * (1 + y) or 0.5 * (1 - y)
    end
    local tmean = (phi(-1) - phi(2)) / (Phi(2) - Phi(-1))
    T.near(svy / N, tmean, 4 * 1 / math.sqrt(N), "truncated normal mean")
    T.check(lo >= -1 and hi <= 2 and lo < -0.95 and hi > 1.9, "truncated normal fills [min, max]")
    T.near(ssp / N, 2, 4 * 0.5 / math.sqrt(N), "lognormal mean (given as the variable's mean)")
    local sd = math.sqrt(ssp2 / N - (ssp / N) ^ 2)
    -- The sd of a sample sd is about sd sqrt((kurtosis - 1) / (4 N)); lognormal with cv 0.25 has
    -- excess kurtosis ~1.1, so 4 standard errors are about 0.05 sd.
    T.near(sd, 0.5, 0.05 * 0.5, "lognormal sd")
    -- Mass given: the size follows at the density; volume and r_eq are consistent.
    local an2 = rf.analysis{ profile = flat, materials = { s = lin }, seed = 4,
        seeders = { { at = {50, 5}, rock = { { shape = "three_balls", mass = 1000 }, { shape = "fitted", L1 = 2, L2 = 0.8, mass = 900 },
            { shape = "ngon", n = 5, volume = 0.4 } } } } }
    local seen = {}
    for i = 1, 30 do
        local s = rf.sample(an2, i)
        seen[s.rock.shape] = s.rock
    end
    T.near(seen.three_balls.mass, 1000, 1e-12, "An (2006) rock scaled to its mass")
    T.check(rf.shapes.thesis_a == rf.shapes.three_balls, "the older name of the shape still works")
    T.near(seen.fitted.mass, 900, 1e-12, "fitted rock: the mass sets the density")
    T.near(seen.fitted.density * seen.fitted.volume, 900, 1e-12, "fitted: density x area")
    T.near(seen.ngon.volume, 0.4, 1e-12, "n-gon scaled to its volume")
    -- The Lua union area against the engine's exact one.
    local m = talus.model{}
    for _, name in ipairs({ "three_balls", "ngon", "fitted" }) do
        local geom = rf.shapes[name]({ L1 = 2, L2 = 0.8, n = 7 })
        local t = m:clump_template{ pebbles = geom }
        T.near(rf.union_area(geom), t.area, 1e-12, "union area of " .. name)
    end
    -- A rock seeded below the slope is lifted to clear it.
    local an3 = rf.analysis{ profile = flat, materials = { s = lin }, seeders = { { at = {50, -3}, rock = { shape = "ball", radius = 0.5 } } } }
    local s3 = rf.sample(an3, 1)
    T.check(s3.lifted and s3.release.y >= 0.5, "lifted above the surface")
end

-- ---------------------------------------------------------------- zones and seeder weights
do
    -- Per-segment material names; and x ranges that cut a segment (a vertex is inserted there).
    local pts = { {0, 10}, {4, 6}, {10, 6}, {14, 0} }
    local a = rf.analysis{ profile = pts, materials = { hard = lin, soft = lin }, zones = { "hard", "soft", "hard" },
        seeders = { { at = {1, 11} } } }
    T.check(#a.nominal == 4 and a.segment_material[2] == "soft" and a.segment_material[3] == "hard", "zones per segment")
    local b = rf.analysis{ profile = pts, materials = { hard = lin, soft = lin },
        zones = { { material = "hard", x_from = 0, x_to = 7 }, { material = "soft", x_from = 7, x_to = 14 } },
        seeders = { { at = {1, 11} } } }
    T.check(#b.nominal == 5 and b.nominal[3][1] == 7 and b.nominal[3][2] == 6, "vertex inserted at the zone boundary")
    T.check(b.segment_material[2] == "hard" and b.segment_material[3] == "soft", "materials on both sides of it")
    -- Two seeders with weights 1 and 3: the share of the second is 3/4; N = 2000 draws give a
    -- binomial standard error sqrt(p (1 - p) / N) = 0.0097; 4 of them.
    local c = rf.analysis{ profile = flat, materials = { s = lin }, seed = 21,
        seeders = { { name = "one", at = {10, 5}, weight = 1 }, { name = "two", at = {20, 5}, weight = 3 } } }
    local k = 0
    for i = 1, 2000 do if rf.sample(c, i).seeder == "two" then k = k + 1 end end
    T.near(k / 2000, 0.75, 4 * math.sqrt(0.75 * 0.25 / 2000), "seeder weights")
end

-- ---------------------------------------------------------------- roughness
do
    local pts = { {0, 10}, {3, 9}, {5, 5}, {8, 4}, {12, 0} }
    local a = rf.roughen(pts, 0.1, 12345)
    local b = rf.roughen(pts, 0.1, 12345)
    local c = rf.roughen(pts, 0.1, 12346)
    local differs, maxoff = false, 0
    for k = 1, #pts do
        T.check(a[k][1] == b[k][1] and a[k][2] == b[k][2], "same seed, same vertex " .. k)
        if a[k][1] ~= c[k][1] then differs = true end
        maxoff = math.max(maxoff, math.sqrt((a[k][1] - pts[k][1]) ^ 2 + (a[k][2] - pts[k][2]) ^ 2))
    end
    T.check(differs, "another seed, another profile")
    T.check(maxoff <= 0.1 and maxoff > 0.01, "offsets bounded by the amplitude (max " .. maxoff .. ")")
    T.check(a[1][1] == 0 and a[1][2] == 10 and a[5][1] == 12 and a[5][2] == 0, "end points kept")
    local an = rf.analysis{ profile = pts, materials = { s = lin }, roughness = { amplitude = 0.05, spacing = 0.5 },
        seeders = { { at = {1, 12} } }, seed = 9 }
    local p1, p1b, p2 = rf.sample(an, 1).points, rf.sample(an, 1).points, rf.sample(an, 2).points
    T.check(#p1 > 20, "refined to the spacing")
    local same12, worst = true, 0
    for k = 1, #p1 do
        T.check(p1[k][1] == p1b[k][1] and p1[k][2] == p1b[k][2], "rock 1's profile reproducible")
        if p1[k][2] ~= p2[k][2] then same12 = false end
        local d = math.abs(p1[k][2] - rf.ground(pts, p1[k][1]))
        worst = math.max(worst, d)
    end
    T.check(not same12, "each rock meets its own roughness")
    -- A vertex moved by <= A perpendicular to the slope moves <= A / cos(slope) vertically; the
    -- steepest segment here is 63 deg (1/cos = 2.24).
    T.check(worst <= 0.05 * 2.25, "rough profile within the amplitude of the nominal one")
end

-- ---------------------------------------------------------------- mass release
do
    local an = rf.analysis{ profile = { {0, 3}, {3, 0}, {20, 0} }, materials = { s = lin },
        rock_contact = { model = "linear", props = { kn = 1e7, ks = 5e6, fric = 0.5, dp_nratio = 0.3 } },
        seeders = { { kind = "line", from = {0.4, 3.5}, to = {1.6, 3.5}, rock = { shape = "ball", radius = 0.1 } } },
        collectors = { { name = "c", x = 4 } }, seed = 2, t_max = 20 }
    local recs = rf.mass_release(an, { n = 4 })
    T.check(#recs == 4, "one record per rock")
    for i, r in ipairs(recs) do
        T.check(r.rock == i and r.stop ~= nil and r.end_x ~= nil, "record " .. i .. " complete")
    end
end

-- ---------------------------------------------------------------- bad input
do
    local script = T.script()
    local base = function(extra)
        local o = { profile = flat, materials = { s = lin }, seeders = { { at = {1, 1} } } }
        for k, v in pairs(extra) do o[k] = v end
        return o
    end
    local line = T.line() + 1
    T.fails(function() rf.analysis(base{ bogus = 1 }) end, { script .. ":" .. line .. ":", "unknown option 'bogus'" },
        "unknown option names the script line")
    line = T.line() + 1
    T.fails(function() rf.analysis(base{ profile = { {0, 0}, {5, 1}, {4, 2} } }) end,
        { script .. ":" .. line .. ":", "x must not decrease", "point 3" }, "overhanging profile")
    T.fails(function() rf.analysis(base{ profile = { {0, 0} } }) end, { "at least 2 points" }, "one point")
    T.fails(function() rf.analysis(base{ zones = { { material = "s", x_from = 0, x_to = 150 } } }) end,
        { "zones[1]", "outside the profile" }, "zone outside the profile")
    T.fails(function() rf.analysis(base{ zones = { { material = "s", x_from = 0, x_to = 50 } } }) end,
        { "in no zone" }, "profile not covered by zones")
    T.fails(function() rf.analysis(base{ materials = { s = { model = "linear", props = { knn = 1 } } } }) end,
        { "unknown property 'knn'" }, "unknown property")
    T.fails(function() rf.analysis(base{ materials = { s = { model = "nosuchmodel" } } }) end,
        { "nosuchmodel" }, "unknown model")
    T.fails(function() rf.analysis(base{ seeders = { { at = {1, 1}, vx = { dist = "gauss" } } } }) end,
        { "seeders[1].vx", "dist must be" }, "bad distribution")
    T.fails(function() rf.analysis(base{ seeders = { { at = {1, 1}, rock = { shape = "cube" } } } }) end,
        { "unknown shape 'cube'" }, "bad shape")
    local ok_an = rf.analysis(base{})
    line = T.line() + 1
    T.fails(function() rf.run_rock(ok_an, 1, { trajectroy = true }) end,
        { script .. ":" .. line .. ":", "rockfall.run_rock", "unknown option 'trajectroy'" }, "run_rock option typo")
    T.fails(function() rf.run_rock({}, 1) end, { "analysis from rockfall.analysis" }, "not an analysis")
    T.fails(function() rf.monte_carlo(ok_an, { n = 0 }) end, { "n must be an integer >= 1" }, "bad n")
    local csv = os.tmpname()
    local f = assert(io.open(csv, "w"))
    f:write("x,y\n0,10\n5,oops\n")
    f:close()
    T.fails(function() rf.analysis(base{ profile = csv }) end, { csv, "line 3" }, "bad CSV line")
    f = assert(io.open(csv, "w"))
    f:write("x,y\n0,10\n5,4\n# comment\n9,3\n")
    f:close()
    local an = rf.analysis(base{ profile = csv })
    T.check(#an.points == 3 and an.points[3][1] == 9, "CSV profile with header and comment")
    os.remove(csv)
end

T.done("rockfall_workflow")
