-- SPDX-License-Identifier: MIT
-- Free fall from Lua: central differences put every position exactly on the parabola, for the
-- fixed step and for the automatic step sequence alike (the engine's claim in timestep.cpp).
local T = require("testlib")

local g = 9.81
for _, mode in ipairs({ "fixed", "auto" }) do
    local m = talus.model{ gravity = {0, -g} }
    local x0, y0, vx0, vy0 = 1.0, 50.0, 2.0, 3.0
    local b = m:ball{ pos = {x0, y0}, radius = 0.1, density = 2600, vel = {vx0, vy0} }
    if mode == "fixed" then
        m:timestep{ fixed = 1e-3 }
    else
        m:timestep{ max = 0.01 }
    end
    local steps = 0
    for _ = 1, 20 do
        m:cycle(37)
        steps = steps + 37
        local t = m:time()
        local p = b.pos
        T.near(p[1], x0 + vx0 * t, 1e-12, mode .. " x at t = " .. t)
        T.near(p[2], y0 + vy0 * t - 0.5 * g * t * t, 1e-12, mode .. " y at t = " .. t)
        -- ball.vel is the half-step velocity v(t - dt/2)
        local dt = m:dt()
        T.near(b.vel[2], vy0 - g * (t - 0.5 * dt), 1e-12, mode .. " vy at t - dt/2")
        T.near(b.vel[1], vx0, 1e-14, mode .. " vx")
    end
    T.check(m:step() == steps, "step count")
    if mode == "fixed" then
        T.near(m:time(), steps * 1e-3, 1e-12, "fixed: time = steps * dt")
        local dt, rule = m:dt()
        T.check(dt == 1e-3 and rule == "fixed", "fixed: m:dt() returns the step and its rule")
    end
end

-- solve{time} lands exactly on the requested time
local m = talus.model{ gravity = {0, -g} }
local b = m:ball{ pos = {0, 0}, radius = 0.1, mass = 2.0 }
m:solve{ time = 0.75 }
T.near(m:time(), 0.75, 1e-12, "solve lands on the time")
T.near(b.pos[2], -0.5 * g * 0.75 ^ 2, 1e-12, "solve: y(0.75)")
T.near(b.mass, 2.0, 0, "mass given directly")
T.near(b.density, 2.0 / (math.pi * 0.01), 1e-12, "density follows from the mass (disk)")
T.done("free_fall")
