-- SPDX-License-Identifier: MIT
-- A servo wall compresses a pack of 100 balls in a box to a target stress (core/src/step/wall_servo.cpp),
-- and a measurement region over the whole box reads the same stress from the contact forces
-- (core/src/api/measure.cpp). No gravity and no friction, so that the walls carry only normal
-- forces and the box's stress is fixed by them (below).
local T = require("testlib")

local W, SIGMA, KN = 1.0, 1e5, 1e8
local m = talus.model{ gravity = {0, 0} }
m:contact_model("linear", { kn = KN, ks = KN, fric = 0 })
local bottom = m:wall{ points = {{-0.05, 0}, {1.25, 0}} }
local left = m:wall{ points = {{0, -0.05}, {0, 1.3}} }
local right = m:wall{ points = {{1.2, 1.3}, {1.2, -0.05}} }
local top = m:wall{ points = {{-0.05, 1.2}, {1.25, 1.2}} }
-- A loose grid of radii 0.035..0.045 (a fixed sequence, no generator state).
local k = 0
for i = 0, 9 do
    for j = 0, 9 do
        k = k + 1
        local r = 0.035 + 0.01 * ((k * 37) % 11) / 10
        m:ball{ pos = {0.05 + 0.1 * i, 0.05 + 0.1 * j}, radius = r, density = 2600 }
    end
end
m:damping{ damp = 0.7 }
-- Two servo walls, top and right, press the loose grid isotropically into a jammed pack.
local st = top:servo{ stress = SIGMA, length = W, vmax = 0.5 }
T.near(st.dir[2], -1, 0, "the top wall's default direction is down, into the pack")
local sr = right:servo{ stress = SIGMA, length = 1.0, vmax = 0.5 }
T.near(sr.dir[1], -1, 0, "the right wall's default direction is left, into the pack")

-- Run until the servo holds the target and the pack is at rest (ratio, PFC's criterion).
local reason
for _ = 1, 200 do
    reason = m:solve{ ratio = 1e-6, max_steps = 5000 }
    st, sr = top:servo(), right:servo()
    if reason == "ratio" and math.abs(st.stress - SIGMA) < 1e-6 * SIGMA and
        math.abs(sr.stress - SIGMA) < 1e-6 * SIGMA then break end
end
T.check(reason == "ratio", "the pack comes to rest: " .. tostring(reason))
-- 1. The servo: at rest its error decays by (1 - alpha) per step: 1e-6 is reached (the brief
-- asks for 1%).
T.near(st.stress, SIGMA, 1e-6 * SIGMA, "servo stress at the target")
T.near(top.force[2] / W, st.stress, 1e-12 * SIGMA, "the servo reads the reported wall force")

-- 2. Equilibrium of the pack: frictionless walls carry normal forces only; the floor carries
-- the top's load (to the unbalanced force, ratio 1e-6 of a mean contact force).
T.near(bottom.force[2], -top.force[2], 1e-5 * top.force[2], "floor = top")
T.near(left.force[1], -right.force[1], 1e-5 * top.force[2], "left = right")

-- 3. The region's stress. For bodies at rest, sum_balls sum_c (x_c - x_p) (x) F_cp = sum over
-- the wall contacts of x_c (x) F_c (the internal pairs cancel, each ball's net force is zero),
-- so over a box that is the vessel's interior, WR x H:
--   s_yy = -(F_top (H - d_top / 2) - F_bottom d_bottom / 2) / (WR H) = -(F_top / WR)(1 - d / H)
-- with d the mean wall overlap (the contact points lie d/2 inside the walls): ~1e-4 / 0.9.
-- The solid fraction over the balls' area differs from 1/A by the slivers the balls push into
-- the walls (~4e-7 m^2 each, 3e-5 relative) and the unbalanced forces add 1e-6. Tolerance 1e-3.
local H, WR = top.points[1][2], right.points[1][1]
local r = m:measure{ box = {0, 0, WR, H} }
T.check(r.balls == 100, "every ball's centre is in the box")
T.near(r.stress.yy, -top.force[2] / WR, 1e-3 * SIGMA, "region stress yy = - top wall stress")
T.near(r.stress.xx, -right.force[1] / H, 1e-3 * SIGMA, "region stress xx = - side wall stress")
-- The whole tensor against the wall contacts directly: (1/A) sum x_c (x) F_c over the ball-wall
-- contacts (F on the ball: minus the force on end 2). The mean shear stress need not vanish
-- without friction: it is the couple of the walls' off-centre resultants.
local sxx, syy, sxy = 0, 0, 0
for c in m:contacts{} do
    if c.wall and c.overlap > 0 then
        local n, t = c.normal, {-c.normal[2], c.normal[1]}
        local fx = -(c.normal_force * n[1] + c.shear_force * t[1])
        local fy = -(c.normal_force * n[2] + c.shear_force * t[2])
        sxx, syy = sxx + c.point[1] * fx, syy + c.point[2] * fy
        sxy = sxy + 0.5 * (c.point[1] * fy + c.point[2] * fx)
    end
end
local A = WR * H
T.near(r.stress.xx, sxx / A, 1e-4 * SIGMA, "region stress xx = wall contacts' moment")
T.near(r.stress.yy, syy / A, 1e-4 * SIGMA, "region stress yy = wall contacts' moment")
T.near(r.stress.xy, sxy / A, 1e-4 * SIGMA, "region stress xy = wall contacts' moment")
T.check(r.stress.yy < 0, "compression is negative (PFC)")
-- The servo's target, seen by the region: the force SIGMA * length (length 1 m as given) over
-- the current width.
T.near(-r.stress.yy * WR, SIGMA * 1.0, 1e-3 * SIGMA, "region stress x width = servo target force")
T.near(-r.stress.xx * H, SIGMA * 1.0, 1e-3 * SIGMA, "region stress x height = right servo's force")
T.check(r.porosity > 0.1 and r.porosity < 0.6, "porosity in range: " .. r.porosity)
T.check(r.coordination > 2, "coordination: " .. r.coordination)
-- The wall work is booked as boundary work like any moving wall's (energy tracing).
print(string.format("servo_pack: %d steps, %.6f x %.6f m, wall stresses %.9g %.9g Pa, region %.9g %.9g Pa, porosity %.4f, coordination %.3f",
    m:step(), WR, H, top.force[2] / WR, right.force[1] / H, -r.stress.yy, -r.stress.xx, r.porosity, r.coordination))

-- 4. Boundary work: with tracing on, a servo-driven change of target moves the wall, and the
-- energy balance closes (the servo's wall is booked as any moving wall: law_of_motion.cpp).
m:energy{ on = true }
top:servo{ stress = 2 * SIGMA }
right:servo{ stress = 2 * SIGMA }
for _ = 1, 200 do
    reason = m:solve{ ratio = 1e-6, max_steps = 2000 }
    if reason == "ratio" and math.abs(top:servo().stress - 2 * SIGMA) < 1e-6 * SIGMA and
        math.abs(right:servo().stress - 2 * SIGMA) < 1e-6 * SIGMA then break end
end
local e = m:energies()
T.check(e.boundary > 0, "the servo wall did work on the pack: " .. e.boundary)
T.check(math.abs(e.balance_error) < 1e-3 * e.boundary,
    string.format("energy balance closes: error %.3g J of %.3g J boundary work", e.balance_error, e.boundary))

T.done("servo_pack")
