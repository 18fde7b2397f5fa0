-- SPDX-License-Identifier: MIT
-- material/vessels.lua: what a genesis packs into (genesis.lua): a box of four walls, each
-- servoed on its own, or a circle (a regular polygon of segment walls) shrunk by one radial
-- servo. A vessel samples a place for a body and says whether it is inside, builds its walls,
-- measures its stress, servoes to a target, offers its walls as floater sites and describes the
-- packing's outline.
local Wl = require("material.walls")

local V = {}

local function porosity_of(balls, area)
    local a = 0
    for _, b in ipairs(balls) do a = a + math.pi * b[3] * b[3] end
    return 1 - a / area
end

-- The servo's speed cap: 1e-5 of a mean radius per step keeps it quasi-static. Gain alpha 0.25,
-- not PFC's 0.5: a wall's stress answers a move only after the wave has crossed the packing
-- (tens of steps), and with 0.5 the walls overshot and lost contact. PFC's gain takes the
-- stiffness of the wall's own contacts, but behind them stand ~H / 2R layers of balls in
-- series, so a step closes about alpha 2R / H of the stress error, not alpha: with 0.05 the
-- walls of a 5 000-ball box (100 layers) were still 15% below the stress after the 3 000 steps
-- of each servo, with 0.25 the first servo reached it in 400 steps.
local kServoAlpha = 0.25
local function servo_vmax(m, rmean) return 1e-5 * rmean / m:dt() end

