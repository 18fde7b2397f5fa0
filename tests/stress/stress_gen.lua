-- SPDX-License-Identifier: MIT
-- Seeded random scenes for the stress suite (docs/stress.md).
--
-- A scene is plain data (gen.scene(seed) -> table); gen.build(S) turns it into a model and
-- gen.dump(S) into a standalone script that `talus run` replays bit for bit (numbers are written
-- with %.17g, which round-trips a double). The generator draws from its own SplitMix64 on Lua's
-- 64-bit integers, so a seed gives the same scene on every machine and build; it never calls
-- math.random.
local gen = {}

-- ------------------------------------------------------------------ PRNG (SplitMix64)

local Rng = {}
Rng.__index = Rng

--- SplitMix64 (Steele, Lea, Flood 2014): state += golden gamma, then two xor-shift-multiply
--- rounds. Lua 5.4 integers wrap modulo 2^64 and `>>` is a logical shift, which is exactly the
--- unsigned arithmetic the algorithm needs.
function Rng:next()
    self.s = self.s + 0x9E3779B97F4A7C15
    local z = self.s
    z = (z ~ (z >> 30)) * 0xBF58476D1CE4E5B9
    z = (z ~ (z >> 27)) * 0x94D049BB133111EB
    return z ~ (z >> 31)
end

