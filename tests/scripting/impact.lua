-- SPDX-License-Identifier: MIT
-- talus.impact and talus.drive against closed forms (the closed form of a linear spring-dashpot and 1.5).
local T = require("testlib")
local dir = arg[1] or "."

-- normal impact, linear spring + dashpot (full mode): e = exp(-pi beta / sqrt(1 - beta^2))
for _, beta in ipairs({ 0.0, 0.2, 0.5 }) do
    local r = talus.impact{ props = { kn = 1e8, ks = 1e8, dp_nratio = beta }, radius = 0.1,
                            density = 2600, speed = 2.0 }
    local e = math.exp(-math.pi * beta / math.sqrt(1 - beta ^ 2))
    T.check(r.separated, "separated")
    T.near(r.restitution, e, 5e-3, "restitution for beta = " .. beta)
    T.near(r.vn_in, 2.0, 1e-12, "vn_in")
    T.near(-r.vn_out / r.vn_in, r.restitution, 1e-12, "restitution = -vn_out / vn_in")
    T.check(r.steps >= 20, "the resolution rule resolves the impact (" .. r.steps .. " steps)")
    local m_eff = 2600 * math.pi * 0.01
    local wd = math.sqrt(1e8 / m_eff) * math.sqrt(1 - beta ^ 2)
    T.near(r.duration, math.pi / wd, 2e-2, "duration = pi / omega_d")
    T.check(type(r.step_rule) == "string" and r.timestep > 0, "step rule and timestep")
    T.check(r.energies.kinetic > 0 and r.energy_in > r.energy_out or beta == 0, "energies")
end

-- oblique impact, gross sliding (Maw, Barber & Fawcett 1976, disk kappa = 1/2, exact for DEM):
-- e_t = 1 - mu (1 + e) / tan(theta), spin R w = mu (1 + e) v cos(theta) / kappa
local mu, theta, v = 0.2, 60, 3.0
local r = talus.impact{ props = { kn = 1e8, ks = 1e8, fric = mu }, radius = 0.1, density = 2600,
                        velocity = v, angle = theta, trace = dir .. "/impact_trace.csv" }
local e = r.restitution
T.near(e, 1.0, 5e-3, "elastic normal restitution")
local th = math.rad(theta)
T.near(r.vt_in, v * math.sin(th), 1e-12, "velocity/angle: tangential part")
T.near(r.tangential_restitution, 1 - mu * (1 + e) / math.tan(th), 5e-3, "sliding: e_t")
-- The spin is ~0.5% below the rigid-body value: the engine's lever arm is the distance to the
-- contact point, R - u, shortened by the overlap (1.4% of R at the peak here).
T.near(math.abs(r.spin_out) * 0.1, mu * (1 + e) * v * math.cos(th) / 0.5, 1e-2, "sliding: spin")
T.check(r.rebound_angle > 0 and r.rebound_angle < 90, "rebound angle in degrees")
local f = assert(io.open(dir .. "/impact_trace.csv"))
T.check(f:read("l") == "time,overlap,normal_force,shear_force,moment", "trace CSV header")
f:close()

local rt = talus.impact{ props = { kn = 1e7 }, speed = 1, trace = true, target = "ball",
                         mass = "sphere" }
T.check(#rt.trace.time > 10 and #rt.trace.time == #rt.trace.normal_force, "trace = true")
T.near(rt.restitution, 1.0, 5e-3, "elastic ball-ball")

-- drive: the linear law is Fn = kn u, no tension; knest = kn (no dashpot). On the first contact
-- step the model adds the impulse its spring missed at touch (talus/sdk/corners.hpp):
-- (kn rate dt / 2)(lead - 1/2)^2, here lead = 1 (touch at the start of the step).
local overlap = {}
for i = 1, 21 do overlap[i] = (i <= 11) and (i - 1) * 1e-4 or (21 - i) * 1e-4 end
overlap[22] = -1e-4
local d = talus.drive{ props = { kn = 5e6, ks = 1e6, fric = 0.5 }, overlap = overlap, dt = 1e-5 }
for i = 1, #overlap do
    -- corners: touch at the start of step 2, separation at the end of step 21 (u = 0)
    local corner = (i == 2 or i == 21) and 0.5 * 5e6 * (1e-4 / 1e-5) * 1e-5 * 0.25 or 0
    if i ~= #overlap then
        T.near(d.normal_force[i], 5e6 * math.max(overlap[i], 0) + corner, 1e-9,
               "drive: Fn = kn u at " .. i)
    end
end
T.near(d.knest[5], 5e6, 0, "drive: knest")
T.near(d.strain, 0, 1e-12, "drive: no strain after unloading")

-- errors
T.fails(function() talus.impact{ speed = 1, angle = 30, velocity = 1 } end,
    { "impact: give either speed/tangential or velocity/angle" }, "both speed forms")
T.fails(function() talus.impact{ props = { kn = 1e8 }, target = "rock" } end,
    { "impact: 'target' must be one of \"wall\", \"ball\" (got \"rock\")" }, "target enum")
T.fails(function() talus.impact{ props = { kn = 1e8 }, radius = -1 } end,
    { "impact: radius and density must be > 0" }, "core validation")
T.done("impact")
