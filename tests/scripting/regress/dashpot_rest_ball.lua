-- SPDX-License-Identifier: MIT
-- A ball resting on a floor with a normal dashpot.
-- The dashpot's rate prediction left gravity out, so at rest it predicted the ball would keep
-- sinking and pulled: the linear spring carried 2.3% more than the weight (dashpot -2.4 N) and the
-- floor reaction read 1.1% above the weight at the default step, 0.09% at a tenth of it. In
-- equilibrium the dashpot force must vanish and the spring carry exactly the weight
-- (core/include/talus/sdk/dashpot.hpp, DashpotHistory).
local T = require("testlib")

local m = talus.model{ gravity = {0, -9.81} }
m:contact_model("linear", { kn = 1e9, ks = 1e9, fric = 0.5, dp_nratio = 0.3 })
local w = m:wall{ points = { {-1, 0}, {1, 0} } }
local b = m:ball{ pos = {0, 0.05}, radius = 0.05, density = 2600 }
local weight = b.mass * 9.81

-- Tolerance: the transient decays at beta omega (omega = 5600 rad/s: e-folding in 0.6 ms), so
-- after 0.5 s only round-off is left (measured 1e-13 of the weight); 1e-9 is 1e7 below the defect.
local tol = 1e-9
local function check(label)
    local c = m:contacts{}()
    T.check(c ~= nil, label .. ": the ball touches the floor")
    T.near(-w.force[2] / weight, 1, tol, label .. ": floor reaction / weight")
    T.near(c:prop("lin_fn") / weight, 1, tol, label .. ": spring force / weight")
    T.near(c:prop("dp_fn") / weight, 0, tol, label .. ": dashpot force / weight")
end

m:solve{ time = 0.5 }      -- the automatic step; the last one is shortened to land on 0.5 s
check("default step")
local dt = m:dt()
m:timestep{ fixed = dt / 10 }
m:solve{ time = 0.05 }
check("a tenth of the step")
T.done("dashpot_rest_ball")
