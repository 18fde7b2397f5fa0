-- m:broadphase{margin = 1e-320} made the float broadphase
-- tree's coordinates infinite (scale 0.1 / margin), no contact was ever found and the ball fell
-- through the floor. Such a margin is refused now; the smallest accepted one still finds the
-- floor.
local T = require("testlib")

local function drop(margin)
    local m = talus.model{ gravity = {0, -9.81} }
    m:contact_model("linear", { kn = 1e6 })
    m:wall{ points = {{-1, 0}, {1, 0}} }
    local b = m:ball{ pos = {0, 0.2}, radius = 0.05, density = 2600 }
    m:broadphase{ margin = margin }
    m:cycle(2000)
    return b.pos[2]
end

local line = T.line() + 1
T.fails(function() drop(1e-320) end, { T.script() .. ":", "broadphase: margin must be 0",
    "(got 9.99989e-321)" }, "a subnormal margin")
T.fails(function() drop(1e-10) end, { "broadphase: margin" }, "below 1e-9 m")
T.fails(function() drop(1e10) end, { "broadphase: margin" }, "above 1e9 m")
-- Accepted extremes: the ball (radius 0.05) must stand on the floor, never below it. The
-- static overlap is m g / kn = 20.4 * 9.81 / 1e6 = 0.2 mm; after 2000 steps it still bounces,
-- so the check is only that it has not passed through (centre above 0.045 m).
for _, mg in ipairs{ 1e-9, 0.0025, 0 } do
    local y = drop(mg)
    T.check(y > 0.045, string.format("margin %g: the ball fell through the floor (y = %g)", mg, y))
end
T.done("input_margin")
