-- SPDX-License-Identifier: MIT
-- calibrate/rigs.lua: the rigs a calibration runs: one impact (talus.impact), a clump dropped onto a
-- wall, a rock released on a slope (run-out).
local Opt = require("talus_util.options")
local raise = require("talus_util.errors").raise

local C = {}
local merged = Opt.merged


--- One impact on the single-contact rig (talus.impact, docs/lua-api.md): returns a function
--- rig(params, v) -> restitution, result, where params are contact properties merged over
--- opts.props and v is the normal approach speed. Every other option goes to talus.impact
--- (radius, density, mass, target, target_radius, target_density, timestep, guard, ...).
function C.impact_rig(opts)
    opts = opts or {}
    return function(params, v)
        local o = {}
        for k, val in pairs(opts) do if k ~= "props" then o[k] = val end end
        o.props = merged(opts.props, params)
        o.speed = v
        local r = talus.impact(o)
        if not r.separated then
            raise(string.format("calibrate.impact_rig: no separation at v = %g m/s", v))
        end
        return r.restitution, r
    end
end

--- An's (2006, chapter 6) rock: three equal pebbles of radius R in contact, as an
--- equilateral triangle of side 2R, in the clump frame with the centroid at the origin and the
--- base (two pebbles) along -y.
function C.triangle_pebbles(R)
    local h = R / math.sqrt(3) -- centroid height above the base line of centres (side 2R)
    return { { -R, -h, R }, { R, -h, R }, { 0, 2 * h, R } }
end

--- A clump dropped onto a horizontal wall (y = 0), without gravity (the rebound is then read
--- without the free-flight correction; gravity during a contact of ~1e-2 s would change the
--- ratio by g t / v). Returns rig(params, v) -> Rn, info: Rn is the apparent normal restitution,
--- vertical velocity of the centroid after / before (An 2006 read the bounce from the clump's
--- kinetic energy; info.e_energy gives that ratio too: sqrt(KE after / KE before)).
--- opts: model, props, pebbles (clump frame; default C.triangle_pebbles(radius)), radius (0.04),
--- density (2600), angle (rad, default 0: two pebbles down, "dropped flat"), mass ("disk" or
--- "sphere"; sphere gives direct mass properties: each pebble 4/3 pi R^3 rho with I = 2/5 m R^2,
--- plus the parallel-axis terms, since the model refuses union clumps in sphere mode), gap
--- (initial gap of the lowest point, default 1e-3 R), spin (rad/s at the start, counter-clockwise,
--- default 0), timestep (table for m:timestep), max_time,
--- measure ("vy", default: the centroid's vertical velocity ratio; "energy": sqrt of the
--- kinetic energy after / before, translation and rotation, as An (2006) read it).
function C.clump_drop_rig(opts)
    opts = opts or {}
    local R = opts.radius or 0.04
    local rho = opts.density or 2600
    local pebbles = opts.pebbles or C.triangle_pebbles(R)
    local mass_mode = opts.mass or "disk"
    if opts.measure and opts.measure ~= "vy" and opts.measure ~= "energy" then
        raise("calibrate.clump_drop_rig: measure must be 'vy' or 'energy' (got "
            .. tostring(opts.measure) .. ")")
    end
    local angle = opts.angle or 0
    return function(params, v)
        local m = talus.model{ gravity = { 0, 0 }, mass = mass_mode }
        m:contact_model(opts.model or "power", merged(opts.props, params))
        if opts.timestep then m:timestep(opts.timestep) end
        m:wall{ points = { { -10, 0 }, { 10, 0 } } }
        -- lowest point of the turned pebbles, so that the clump starts a gap above the wall
        local c, s = math.cos(angle), math.sin(angle)
        local low = math.huge
        for _, p in ipairs(pebbles) do
            low = math.min(low, s * p[1] + c * p[2] - p[3])
        end
        local gap = opts.gap or 1e-3 * R
        local y0 = gap - low
        local spec = { pebbles = pebbles, pos = { 0, y0 }, angle = angle, vel = { 0, -v },
            spin = opts.spin or 0 }
        if mass_mode == "sphere" then
            local mass, inertia = 0, 0
            for _, p in ipairs(pebbles) do
                local mp = 4 / 3 * math.pi * p[3] ^ 3 * rho
                mass = mass + mp
                inertia = inertia + 0.4 * mp * p[3] ^ 2 + mp * (p[1] ^ 2 + p[2] ^ 2)
            end
            -- pebbles given about the centroid (true for the default triangle)
            spec.mass_mode, spec.mass, spec.inertia = "direct", mass, inertia
        else
            spec.density = rho
        end
        local rock = m:clump(spec)
        local ke0 = 0.5 * rock.mass * v * v
        -- advance until the clump has left the wall and its centroid is back above its start:
        -- with no gravity it then flies free for good (vertical velocity constant).
        local max_time = opts.max_time or 2.0
        local touched, left = false, false
        local chunk = opts.chunk or 200
        while m:time() < max_time do
            m:cycle(chunk)
            local n = m:contact_count{ active = true }
            if n > 0 then touched = true end
            if touched and n == 0 and rock.pos[2] > y0 and rock.vel[2] > 0 then
                left = true
                break
            end
        end
        if not touched then
            raise(string.format("calibrate.clump_drop_rig: no contact at v = %g m/s", v))
        end
        if not left then
            raise(string.format("calibrate.clump_drop_rig: the rock did not leave the wall within "
                .. "max_time = %g s at v = %g m/s", max_time, v))
        end
        local vy, vx, w = rock.vel[2], rock.vel[1], rock.spin
        local ke1 = 0.5 * rock.mass * (vx * vx + vy * vy) + 0.5 * rock.inertia * w * w
        local e_energy = math.sqrt(ke1 / ke0)
        return (opts.measure == "energy") and e_energy or vy / v, { vy = vy, vx = vx, spin = w, mass = rock.mass, inertia = rock.inertia,
            e_energy = e_energy, steps = m:step(), time = m:time() }
    end
