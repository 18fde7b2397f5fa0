-- SPDX-License-Identifier: MIT
-- An impact resolved in 2-3 steps with the guard set to "error" stops the run at m:cycle.
local m = talus.model{ gravity = {0, -9.81} }
m:contact_model("linear", { kn = 1e8 })
m:wall{ points = { {-1, 0}, {1, 0} } }
m:ball{ pos = {0, 0.11}, radius = 0.1, density = 2600, vel = {0, -2} }
m:timestep{ fixed = 1e-3 }
m:guard{ resolution = "error" }
m:cycle(100)  -- line 9
