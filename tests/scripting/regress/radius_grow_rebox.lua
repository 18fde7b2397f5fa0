-- SPDX-License-Identifier: MIT
-- A ball grown by the script between cycles past its broadphase box (b.radius, as a radius
-- expansion does) must not stop the run: the kinematic rule used to see a room of zero and
-- end with "automatic step became 0 (kinematic rule)" (the material library's genesis). The
-- grown ball's new contact must form in the next cycle, and at rest the floor must carry the
-- weights exactly (equilibrium: wall reaction = total weight).
local T = require("testlib")

local m = talus.model{ gravity = {0, -9.81} }
m:on_warning(function() end)  -- the grown ball starts overlapping (a placement warning)
m:contact_model("linear", { kn = 1e6, ks = 1e6, fric = 0.3, dp_nratio = 0.5 })
m:damping{ ["local"] = 0.7 }
local floor = m:wall{ points = {{-1, 0}, {1, 0}} }
local a = m:ball{ pos = {0, 0.05}, radius = 0.05, density = 2600 }
local b = m:ball{ pos = {0.2, 0.05}, radius = 0.05, density = 2600 }
m:cycle(200)
T.check(m:contact_count() == 2, "two balls on the floor, no contact between them")
-- grow b from 0.05 to 0.16 m: far past the broadphase margin; its centre stays, so it now
-- overlaps the floor by 0.11 m and ball a by 0.01 m
b.radius = 0.16
local ok, err = pcall(function() m:cycle(1) end)
T.check(ok, "the cycle after the growth runs (" .. tostring(err) .. ")")
local touching = false
for c in m:contacts() do
    if c.wall == nil and c.ball2 ~= nil and c.overlap > 0 then touching = true end
end
T.check(touching, "the grown ball's contact with its neighbour formed at once")
m:solve{ ratio = 1e-6, max_steps = 200000 }
local weight = (a.mass + b.mass) * 9.81
T.near(floor.force[2], -weight, 1e-5 * weight, "floor reaction = weight at rest")
print("radius_grow_rebox: " .. T.checks .. " checks passed")
