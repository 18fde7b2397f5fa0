-- SPDX-License-Identifier: MIT
-- A fixed step of 0.01 s for a stiff contact: the ball dropped from 0.5 m met the floor for one
-- step (0.52 steps per contact duration) and left at 20 m/s. With the guard's defaults this is a
-- severe finding: the run stops with an error at the solve line and `talus run` exits non-zero
-- (before: four warnings, the ball ended at y = 7.5 m, exit status 0).
local m = talus.model{ gravity = {0, -9.81} }
m:contact_model("linear", { kn = 1e7, ks = 1e7, fric = 0.5 })
m:wall{ points = {{-5, 0}, {5, 0}} }
m:ball{ pos = {0, 0.5}, radius = 0.1, density = 2600 }
m:timestep{ fixed = 0.01 }
m:solve{ time = 5 } -- line 11
print("not reached")