--- The box [0, W] x [0, H]: four walls reaching a quarter of the longer side past the corners,
--- so none opens as they move.
function V.box(W, H)
    -- The servo stops at max_steps + servo_overrun steps: the box's went on to the first check
    -- past max_steps (one more 200-step chunk when max_steps is a multiple of 200), the
    -- circle's stops at max_steps. Kept as each was: every packing made so far depends on it.
    local v = { name = "box", servo_overrun = 1 }
    local walls

    function v.target_area(solid) return solid * W * H end
    function v.extent() return W, H end
    function v.sample(r, u01)
        local x = r + (W - 2 * r) * u01()
        local y = r + (H - 2 * r) * u01()
        return x, y
    end
    function v.inside() return true end
    function v.fits(rb)
        if 2 * rb < math.min(W, H) then return nil end
        return string.format("(bounding radius %.4g m at half size) does not fit the %.4g x %.4g m box", rb, W, H)
    end

    function v.build(m)
        local ext = 0.25 * math.max(W, H)
        walls = {
            Wl.make(m, { 0, -ext }, { 0, H + ext }, { 1, 0 }, "vessel"),   -- left
            Wl.make(m, { W, -ext }, { W, H + ext }, { -1, 0 }, "vessel"),  -- right
            Wl.make(m, { -ext, 0 }, { W + ext, 0 }, { 0, 1 }, "vessel"),   -- bottom
            Wl.make(m, { -ext, H }, { W + ext, H }, { 0, -1 }, "vessel"),  -- top
        }
        local function xlen() return Wl.pos(walls[2]) * -1 - Wl.pos(walls[1]) end
        local function ylen() return Wl.pos(walls[4]) * -1 - Wl.pos(walls[3]) end
        walls[1].len, walls[2].len = ylen, ylen
        walls[3].len, walls[4].len = xlen, xlen
        -- each wall's stress is over the gap between the two walls across it (the engine's
        -- servo measures it every step)
        walls[1].span, walls[2].span = { walls[3].wall, walls[4].wall }, { walls[3].wall, walls[4].wall }
        walls[3].span, walls[4].span = { walls[1].wall, walls[2].wall }, { walls[1].wall, walls[2].wall }
    end
    function v.start() end
    function v.finish() end

    -- the walls' stresses {left, right, bottom, top} [Pa], and their mean
    function v.stresses()
        local st = {}
        for i, rec in ipairs(walls) do st[i] = Wl.push(rec) / rec.len() end
        return st
    end
    function v.stress()
        local st = v.stresses()
        return 0.25 * (st[1] + st[2] + st[3] + st[4])
    end
    -- every wall within tol x sigma0 of sigma0
    function v.at_stress(sigma0, tol)
        local st = v.stresses()
        for i = 1, 4 do
            if math.abs(st[i] - sigma0) > tol * sigma0 then return false end
        end
        return true
    end
    function v.stress_text()
        local st = v.stresses()
        return string.format("wall stresses %.4g %.4g %.4g %.4g Pa", st[1], st[2], st[3], st[4])
    end

    -- the four walls servoed to sigma0 each (PFC's gain G = alpha L / (k dt), velocity cap)
    function v.servo(m, sigma0, _, rmean)
        for _, rec in ipairs(walls) do rec.target = sigma0 end
        return Wl.servo(m, walls, { vmax = servo_vmax(m, rmean), alpha = kServoAlpha })
    end

    -- the walls as floater sites relative to P (floaters.lua): all four
    function v.wall_sites(P, sites)
        for _, rec in ipairs(walls) do
            local w = Wl.pos(rec) - (rec.n[1] * P[1] + rec.n[2] * P[2])
            sites[#sites + 1] = { nx = rec.n[1], ny = rec.n[2], w = w, gap = -w, key = "w" .. rec.wall.id }
        end
    end

    -- box = the walls' final positions {xmin, ymin, xmax, ymax}, their stresses, the porosity
    -- within them
    function v.describe(pk)
        local box = { Wl.pos(walls[1]), Wl.pos(walls[3]), -Wl.pos(walls[2]), -Wl.pos(walls[4]) }
        pk.box, pk.stress = box, v.stresses()
        pk.porosity = porosity_of(pk.balls, (box[3] - box[1]) * (box[4] - box[2]))
    end
    return v
end

--- The circle of diameter D0 as a regular polygon of N segment walls inscribed in it (vertices
--- on the circle, a flat centred at the top and at the bottom: the loaded diameter), centred at
--- (D0/2, D0/2). Each segment is its own wall so the vessel can shrink: in the servo every
--- segment moves along its inward normal at one common speed (a homothetic shrink of the
--- polygon about the centre), driven by the vessel's mean pressure (the sum of the segments'
--- normal forces over the perimeter).
function V.circle(D0, N)
    local v = { name = "circle", servo_overrun = 0 }
    local R0 = 0.5 * D0
    local cx, cy = R0, R0
    local half = math.pi / N
    local apothem0 = R0 * math.cos(half)
    local function poly_area(a) return N * a * a * math.tan(half) end
    local walls, spin_hook

    function v.target_area(solid) return solid * poly_area(apothem0) end
    function v.extent() return D0, D0 end
    -- a point of the square around the circle; inside() keeps those at most (a - r) from the
    -- centre (inside every flat)
    function v.sample(_, u01)
        local x, y = 2 * R0 * u01(), 2 * R0 * u01()
        return x, y
    end
    function v.inside(x, y, r) return math.sqrt((x - cx) ^ 2 + (y - cy) ^ 2) <= apothem0 - r end
    function v.fits(rb)
        if rb < apothem0 then return nil end
        return string.format("(bounding radius %.4g m at half size) does not fit the %.4g m circle", rb, D0)
    end

    -- Segment k is the chord between the circle's points at angles pi/2 - pi/N + 2 pi k/N and
    -- the next (k = 0: the top flat), lengthened by a quarter chord at each end so that
    -- neighbours still meet when the polygon grows (servo retreat) by up to a quarter of its
    -- apothem; the lengthening lies outside the neighbour's line (convex polygon), where no
    -- ball is.
    function v.build(m)
        walls = {}
        for k = 0, N - 1 do
            local a1 = 0.5 * math.pi - half + 2 * half * k
            local a2 = a1 + 2 * half
            local p1 = { cx + R0 * math.cos(a1), cy + R0 * math.sin(a1) }
            local p2 = { cx + R0 * math.cos(a2), cy + R0 * math.sin(a2) }
            local tx, ty = 0.25 * (p2[1] - p1[1]), 0.25 * (p2[2] - p1[2])
            local am = a1 + half
            walls[#walls + 1] = Wl.make(m, { p1[1] - tx, p1[2] - ty }, { p2[1] + tx, p2[2] + ty },
                { -math.cos(am), -math.sin(am) }, "vessel")
        end
    end

    local function apothem() -- distance of the flats from the centre (all equal: one speed)
        local rec = walls[1]
        return -(Wl.pos(rec) - (cx * rec.n[1] + cy * rec.n[2]))
    end
    local function pressure()
        local f = 0
        for _, rec in ipairs(walls) do f = f + Wl.push(rec) end
        local a = apothem()
        return f / (2 * N * a * math.tan(half))
    end

    -- A frictionless packing in a (nearly) circular vessel may turn as a body: the walls push
    -- only along their normals, so only the polygon's corners resist a rotation (a weak, slow
    -- mode), and local damping (a force against the velocity proportional to the unbalanced
    -- force) hardly slows a motion that needs almost no force. Measured (seed 5 of the test
    -- disk): 98% of the kinetic energy was such a rotation (0.6 rad/s), the balls rode over the
    -- polygon's corners and the ratio stalled at 3e-3. Zeroing the rotation every 50 steps did
    -- not cure it: the walls' net torque is not zero until the packing has turned to its
    -- equilibrium angle, and a packing kept from turning stays out of balance (ratio 2e-3). So
    -- the mode gets kinetic damping (Cundall's): its angular velocity omega = L / I (L, I the
    -- balls' angular momentum and polar inertia about the centre, mass ~ r^2) is checked every
    -- 50 steps and taken out of the velocities (v -= omega x (p - c)) when |omega| fell since
    -- the last check: the rotation's kinetic energy peaked, so the packing passed the angle
    -- where the torque vanishes, and is stopped there. Nothing else of the motion changes.
    function v.start(m)
        local om_prev = 0
        spin_hook = m:on_cycle(function()
            local L, I = 0, 0
            for b in m:balls() do
                local p, vel, w = b.pos, b.vel, b.radius * b.radius
                local x, y = p[1] - cx, p[2] - cy
                L = L + w * (x * vel[2] - y * vel[1]); I = I + w * (x * x + y * y)
            end
            if I == 0 then return end
            local om = L / I
            if math.abs(om) < math.abs(om_prev) or om * om_prev < 0 then
                for b in m:balls() do
                    local p, vel = b.pos, b.vel
                    b.vel = { vel[1] + om * (p[2] - cy), vel[2] - om * (p[1] - cx) }
                end
                om = 0
            end
            om_prev = om
        end, 50)
    end
    function v.finish(m) m:remove_on_cycle(spin_hook) end

    v.stress = pressure
    function v.at_stress(sigma0, tol) return not (math.abs(pressure() - sigma0) > tol * sigma0) end
    function v.stress_text() return string.format("pressure %.4g Pa", pressure()) end

    -- The radial servo: one engine servo over all segments, each moving along its inward normal
    -- at one common speed (a servo per segment would make the polygon wander from the circle),
    -- driven by the vessel's pressure: the segments' summed push over the polygon's perimeter
    -- 2 N a tan(pi / N), taken at the apothem a of the servo's start (the servo moves the walls
    -- by a strain of ~1e-5 of the packing: the perimeter changes by as much). PFC's gain on the
    -- segments' contact stiffness, alpha and the speed cap as the box's.
    function v.servo(m, sigma0, _, rmean)
        local list, dirs = {}, {}
        for i, rec in ipairs(walls) do list[i], dirs[i] = rec.wall, rec.n end
        local sv = m:servo{ walls = list, dirs = dirs, stress = sigma0, length = 2 * N * apothem() * math.tan(half),
                            alpha = kServoAlpha, vmax = servo_vmax(m, rmean) }
        return {
            stop = function()
                sv:remove()
                for _, rec in ipairs(walls) do rec.wall.vel = { 0, 0 } end
            end,
        }
    end

    -- the segments whose line passes within 4 rmax of P (a candidate circle reaches 2 rmax
    -- from P with a radius up to 2 R)
    function v.wall_sites(P, sites, rmax)
        for _, rec in ipairs(walls) do
            local w = Wl.pos(rec) - (rec.n[1] * P[1] + rec.n[2] * P[2])
            if -w < 4 * rmax then
                sites[#sites + 1] = { nx = rec.n[1], ny = rec.n[2], w = w, gap = -w, key = "w" .. rec.wall.id }
            end
        end
    end

    -- box = the circle's bounding box; vessel = {center, diameter (final circumcircle),
    -- apothem, segments}; stress = {vessel = pressure, measured = mean stress of the whole disk
    -- by m:measure, inner = over the circle of 0.8 R}; porosity over the polygon, and over that
    -- inner circle.
    function v.describe(pk, m, ratio)
        local a = apothem()
        local Rc = a / math.cos(half)
        local solid = 0
        for _, p in ipairs(pk.balls) do solid = solid + math.pi * p[3] * p[3] end
        -- The whole disk's mean stress (a measurement circle = the circumcircle, every ball
        -- wholly inside): in equilibrium it equals the vessel pressure exactly, since the mean
        -- of (sigma_xx + sigma_yy)/2 over the polygon is sum_i F_i a / (2 A) = sum F / L (each
        -- flat at distance a, area A = L a / 2); m:measure divides by the circle's area, hence
        -- the factor.
        local whole = m:measure{ circle = { cx, cy, Rc } }
        local meas = m:measure{ circle = { cx, cy, 0.8 * Rc } }
        pk.box = { cx - Rc, cy - Rc, cx + Rc, cy + Rc }
        pk.vessel = { center = { cx, cy }, diameter = 2 * Rc, apothem = a, segments = N }
        pk.stress = { vessel = pressure(),
                      measured = -0.5 * (whole.stress.xx + whole.stress.yy) * math.pi * Rc * Rc / poly_area(a),
                      inner = -0.5 * (meas.stress.xx + meas.stress.yy) }
        pk.porosity = 1 - solid / poly_area(a)
        pk.porosity_inner = meas.porosity
        pk.ratio = ratio -- the final unbalanced-force ratio
        pk.genesis.diameter, pk.genesis.segments = D0, N
    end
    return v
end

return V