--- Uniform in [0, 1): the top 53 bits.
function Rng:u() return (self:next() >> 11) * 0x1p-53 end
function Rng:uniform(a, b) return a + (b - a) * self:u() end
--- Log-uniform in [a, b] (a, b > 0): stiffnesses, densities, sizes span decades.
function Rng:log(a, b) return a * (b / a) ^ self:u() end
--- Integer in [a, b].
function Rng:int(a, b) return a + (self:next() >> 1) % (b - a + 1) end
function Rng:chance(p) return self:u() < p end
function Rng:pick(list) return list[self:int(1, #list)] end

function gen.rng(seed)
    -- Mix the seed once so that neighbouring seeds start far apart.
    local r = setmetatable({ s = seed * 0x632BE59BD9B4E019 + 0x1234567 }, Rng)
    r:next()
    return r
end

-- ------------------------------------------------------------------ scene generation

gen.models = { "linear", "hertz", "hysdamp", "power", "cbond", "ng" }
gen.kinds = { "free", "box", "valley", "saw", "slope" }

--- Random valid properties of one shipped model (ranges of docs/models/*.md). `rmax` and `rmin`
--- size the length-dependent ones (power's transition force, cbond's gap).
local function modelProps(r, name, rmin, rmax)
    local p = {}
    local function fric() return r:chance(0.2) and 0 or r:log(0.01, 5) end
    local function ratio() return r:chance(0.4) and 0 or r:uniform(0, 1) end
    if name == "linear" then
        p.kn = r:log(1e3, 1e12)
        p.ks = r:chance(0.2) and 0 or p.kn * r:uniform(0, 1.5)
        p.fric = fric()
        p.dp_nratio = ratio()
        p.dp_sratio = ratio()
        p.dp_mode = r:int(0, 3)
    elseif name == "hertz" then
        p.hz_shear = r:log(1e4, 1e11)
        p.hz_poiss = r:uniform(0, 0.49)
        p.fric = fric()
        if r:chance(0.3) then
            -- Above 0.1196, the smallest restitution of the no-tension modes (docs/models/hertz.md).
            p.hz_e = r:uniform(0.13, 1)
        else
            p.dp_nratio = ratio()
        end
        p.dp_sratio = ratio()
        p.dp_mode = r:int(0, 3)
    elseif name == "hysdamp" then
        p.kn_m = r:log(1e3, 1e12)
        p.tension = r:chance(0.3) and 1 or 0
        p.d = p.tension == 1 and r:uniform(0.4, 1) or r:uniform(0.05, 1)
        p.ks = r:chance(0.2) and 0 or p.kn_m * r:uniform(0, 1.5)
        p.fric = fric()
    elseif name == "power" then
        p.kn = r:log(1e3, 1e12)
        p.ks = r:chance(0.2) and 0 or p.kn * r:uniform(0, 1.5)
        p.fric = fric()
        -- A transition force reached at an overlap of 1e-5 to 1e-1 of the largest radius.
        p.transition = r:chance(0.3) and math.huge or p.kn * rmax * r:log(1e-5, 1e-1)
        p.exp_mode = r:int(0, 3)
        p.exponent = r:uniform(1, 10)
        p.target_e = r:uniform(0.05, 1)
    elseif name == "cbond" then
        p.kn = r:log(1e3, 1e12)
        p.ks = r:chance(0.2) and 0 or p.kn * r:uniform(0, 1.5)
        p.fric = fric()
        -- Strengths: unbreakable, or a force reached at 1e-6 to 1e-1 of the smallest radius.
        p.cb_tenf = r:chance(0.3) and math.huge or p.kn * rmin * r:log(1e-6, 1e-1)
        p.cb_shearf = r:chance(0.3) and math.huge or p.kn * rmin * r:log(1e-6, 1e-1)
        p.cb_bond = r:chance(0.6) and 1 or 0
        p.cb_gap = r:chance(0.3) and 0 or rmin * r:log(1e-6, 1e-2)
    elseif name == "ng" then
        p.ng_shear = r:log(1e4, 1e11)
        p.ng_poiss = r:uniform(0, 0.49)
        p.ng_form = r:int(0, 1)
        p.fric = fric()
    end
    return p
end

local inheritable = { linear = true, cbond = true, power = true, hysdamp = true }

--- Raises the stiffness of props (and power's transition force) so that the hardest impact the
--- scene can make, mass `mass` at closing speed `v`, overlaps by at most `u`: a softer contact
--- lets the ball pass through, which the engine reports as an error (a correct stop, but one
--- that ends the scene early). Used on 85% of the scenes; the others keep the raw draw.
local function stiffen(name, p, mass, v, u, reff)
    local e = 0.5 * mass * v * v
    local kmin = math.min(1e12, 2 * e / (u * u)) -- linear spring: e = k u^2 / 2
    for _, key in ipairs({ "kn", "kn_m" }) do
        if p[key] and p[key] < kmin then
            if p.ks then p.ks = p.ks * kmin / p[key] end
            p[key] = kmin
        end
    end
    -- Hertz: e = (8/15) E* sqrt(R*) u^(5/2), with E* >= G (both hertz and ng).
    local gmin = math.min(1e11, (15 / 8) * e / (math.sqrt(reff) * u ^ 2.5))
    for _, key in ipairs({ "hz_shear", "ng_shear" }) do
        if p[key] and p[key] < gmin then p[key] = gmin end
    end
    -- power: the plastic overlap m v^2 / (2 T) must stay below u as well.
    if name == "power" and p.transition ~= math.huge and p.transition < 2 * e / u then p.transition = 2 * e / u end
end


--- Wall chains around a region [x0, x1] x [y0, y1] that holds the balls.
local function makeWalls(r, kind, x0, x1, y0, y1, rmax)
    local w, h = x1 - x0, y1 - y0
    local walls = {}
    if kind == "box" then
        local m = rmax * 0.5
        walls[1] = { points = { { x0 - m, y0 - m }, { x1 + m, y0 - m }, { x1 + m, y1 + m }, { x0 - m, y1 + m } },
                     closed = true }
    elseif kind == "valley" then
        -- A V with a short flat (or slightly tilted) bottom, as in the rockfall gullies.
        local depth = r:uniform(0.3, 2) * w
        local xm = (x0 + x1) / 2
        local b = w * r:uniform(0, 0.1)
        walls[1] = { points = { { x0 - w * 0.5, y1 + depth * 0.2 }, { xm - b, y0 - rmax },
                                { xm + b, y0 - rmax + b * r:uniform(-0.5, 0.5) }, { x1 + w * 0.5, y1 + depth * 0.2 } } }
    elseif kind == "saw" then
        -- A sawtooth floor: every tooth tip is a convex vertex (issue 6 item 4).
        local teeth = r:int(2, 40)
        local amp = rmax * r:log(0.05, 3)
        local pts = {}
        for i = 0, 2 * teeth do
            pts[#pts + 1] = { x0 - rmax + (w + 2 * rmax) * i / (2 * teeth), y0 - rmax - (i % 2) * amp }
        end
        walls[1] = { points = pts }
        if r:chance(0.5) then -- side walls so that the balls stay
            walls[2] = { points = { { x0 - rmax, y0 - rmax }, { x0 - rmax, y1 + h } } }
            walls[3] = { points = { { x1 + rmax, y0 - rmax }, { x1 + rmax, y1 + h } } }
        end
    elseif kind == "slope" then
        -- A rockfall profile: descending segments of random inclination, convex and concave
        -- vertices, below the balls' region.
        local nseg = r:int(2, 8)
        local pts = { { x0 - w, y0 - rmax } }
        local x, y = x0 - w, y0 - rmax
        for _ = 1, nseg do
            local dx = 3 * w / nseg
            x = x + dx
            y = y - dx * math.tan(math.rad(r:uniform(-10, 60)))
            pts[#pts + 1] = { x, y }
        end
        walls[1] = { points = pts }
    end
    for _, wl in ipairs(walls) do
        if r:chance(0.25) then
            local v = r:log(0.01, 5)
            local a = r:uniform(0, 2 * math.pi)
            wl.vel = { v * math.cos(a), v * math.sin(a) }
        end
        if r:chance(0.1) then wl.spin = r:uniform(-1, 1) * r:log(1e-3, 1) end
        if wl.spin and r:chance(0.5) then wl.center = { (x0 + x1) / 2, y0 } end
    end
    return walls
end

--- The scene of one seed. Sizes of everything are bounded so that a scene runs well under a
--- second: steps x balls is about 6e5, at most 10000 steps (gen.scene's `budget`).
function gen.scene(seed, opts)
    opts = opts or {}
    local r = gen.rng(seed)
    local S = { seed = seed }
    S.model = opts.model or gen.models[1 + seed % #gen.models]
    S.kind = opts.kind or r:pick(gen.kinds)
    S.mass = r:chance(0.1) and "sphere" or "disk"

    -- Balls: 1 to 300, radius ratio up to 20, densities 1e2 to 2e4 kg/m^3.
    local n
    if r:chance(0.15) then n = 1 else n = math.floor(r:log(2, 300.999)) end
    if opts.max_balls then n = math.min(n, opts.max_balls) end
    local rmax = r:log(0.003, 1)
    local ratio = r:chance(0.3) and 1 or r:log(1, 20)
    local rmin = rmax / ratio
    local rho_scene = r:log(1e2, 2e4)
    local rho_each = r:chance(0.5)
    local vmax = r:chance(0.15) and 0 or r:log(0.01, 100)
    S.overlap = r:chance(0.05) -- bodies may be born overlapping (issue 6 item 8)
    S.soft = r:chance(0.15) -- keep the drawn stiffness even if too soft for the impacts

    -- Region: the balls' area over a packing fraction.
    local phi = r:log(0.02, 0.5)
    local area = 0
    local radii = {}
    for i = 1, n do
        radii[i] = ratio == 1 and rmax or r:log(rmin, rmax)
        area = area + math.pi * radii[i] ^ 2
    end
    local side = math.sqrt(area / phi)
    local aspect = r:log(0.5, 2)
    local w, h = side * aspect, side / aspect
    local x0, y0 = r:uniform(-10, 10), r:uniform(-10, 10)
    local x1, y1 = x0 + w, y0 + h

    S.walls = makeWalls(r, S.kind, x0, x1, y0, y1, rmax)
    local segs = {}
    for _, wl in ipairs(S.walls) do
        local p = wl.points
        for i = 1, #p - 1 do segs[#segs + 1] = { p[i], p[i + 1] } end
        if wl.closed then segs[#segs + 1] = { p[#p], p[1] } end
    end
    -- Squared distance from (x, y) to segment s.
    local function segDist2(x, y, sg)
        local ax, ay, bx, by = sg[1][1], sg[1][2], sg[2][1], sg[2][2]
        local dx, dy = bx - ax, by - ay
        local t = ((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy)
        t = math.max(0, math.min(1, t))
        local px, py = ax + t * dx - x, ay + t * dy - y
        return px * px + py * py
    end

    -- Place by rejection, clear of the other balls and of the walls (unless the scene is one
    -- whose bodies are born overlapping); drop the balls that do not fit.
    local fixities = r:chance(0.15) -- scene-level, so that most scenes have none (item 5)
    local loads = r:chance(0.15)
    S.balls = {}
    local placed = {}
    local function free(x, y, rad)
        if S.overlap then return true end
        for _, q in ipairs(placed) do
            local dx, dy = x - q[1], y - q[2]
            if dx * dx + dy * dy < (rad + q[3]) ^ 2 then return false end
        end
        for _, sg in ipairs(segs) do if segDist2(x, y, sg) < rad * rad then return false end end
        return true
    end
    table.sort(radii, function(a, b) return a > b end)
    for i = 1, n do
        local rad = radii[i]
        local x, y
        for _ = 1, 60 do
            local tx, ty = r:uniform(x0 + rad, math.max(x0 + rad, x1 - rad)), r:uniform(y0 + rad, math.max(y0 + rad, y1 - rad))
            if free(tx, ty, rad) then x, y = tx, ty break end
        end
        if x then
            placed[#placed + 1] = { x, y, rad }
            local b = { pos = { x, y }, radius = rad }
            local rho = rho_each and r:log(1e2, 2e4) or rho_scene
            if r:chance(0.1) then b.mass = rho * math.pi * rad * rad else b.density = rho end
            if vmax > 0 and not r:chance(0.2) then
                local v, a = r:uniform(0, vmax), r:uniform(0, 2 * math.pi)
                b.vel = { v * math.cos(a), v * math.sin(a) }
            end
            if vmax > 0 and r:chance(0.4) then b.spin = r:uniform(-1, 1) * vmax / rad end
            if fixities and r:chance(0.15) then
                local f = {}
                for _, c in ipairs({ "x", "y", "spin" }) do if r:chance(0.5) then f[#f + 1] = c end end
                b.fix = #f > 0 and f or { "spin" }
            end
            if loads and r:chance(0.2) then
                local mass = b.mass or rho * math.pi * rad * rad
                b.fapp = { mass * r:uniform(-20, 20), mass * r:uniform(-20, 20) }
            end
            if loads and r:chance(0.2) then b.mapp = rho * rad ^ 4 * r:uniform(-100, 100) end
            S.balls[#S.balls + 1] = b
        end
    end

    -- Contact model, properties, inheritance, a group rule with a second model.
    S.props = modelProps(r, S.model, rmin, rmax)
    if inheritable[S.model] and r:chance(0.1) then
        for _, b in ipairs(S.balls) do
            if r:chance(0.5) then b.kn = r:log(1e3, 1e12) end
            if r:chance(0.3) then b.fric = r:log(0.01, 2) end
        end
    end
    if r:chance(0.12) and #S.balls > 1 then
        local other = r:pick(gen.models)
        S.rule = { model = other, props = modelProps(r, other, rmin, rmax), groups = { "a", "b" } }
        for _, b in ipairs(S.balls) do b.group = r:chance(0.5) and "a" or "b" end
    end

    if #S.walls > 0 and inheritable[S.model] and r:chance(0.1) then
        S.walls[1].kn = r:log(1e3, 1e12)
        S.walls[1].fric = r:log(0.01, 2)
    end

    local u = r:u()
    if u < 0.5 then
        S.gravity = { 0, -9.81 }
    elseif u < 0.6 then
        local g, a = r:uniform(0, 20), r:uniform(0, 2 * math.pi)
        S.gravity = { g * math.cos(a), g * math.sin(a) }
    else
        S.gravity = { 0, 0 }
    end
    -- Idle start: no gravity and nothing moving for a while, then gravity (issue 6 item 1).
    if S.gravity[2] ~= 0 and r:chance(0.08) then
        S.idle = r:int(20, 300)
        for _, b in ipairs(S.balls) do b.vel, b.spin, b.fapp, b.mapp = nil, nil, nil, nil end
        for _, wl in ipairs(S.walls) do wl.vel, wl.spin, wl.center = nil, nil, nil end
    end

    if r:chance(0.3) then S.damping = { ["local"] = r:uniform(0, 0.9) } end
    if r:chance(0.15) then
        S.damping = S.damping or {}
        S.damping.viscous = r:log(0.01, 50)
    end
    if r:chance(0.2) then
        S.timestep = { safety = r:uniform(0.3, 0.9), resolution = r:pick({ 10, 20, 30, 50 }), growth = r:uniform(1.1, 3) }
    end
    if r:chance(0.1) then S.guard = { energy = "error" } end
    -- A quarter of the scenes switch the engine's run-level balance check off (where the engine
    -- has one), so that the suite's own energy check still sees the booking defects it would
    -- announce: a warning is an answer, but not a fix.
    if r:chance(0.25) then
        S.guard = S.guard or {}
        S.guard.balance = "off"
    end
    if r:chance(0.1) then S.margin = rmin * r:log(0.01, 10) end

    -- The hardest impact: the heaviest ball at the largest closing speed (its own, a partner's,
    -- a wall's and the speed gravity can give over the scene's height), overlapping 10% of the
    -- smallest radius at most.
    if not S.soft then
        local mmax, vw = 0, 0
        for _, b in ipairs(S.balls) do
            local rho = b.density or b.mass / (math.pi * b.radius ^ 2)
            local mb = rho * math.pi * b.radius ^ 2 * (S.mass == "sphere" and math.max(1, 4 / 3 * b.radius) or 1)
            mmax = math.max(mmax, mb)
        end
        for _, wl in ipairs(S.walls) do
            if wl.vel then vw = math.max(vw, math.sqrt(wl.vel[1] ^ 2 + wl.vel[2] ^ 2)) end
            if wl.spin then vw = math.max(vw, math.abs(wl.spin) * 4 * (w + h)) end
        end
        local gmag = math.sqrt(S.gravity[1] ^ 2 + S.gravity[2] ^ 2)
        local v = 2 * vmax + vw + math.sqrt(2 * gmag * 6 * (w + h)) + 1e-3
        stiffen(S.model, S.props, mmax, v, 0.1 * rmin, rmin / 2)
        if S.rule then stiffen(S.rule.model, S.rule.props, mmax, v, 0.1 * rmin, rmin / 2) end
    end

    local budget = opts.budget or 600000
    S.steps = math.max(200, math.min(10000, budget // math.max(1, #S.balls)))
    S.chunks = 10
    -- Changes between chunks: a ball deleted (its contacts end), a wall's velocity changed
    -- (boundary work with a velocity step). Chunk numbers count the idle phase as chunk 1.
    S.events = {}
    if #S.balls > 1 and r:chance(0.05) then
        S.events[#S.events + 1] = { chunk = r:int(1, 5), kind = "delete", ball = r:int(1, #S.balls) }
    end
    if #S.walls > 0 and r:chance(0.05) then
        local v, a = r:log(0.01, 3), r:uniform(0, 2 * math.pi)
        S.events[#S.events + 1] = { chunk = r:int(1, 5), kind = "wallvel", wall = r:int(1, #S.walls),
                                    vel = { v * math.cos(a), v * math.sin(a) } }
    end
    return S
end

-- ------------------------------------------------------------------ building and dumping

local function ballDef(b)
    local d = {}
    for k, v in pairs(b) do d[k] = v end
    return d
end

--- True when m:guard{} knows the option (the run-level balance check is newer than the rest).
local guard_options
function gen.hasGuardOption(name)
    if not guard_options then
        guard_options = {}
        for k in pairs(talus.model{}:guard()) do guard_options[k] = true end
    end
    return guard_options[name] == true
end

--- Builds the model of scene S (energy tracing on). Returns the model.
function gen.build(S)
    local g = S.idle and { 0, 0 } or S.gravity
    local m = talus.model{ gravity = g, mass = S.mass }
    m:contact_model(S.model, S.props)
    if S.rule then m:contact_model(S.rule.model, S.rule.props, { groups = S.rule.groups }) end
    local walls, balls = {}, {}
    for _, wl in ipairs(S.walls) do walls[#walls + 1] = m:wall(wl) end
    for _, b in ipairs(S.balls) do
        local d = ballDef(b)
        local fapp, mapp = d.fapp, d.mapp
        d.fapp, d.mapp = nil, nil
        local ball = m:ball(d)
        if fapp then ball.fapp = fapp end
        if mapp then ball.mapp = mapp end
        balls[#balls + 1] = ball
    end
    S.handles = { balls = balls, walls = walls }
    if S.damping then m:damping(S.damping) end
    if S.timestep then m:timestep(S.timestep) end
    if S.guard then
        local g = {}
        for k, v in pairs(S.guard) do g[k] = v end
        if not gen.hasGuardOption("balance") then g.balance = nil end
        m:guard(g)
    end
    if S.margin then m:broadphase{ margin = S.margin } end
    m:energy{ on = true }
    return m
end

--- What happens after chunk i of the plan: gravity switched on after the idle phase, events.
--- The checker calls it; gen.dump writes the same calls.
function gen.afterChunk(S, m, i)
    if i == 1 and S.idle then m:gravity(S.gravity) end
    for _, ev in ipairs(S.events or {}) do
        if ev.chunk == i then
            if ev.kind == "delete" then
                S.handles.balls[ev.ball]:delete()
            elseif ev.kind == "wallvel" then
                S.handles.walls[ev.wall].vel = ev.vel
            end
        end
    end
end

--- Runs the scene's steps on a built model in `S.chunks` chunks; `after(m, chunk)` is called
--- after each chunk (and after the idle phase). Used by the checker; gen.dump writes the same
--- sequence of calls.
function gen.plan(S)
    local plan = {}
    local steps = S.steps
    if S.idle then
        plan[#plan + 1] = S.idle
        steps = math.max(0, steps - S.idle)
    end
    local per = math.max(1, steps // S.chunks)
    local left = steps
    while left > 0 do
        local k = math.min(per, left)
        plan[#plan + 1] = k
        left = left - k
    end
    return plan
end

local function num(x)
    if x ~= x then return "0/0" end
    if x == math.huge then return "math.huge" end
    if x == -math.huge then return "-math.huge" end
    if math.type(x) == "integer" then return tostring(x) end
    return string.format("%.17g", x)
end

local function lit(v)
    local t = type(v)
    if t == "number" then return num(v) end
    if t == "string" then return string.format("%q", v) end
    if t == "boolean" then return tostring(v) end
    if t == "table" then
        if #v > 0 or next(v) == nil then
            local parts = {}
            for _, x in ipairs(v) do parts[#parts + 1] = lit(x) end
            return "{" .. table.concat(parts, ", ") .. "}"
        end
        local keys = {}
        for k in pairs(v) do keys[#keys + 1] = k end
        table.sort(keys)
        local parts = {}
        for _, k in ipairs(keys) do
            local key = k:match("^[%a_][%w_]*$") and k ~= "local" and k or ("[" .. string.format("%q", k) .. "]")
            parts[#parts + 1] = key .. " = " .. lit(v[k])
        end
        return "{ " .. table.concat(parts, ", ") .. " }"
    end
    error("cannot write a " .. t)
end

--- A standalone script that builds and runs scene S exactly as the checker does and prints the
--- energy balance (the seed's reproducer).
function gen.dump(S)
    local out = {}
    local function w(s) out[#out + 1] = s end
    w(string.format("-- stress scene seed=%d scene=%s variant=%s balls=%d (tests/stress, docs/stress.md)",
        S.seed, S.kind, S.model, #S.balls))
    w(string.format("local m = talus.model{ gravity = %s, mass = %q }", lit(S.idle and { 0, 0 } or S.gravity), S.mass))
    w(string.format("m:contact_model(%q, %s)", S.model, lit(S.props)))
    if S.rule then
        w(string.format("m:contact_model(%q, %s, { groups = %s })", S.rule.model, lit(S.rule.props), lit(S.rule.groups)))
    end
    w("m:on_warning(function(text) print('warning: ' .. text) end)")
    w("local W, B = {}, {}")
    for _, wl in ipairs(S.walls) do w("W[#W + 1] = m:wall" .. lit(wl)) end
    for _, b in ipairs(S.balls) do
        local d = ballDef(b)
        local fapp, mapp = d.fapp, d.mapp
        d.fapp, d.mapp = nil, nil
        local line = "B[#B + 1] = m:ball" .. lit(d)
        if fapp then line = line .. "; B[#B].fapp = " .. lit(fapp) end
        if mapp then line = line .. "; B[#B].mapp = " .. lit(mapp) end
        w(line)
    end
    if S.damping then w("m:damping" .. lit(S.damping)) end
    if S.timestep then w("m:timestep" .. lit(S.timestep)) end
    if S.guard then
        local g = {}
        for k, v in pairs(S.guard) do g[k] = v end
        if not gen.hasGuardOption("balance") then g.balance = nil end
        if next(g) then w("m:guard" .. lit(g)) end
    end
    if S.margin then w("m:broadphase{ margin = " .. num(S.margin) .. " }") end
    w("m:energy{ on = true }")
    w("local function report()")
    w("  local e = m:energies()")
    w("  print(string.format('step %d t %.6g: kinetic %.6g strain %.6g bond %.6g slip %.6g dashpot %.6g plastic %.6g damping %.6g released %.6g | in: initial %.6g body %.6g boundary %.6g | balance_error %.6g J',")
    w("    m:step(), m:time(), e.kinetic, e.strain, e.bond, e.slip, e.dashpot, e.plastic, e.damping, e.released, e.initial_kinetic, e.body, e.boundary, e.balance_error))")
    w("end")
    for i, k in ipairs(gen.plan(S)) do
        w(string.format("m:cycle(%d) report()", k))
        if i == 1 and S.idle then w(string.format("m:gravity(%s)", lit(S.gravity))) end
        for _, ev in ipairs(S.events or {}) do
            if ev.chunk == i and ev.kind == "delete" then w(string.format("B[%d]:delete()", ev.ball)) end
            if ev.chunk == i and ev.kind == "wallvel" then w(string.format("W[%d].vel = %s", ev.wall, lit(ev.vel))) end
        end
    end
    return table.concat(out, "\n") .. "\n"
end

return gen
