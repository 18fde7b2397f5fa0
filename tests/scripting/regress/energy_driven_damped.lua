-- SPDX-License-Identifier: MIT
-- Work booked for viscous damping of spin and for fixed (driven) velocity components.
local T = require("testlib")

-- 1. A spinning ball with mass-proportional viscous damping: every joule of rotational kinetic
-- energy lost is damping work. Tolerance: the balance closes to second order in the step
-- (docs/physics/energy.md); at c dt = 0.01 that is ~1e-5 of the input, so 1e-4 is a bound.
do
    local m = talus.model{}
    m:damping{ viscous = 10 }
    local b = m:ball{ pos = {0, 0}, radius = 0.1, density = 1000, spin = 100 }
    m:energy{ on = true }
    m:timestep{ fixed = 1e-3 }
    m:cycle(100)
    local e = m:energies()
    T.check(b.spin < 40, "spin decays")
    T.near(e.damping, e.initial_kinetic - e.kinetic, 1e-4 * e.initial_kinetic, "spin damping work")
    T.check(math.abs(e.balance_error) < 1e-4 * e.initial_kinetic, "viscous spin balance " .. e.balance_error)
end

-- 2. A driven ball (x and y fixed, 1 m/s) pushes a free one of equal size: an elastic collision
-- with an infinitely heavy piston sends the free ball off at twice the piston's speed, and the
-- work the drive did is the kinetic energy gained, m_B (2 v)^2 / 2 - m_B 0 = 2 m_B v^2.
do
    local m = talus.model{}
    m:contact_model("linear", { kn = 1e6 })
    local a = m:ball{ pos = {0, 0}, radius = 0.1, density = 1000, vel = {1, 0}, fix = {"x", "y"} }
    local b = m:ball{ pos = {0.25, 0}, radius = 0.1, density = 1000 }
    m:energy{ on = true }
    m:cycle(3000)
    local e = m:energies()
    local mb = b.mass
    T.near(a.vel[1], 1.0, 1e-15, "piston keeps its speed")
    -- restitution of a resolved linear impact is within 1e-3 (docs/models/linear.md)
    T.near(b.vel[1], 2.0, 2e-3, "free ball leaves at twice the piston speed")
    T.near(e.boundary, 0.5 * mb * b.vel[1]^2, 1e-6 * e.initial_kinetic, "drive work = kinetic energy gained by B")
    T.check(math.abs(e.balance_error) < 1e-5 * (e.initial_kinetic + e.boundary), "piston balance " .. e.balance_error)
end

-- 3. Fixed spin with an applied moment and local damping: the moment's work is taken back by the
-- fixity (boundary), no damping is booked on a fixed component, kinetic energy stays.
for _, alpha in ipairs({0, 0.5}) do
    local m = talus.model{}
    m:damping{ damp = alpha }
    local b = m:ball{ pos = {0, 0}, radius = 0.1, density = 1000, spin = 10, fix = {"spin"} }
    b.mapp = 100
    m:energy{ on = true }
    m:timestep{ fixed = 1e-3 }
    m:cycle(1000)
    local e = m:energies()
    T.near(b.spin, 10, 0, "fixed spin stays")
    T.near(e.body, 100 * 10 * 0.999, 1e-9, "applied moment work")
    T.near(e.boundary, -e.body, 1e-9, "fixity takes the moment's work back")
    T.near(e.damping, 0, 1e-12, "no damping on a fixed component")
    T.check(math.abs(e.balance_error) < 1e-9 * e.initial_kinetic, "fixed spin balance")
end
print("energy_driven_damped: " .. T.checks .. " checks passed")