end


--- A rock launched along a straight slope (a bench when slope = 0) and run until it stops:
--- returns rig(params) -> run-out distance along the slope [m], info. params are the contact
--- model's properties merged over opts.props. opts: model, props, slope (degrees, down-slope
--- to +x; default 0), v0 (m/s, default 2), rock = "ball" (default; rolling from the start:
--- spin = -v0/R) or "pair" (two touching pebbles lying on the slope: it cannot roll, so it
--- slides; useful to check a friction fit), radius (0.1), density (2600), mass ("disk"),
--- gravity (9.81), max_time (60 s), stop_speed (1e-4 v0).
function C.runout_rig(opts)
    opts = opts or {}
    local R = opts.radius or 0.1
    local rho = opts.density or 2600
    local v0 = opts.v0 or 2
    local g = opts.gravity or 9.81
    local beta = math.rad(opts.slope or 0)
    local rock_kind = opts.rock or "ball"
    return function(params)
        local m = talus.model{ gravity = { g * math.sin(beta), -g * math.cos(beta) },
            mass = opts.mass or "disk" }
        -- the slope is the x axis; gravity is turned instead of the wall
        local props = merged(opts.props, params)
        m:contact_model(opts.model or "linear", props)
        m:wall{ points = { { -100, 0 }, { 1e4, 0 } } }
        -- start touching, at the static overlap (weight / kn per contact), so no bounce
        local kn = props.kn or 1e8
        local rock, pos
        if rock_kind == "ball" then
            local b = m:ball{ pos = { 0, R }, radius = R, density = rho, vel = { v0, 0 },
                spin = -v0 / R }
            b.pos = { 0, R - b.mass * g * math.cos(beta) / kn }
            rock, pos = b, function() return b.pos[1] end
        elseif rock_kind == "pair" then
            local c = m:clump{ pebbles = { { -R, 0, R }, { R, 0, R } }, pos = { 0, R },
                density = rho, vel = { v0, 0 } }
            c.pos = { 0, R - 0.5 * c.mass * g * math.cos(beta) / kn }
            rock, pos = c, function() return c.pos[1] end
        else
            raise("calibrate.runout_rig: rock must be 'ball' or 'pair' (got " .. tostring(rock_kind)
                .. ")")
        end
        local x0 = pos()
        local stop = opts.stop_speed or 1e-4 * v0
        local max_time = opts.max_time or 60
        while m:time() < max_time do
            m:cycle(50)
            local vx = rock.vel[1]
            if vx <= stop then
                return pos() - x0, { time = m:time(), steps = m:step(), stopped = true }
            end
        end
        return pos() - x0, { time = m:time(), steps = m:step(), stopped = false }
    end
end

return C
