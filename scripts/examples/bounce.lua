-- SPDX-License-Identifier: MIT
--
-- bounce.lua: a ball dropped on a horizontal wall, linear spring with a normal dashpot.
--
--   talus run scripts/examples/bounce.lua [outdir]
--
-- Writes <outdir>/bounce_history.csv (height of the ball's lowest point, vertical velocity and
-- the energies; plot it with scripts/plot_history.py), and prints the restitution of every
-- bounce against the closed form of a linear spring-dashpot:
--     e = exp(-pi beta / sqrt(1 - beta^2)),  beta = dp_nratio
-- (the dashpot acts until the overlap is back to zero: dp_mode "full"). beta is chosen for
-- e = 0.53, "clean hard bedrock" in RocFall's classic default materials.
--
-- How the restitution is measured: between contacts the ball is in free flight, and central
-- differences put its positions exactly on the flight parabola, so the speed at the height
-- where the overlap is zero follows exactly from one step's position and velocity. Gravity
-- also acts *during* the contact; the ODE m u'' + c u' + k u = m g is solved exactly below,
-- so the numerical error is separated from that (small, physical) effect.

local outdir = arg[1] or "out"
talus.mkdir(outdir)

local g = 9.81
local R, density, drop = 0.1, 2600, 1.0   -- radius [m], [kg/m^3], drop height of the lowest point [m]
local kn = 1e7                             -- [N/m]
local e_target = 0.53
local beta = -math.log(e_target) / math.sqrt(math.pi ^ 2 + math.log(e_target) ^ 2)
local e_closed = math.exp(-math.pi * beta / math.sqrt(1 - beta ^ 2))

local m = talus.model{ gravity = {0, -g}, mass = "disk" }
m:contact_model("linear", { kn = kn, ks = kn / 2, fric = 0.5, dp_nratio = beta, dp_mode = "full" })
m:wall{ points = { {-1, 0}, {1, 0} } }
local ball = m:ball{ pos = {0, R + drop}, radius = R, density = density }
m:energy{ on = true }
local mass = ball.mass

local history = m:history{
    file = outdir .. "/bounce_history.csv", every = 5,
    columns = {
        "time",
        { "height", function() return ball.pos[2] - R end },
        { "vy", function() return ball.vel[2] end },
        "kinetic", "strain", "dashpot", "body", "balance_error",
    },
}

--- Exact restitution of the normal impact with gravity during the contact (overlap u >= 0,
--- u'' + 2 gamma u' + w0^2 u = g, u(0) = 0, u'(0) = v): integrate the closed form to u = 0.
local function restitution_with_gravity(v)
    local w0 = math.sqrt(kn / mass)
    local gamma = beta * w0
    local wd = w0 * math.sqrt(1 - beta ^ 2)
    local us = g / w0 ^ 2                    -- static overlap
    local a, b = -us, (v - gamma * us) / wd
    local function u(t) return us + math.exp(-gamma * t) * (a * math.cos(wd * t) + b * math.sin(wd * t)) end
    local function du(t)
        local ex = math.exp(-gamma * t)
        return ex * ((-gamma * a + wd * b) * math.cos(wd * t) + (-gamma * b - wd * a) * math.sin(wd * t))
    end
    -- first root after the turning point: u > 0 up to about pi / wd
    local lo, hi = 0.5 * math.pi / wd, 0.5 * math.pi / wd
    while u(hi) > 0 do lo, hi = hi, hi + 0.05 * math.pi / wd end
    for _ = 1, 200 do
        local mid = 0.5 * (lo + hi)
        if u(mid) > 0 then lo = mid else hi = mid end
    end
    return -du(hi) / v
end

-- Speed at the height of first touch (lowest point at y = 0), from the free-flight parabola
-- through the last two positions: at the current step, y' = v(t - dt/2) - g dt / 2.
local function speed_at_touch()
    local dt = m:dt()
    local vy = ball.vel[2] - g * dt / 2
    return math.sqrt(vy ^ 2 + 2 * g * (ball.pos[2] - R))
end

local bounces = {}
local v_in = math.sqrt(2 * g * drop)   -- first touch: dropped from rest
local in_contact, waiting = false, false
m:on_cycle(function(model)
    local touching = model:contact_count() > 0 or ball.force[2] ~= 0
    if touching then
        in_contact = true
    elseif in_contact then
        -- First step with no contact force: the flight parabola is fixed from here on.
        in_contact = false
        local v_out = speed_at_touch()
        bounces[#bounces + 1] = { v_in = v_in, v_out = v_out }
        v_in = v_out
    end
end)

local clock = os.clock()
while #bounces < 4 and m:time() < 5 do m:cycle(100) end
local cpu = os.clock() - clock
history:close()

print(string.format("bounce: disk R = %.2f m, m = %.2f kg on a wall, kn = %.3g N/m, "
    .. "dp_nratio = %.4f (dp_mode full)", R, mass, kn, beta))
print(string.format("closed form (the closed form of a linear spring-dashpot): e = exp(-pi beta / sqrt(1 - beta^2)) "
    .. "= %.6f", e_closed))
print("bounce   v_in [m/s]  v_out [m/s]  e measured  e exact, gravity in contact  "
    .. "error vs exact  vs closed form")
local worst = 0
for k, b in ipairs(bounces) do
    local e = b.v_out / b.v_in
    local e_exact = restitution_with_gravity(b.v_in)
    local err = (e - e_exact) / e_exact
    worst = math.max(worst, math.abs(err))
    print(string.format("%6d   %10.5f  %11.5f  %10.6f  %26.6f  %14.2e  %14.2e", k, b.v_in, b.v_out,
        e, e_exact, err, (e - e_closed) / e_closed))
end
local ts = m:timestep()
print(string.format("largest relative error against the exact restitution: %.2e "
    .. "(automatic step, %g steps per contact; %d steps, %.2f s CPU)", worst, ts.resolution,
    m:step(), cpu))

-- The single-contact rig (no gravity) gives the closed form directly.
local r = talus.impact{ props = { kn = kn, ks = kn / 2, fric = 0.5, dp_nratio = beta },
                        radius = R, density = density, speed = math.sqrt(2 * g * drop) }
print(string.format("talus.impact (no gravity): e = %.6f, relative error %.2e, %d steps in "
    .. "contact", r.restitution, (r.restitution - e_closed) / e_closed, r.steps))

local e = m:energies()
print(string.format("energy balance error %.3g J (of %.4g J put in by gravity)", e.balance_error,
    e.body))

-- Plot with: python3 scripts/plot_history.py out/bounce_history.csv -o out/bounce_energy.png
print(string.format("wrote %s/bounce_history.csv", outdir))
