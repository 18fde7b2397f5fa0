-- SPDX-License-Identifier: MIT
-- `rrlinear` through the Lua API, as a rockfall script uses it: a rolling-resistance rule for
-- rock-bench contacts, a round rock rolling on a flat bench, energy traced. The rock stops
-- after the distance the rolling friction gives (docs/models/rrlinear.md):
--   d = v0^2 (1 + kappa) / (2 rr_fric g),  kappa = I / (m R^2)
-- (point-mass run-out v0^2 / (2 g tan(beta)) times 1 + kappa: the rotational energy has to go
-- too), for a disk (kappa = 1/2) and a sphere (mass = "sphere", kappa = 2/5); the rolling slip
-- is booked as slip and the balance closes.
local T = require("testlib")

local g, R, rho, kn, ks, v0 = 9.81, 0.25, 2600, 1e9, 1e9, 3.0

local function roll(mass_mode, kappa, mu_r)
    local m = talus.model{ gravity = {0, -g}, mass = mass_mode }
    -- The bench's rule, by group, as a material zone of a slope would have it.
    m:contact_model("rrlinear", { kn = kn, ks = ks, fric = 0.6, rr_fric = mu_r, dp_nratio = 0.3,
        dp_sratio = 0.3 }, { groups = { "rock", "bench" } })
    m:wall{ points = {{-1, 0}, {10, 0}}, group = "bench" }
    local b = m:ball{ pos = {0, R}, radius = R, density = rho, group = "rock" }
    m:cycle(2000)  -- settle on the normal spring (damped)
    local u = R - b.pos[2]
    local l = R - u / 2
    local x0 = b.pos[1]
    b.vel = {v0, 0}
    b.spin = -v0 / l
    m:energy{ on = true }
    local far = x0
    while b.vel[1] > 0 and m:time() < 10 do
        m:cycle(1)
        far = b.pos[1]
    end
    local dist = far - x0
    -- The rigid form, l = R: the lever arm l = R - u/2 (u/R = 1e-5: a 3e-6 effect) and half
    -- the elastic rotation (rr_fric m g / (2 ks) = 1e-6 m) are below the bound, 5e-5; so is the
    -- start, a velocity set between cycles being the next half step's (up to v0 dt / 2 =
    -- 6e-5 m). Measured +2.5e-5 (disk) and +1.6e-5 (sphere).
    local d = v0 * v0 * (1 + kappa) / (2 * mu_r * g)
    T.near(dist / d, 1, 5e-5, mass_mode .. ": stop distance / closed form")
    local c = m:contacts{}()
    T.near(c:prop("rr_kr"), ks * R * R, 1e-12, mass_mode .. ": rr_kr = ks R^2")
    T.check(math.abs(c:prop("rr_moment")) <= mu_r * R * c:prop("lin_fn") * (1 + 1e-12),
        mass_mode .. ": |rr_moment| <= rr_fric R F_n")
    local e = m:energies()
    local ke0 = 0.5 * b.mass * v0 * v0 * (1 + b.inertia / (b.mass * l * l))
    -- The rolling slip took the kinetic energy (the shear dashpot a little of the start-up).
    T.check(e.slip > 0.99 * ke0 and e.slip <= ke0, mass_mode .. ": rolling slip booked as slip")
    -- Second order in the step (1e-5 measured); bound 1e-4.
    T.near(e.balance_error / e.input, 0, 1e-4, mass_mode .. ": energy balance / input")
    return dist, d
end

local dd, cd = roll("disk", 0.5, 0.3)
local ds, cs = roll("sphere", 0.4, 0.3)
print(string.format("rrlinear_rolling: disk %.6f m (closed form %.6f), sphere %.6f m (%.6f)",
    dd, cd, ds, cs))
-- A lumped-mass rolling friction tan(beta) (STONE, STONE, Guzzetti et al. 2002: bedrock 0.30) stops a
-- point mass after v0^2 / (2 g tan(beta)); rr_fric = (1 + kappa) tan(beta) gives a round rock
-- the same run-out (the bench check).
local tan_beta = 0.30
local db = roll("disk", 0.5, 1.5 * tan_beta)
T.near(db / (v0 * v0 / (2 * g * tan_beta)), 1, 5e-5,
    "disk, rr_fric = 1.5 tan(beta): v0^2/(2 g tan(beta))")
print(string.format("rrlinear_rolling: disk, rr_fric = 1.5 x 0.30: %.6f m "
    .. "(v0^2/(2 g tan beta) = %.6f)", db, v0 * v0 / (2 * g * tan_beta)))

T.fails(function() talus.model{}:contact_model("rrlinear", { rr_fric = -0.1 }) end,
    { "rrlinear: 'rr_fric' must be >= 0", "got -0.1" }, "negative rr_fric refused")
local info = talus.contact_model_info("rrlinear")
local names = {}
for _, p in ipairs(info.properties) do names[p.name] = p end
T.check(names.rr_fric and not names.rr_fric.read_only, "rr_fric is settable")
T.check(names.rr_moment and names.rr_moment.read_only and names.rr_slip.read_only,
    "rr_moment and rr_slip are read-only state")
T.done("rrlinear_rolling")
