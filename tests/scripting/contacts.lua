-- SPDX-License-Identifier: MIT
-- Contacts from Lua: listing, fields, model properties, force writes, filters, stale contacts.
local T = require("testlib")

local m = talus.model{ gravity = {0, -9.81} }
m:contact_model("linear", { kn = 1e6, ks = 5e5, fric = 0.4 })
m:contact_model("linear", { kn = 2e6, ks = 1e6, fric = 0.7 }, { groups = {"a", "b"} })
local floor = m:wall{ points = { {-5, 0}, {0, 0}, {5, 0} }, group = "floor" }
-- b1 rests on the floor's second segment with an overlap; b2 overlaps b1 from above
local b1 = m:ball{ pos = {1, 0.09}, radius = 0.1, density = 1000, group = "a" }
local b2 = m:ball{ pos = {1, 0.27}, radius = 0.1, density = 1000, group = "b" }
m:timestep{ fixed = 1e-6 }
m:cycle(1)

local list = {}
for c in m:contacts() do list[#list + 1] = c end
T.check(#list == 2, "two active contacts")
T.check(m:contact_count() == 2, "contact_count")

local wall_c, ball_c
for _, c in ipairs(list) do
    if c.wall then wall_c = c else ball_c = c end
end
T.check(wall_c and ball_c, "one ball-wall and one ball-ball contact")

-- ball-wall: end 1 is the ball, end 2 the wall (segment 2 of the chain, 1-based)
T.check(wall_c.ball1 == b1 and wall_c.ball2 == nil and wall_c.wall == floor, "ball-wall ends")
T.check(wall_c.segment == 2, "segment index (1-based)")
T.near(wall_c.overlap, 0.01, 1e-6, "ball-wall overlap")
T.check(wall_c.active and wall_c.model == "linear", "active, model name")
T.near(math.abs(wall_c.normal[2]), 1, 1e-12, "normal is vertical")
T.near(wall_c.normal_force, 1e6 * wall_c.overlap, 1e-6, "Fn = kn u (default rule)")
T.near(wall_c:prop("kn"), 1e6, 0, "prop kn (default rule)")
T.near(wall_c:prop("fric"), 0.4, 0, "prop fric")

-- ball-ball: the rule for groups a-b applies
T.check(ball_c.ball1 == b1 and ball_c.ball2 == b2 and ball_c.wall == nil, "ball-ball ends")
T.near(ball_c:prop("kn"), 2e6, 0, "group rule kn")
T.near(ball_c.overlap, 0.02, 1e-6, "ball-ball overlap")
T.near(ball_c.point[2], 0.18, 1e-6, "contact point between the centres")

-- property write and read back, integer mode by name, all properties
ball_c:set_prop("fric", 0.25)
T.near(ball_c:prop("fric"), 0.25, 0, "set_prop fric")
ball_c:set_prop("dp_mode", "no_tension")
T.near(ball_c:prop("dp_mode"), 1, 0, "dp_mode by name")
local props = ball_c:props()
T.near(props.kn, 2e6, 0, "props().kn"); T.check(props.lin_fn ~= nil, "props() has state")

-- force write (PFC "contact force" write) and read back
wall_c.normal_force = 123.5
T.near(wall_c.normal_force, 123.5, 0, "write normal_force")
wall_c.shear_force = -7
T.near(wall_c.shear_force, -7, 0, "write shear_force")
T.near(wall_c.normal_force, 123.5, 0, "shear write keeps normal force")

-- filters
local n = 0
for c in m:contacts{ ball = b2 } do n = n + 1; T.check(c == ball_c, "filter by ball") end
T.check(n == 1, "contacts{ball = b2}")
n = 0
for _ in m:contacts{ model = "LINEAR" } do n = n + 1 end
T.check(n == 2, "contacts{model} (case-insensitive)")
n = 0
for _ in m:contacts{ active = false } do n = n + 1 end
T.check(n >= 2, "contacts{active = false} includes the candidates")

-- errors
T.fails(function() return ball_c.force end, { "contact: unknown field 'force' (known: key, ball1" },
    "unknown field")
T.fails(function() ball_c:prop("knn") end,
    { "contact: unknown property 'knn' for model 'linear'; did you mean 'kn'? (known: kn, ks, fric" }, "unknown prop")
T.fails(function() ball_c:set_prop("lin_fn", 1) end, { "read-only" }, "read-only prop")
T.fails(function() ball_c.overlap = 1 end, { "contact: field 'overlap' is read-only" }, "read-only")

-- separate the balls: the contact ends and its userdata says so
local key = ball_c.key
b2.pos = {1, 5}
b2.vel = {0, 0}
m:cycle(2)
T.check(ball_c.key == key, "the key stays readable")
T.fails(function() return ball_c.normal_force end, { "contact of balls 1 and 2 no longer exists" },
    "ended contact")
T.done("contacts")
