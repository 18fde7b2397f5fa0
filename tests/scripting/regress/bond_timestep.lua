-- SPDX-License-Identifier: MIT
-- A bond installed by m:bond feeds the time step at once: the host calls the new object's FDlaw
-- at the install, so the stiffness it reports (here 1e5 times the old contact's) sets the very
-- next step's stability limit (docs/plugin-abi.md, "Bonds"). And replacing a loaded contact by a
-- stiffer one at the same force books the change of its stored energy: the balance stays closed.
local T = require("testlib")

local R, RHO = 0.1, 2600
local mass = RHO * math.pi * R * R
local m = talus.model{ gravity = {0, 0} }
m:contact_model("linear", { kn = 1e6, ks = 1e6, fric = 0.5 })
-- Two balls pressed together by opposite applied forces: a loaded contact at rest.
local a = m:ball{ pos = {-R + 5e-4, 0}, radius = R, density = RHO }
local b = m:ball{ pos = {R - 5e-4, 0}, radius = R, density = RHO }
m:on_warning(function() end)  -- the placed overlap is meant
a.fapp = {1e3, 0}
b.fapp = {-1e3, 0}
m:damping{ damp = 0.7 }
m:cycle(3000)
m:energy{ on = true }
m:cycle(2)
local dt_linear = m:dt()
local c = m:contacts{}()
local f0 = c.normal_force
T.near(f0, 1e3, 1e-3, "the contact carries the applied load")

local KN = 1e11
local e0 = m:energies()
T.check(m:bond{ model = "cbond", props = { kn = KN, ks = KN, cb_tenf = math.huge, cb_shearf = math.huge } } == 1, "bonded")
c = m:contacts{}()
-- (to the round-off of u_ref = u - F/kn: u ~ 1e-3 m against F/kn = 1e-7 m, ~1e-12)
T.near(c.normal_force, f0, 1e-9, "the force is kept (adopted) by the stiffer bond")
m:cycle(1)
-- Stability (docs/physics/timestep.md): safety sqrt(m / (kn + ks)) per ball, 0.8 by default.
local stable = 0.8 * math.sqrt(mass / (2 * KN))
T.check(m:dt() <= stable * (1 + 1e-12), "the next step is stable: " .. m:dt() .. " <= " .. stable ..
    " (it was " .. dt_linear .. ")")
T.check(dt_linear > 10 * stable, "the old step would not have been: " .. dt_linear)
-- Energy: the stored energy drops from F^2/2k_old to F^2/2k_new at the same force; the
-- difference is booked to `released`.
local e1 = m:energies()
local expect = 0.5 * f0 * f0 * (1 / 1e6 - 1 / KN)
-- e0's strain is the step before the install's (the contact at rest: the same to 1e-9)
T.near(e1.released - e0.released, expect, 1e-6, "released = F^2/2 (1/k_old - 1/k_new)")
m:cycle(2000)
local e2 = m:energies()
T.check(math.abs(c.normal_force - 1e3) < 1, "the stiff bond holds the load: " .. c.normal_force)
-- Balance: the body work of the applied forces is the only input; the error of the leapfrog
-- with damping over the run stays far below the energy moved (bound 1e-6 of the stored energy
-- before the install, 0.5 J).
T.check(math.abs(e2.balance_error - e0.balance_error) < 1e-6 * e0.strain,
    "balance: " .. e2.balance_error .. " J (before " .. e0.balance_error .. " J)")

T.done("bond_timestep")
