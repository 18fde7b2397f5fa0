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

-- pbond came last (wave 9): seed -> model is seed % 7 since, so the seeds of docs/stress.md
-- found before it name scenes of the six-model generator (their regress tests hold the dumps).
gen.models = { "linear", "hertz", "hysdamp", "power", "cbond", "ng", "pbond" }
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
    elseif name == "pbond" then
        -- The linear part as `linear`'s, the bond at touch (a rule with bonded = 1) with a
        -- stiffness per unit area pb_kn such that the bond's pb_kn 2 R_b is 1e-2 to 1e2 times kn
        -- (R_b = pb_rmul min(R) at most 1.5 rmax: rmin bounds it below), or the deformability
        -- forms; strengths unbreakable (inf, wave 9) or a stress reached at an opening of 1e-6
        -- to 1e-1 of the smallest radius.
        p.kn = r:log(1e3, 1e12)
        p.ks = r:chance(0.2) and 0 or p.kn * r:uniform(0, 1.5)
        p.fric = fric()
        p.dp_nratio = ratio()
        p.dp_sratio = ratio()
        p.lin_mode = r:int(0, 1)
        p.pb_rmul = r:chance(0.5) and 1 or r:uniform(0.3, 1.5)
        local pbkn
        if r:chance(0.2) then
            p.pb_emod = p.kn * r:log(1e-2, 1e2) -- pb_kn = pb_emod / (R_A + R_B)
            p.pb_kratio = r:uniform(0.5, 4)
            pbkn = p.pb_emod / (2 * rmin)
        else
            pbkn = p.kn / (2 * rmin) * r:log(1e-2, 1e2)
            p.pb_kn = pbkn
            p.pb_ks = pbkn * r:uniform(0.2, 1.5)
        end
        p.pb_ten = r:chance(0.2) and math.huge or pbkn * rmin * r:log(1e-6, 1e-1)
        p.pb_coh = r:chance(0.2) and math.huge or pbkn * rmin * r:log(1e-6, 1e-1)
        p.pb_fa = r:chance(0.5) and 0 or r:uniform(0, 60)
        p.pb_mcf = r:chance(0.5) and 1 or r:uniform(0, 1)
        p.bonded = 1
    elseif name == "ng" then
        p.ng_shear = r:log(1e4, 1e11)
        p.ng_poiss = r:uniform(0, 0.49)
        p.ng_form = r:int(0, 1)
        p.fric = fric()
    end
    return p
end

local inheritable = { linear = true, cbond = true, power = true, hysdamp = true, pbond = true }

--- Raises the stiffness of props (and power's transition force) so that the hardest impact the
--- scene can make, mass `mass` at closing speed `v`, overlaps by at most `u`: a softer contact
--- lets the ball pass through, which the engine reports as an error (a correct stop, but one
--- that ends the scene early). Used on 85% of the scenes; the others keep the raw draw.
local addClumps, addGroups
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


--- A random pebble set {{x, y, r}, ...} inside the circle of radius `rad` about the frame's
--- origin: 1-5 pebbles, radius ratio up to 5, overlapping or not (drawn independently).
local function pebbleSet(r, rad)
    local n = r:int(1, 5)
    local big = rad * r:uniform(0.3, 1)
    local ratio = r:chance(0.3) and 1 or r:log(1, 5)
    local peb = {}
    for i = 1, n do
        local pr = i == 1 and big or r:log(big / ratio, big)
        local d, a = r:uniform(0, rad - pr), r:uniform(0, 2 * math.pi)
        peb[i] = { d * math.cos(a), d * math.sin(a), pr }
    end
    return peb
end

--- Clumps (docs/stress.md "The scenes"): in ~25% of the scenes some balls are replaced by clumps
--- whose pebbles lie within the ball's circle (so the placement stays clear), some from a
--- template placed several times, some made of existing neighbouring balls (m:clump{balls =}),
--- with random mass modes, angle, scale, fixities and loads; occasionally a clump is released or
--- deleted between chunks. Draws only from `r` (the clump sub-stream).
addClumps = function(S, r, rmin)
    if not r:chance(0.25) or #S.balls == 0 then return end
    S.clumps, S.absorbed, S.fromballs = {}, {}, {}
    local sphere = S.mass == "sphere" -- union and sum are refused there: direct mass only
    local frac = r:uniform(0.2, 1)
    if not sphere and r:chance(0.3) then
        -- Template pebbles within radius 0.5: placed with scale <= R, they fit the ball's circle.
        S.template = { pebbles = pebbleSet(r, 0.5), mass_mode = r:chance(0.8) and "union" or "sum" }
    end
    local mass_factor, pmin = 1, math.huge
    for i, b in ipairs(S.balls) do
        if r:chance(frac) then
            local R = b.radius
            local rho = b.density or b.mass / (math.pi * R * R)
            local c = { pos = { b.pos[1], b.pos[2] }, vel = b.vel, spin = b.spin, fix = b.fix,
                        kn = b.kn, fric = b.fric, group = b.group }
            local peb
            if S.template and r:chance(0.5) then
                c.template = true
                c.scale = R * r:uniform(0.5, 1)
                c.density = rho
                peb = S.template.pebbles
                for _, p in ipairs(peb) do pmin = math.min(pmin, p[3] * c.scale) end
                if S.template.mass_mode == "sum" then mass_factor = math.max(mass_factor, 1.25) end
            else
                -- Pebbles within R/2 (world) of the frame origin: the centroid lies in that circle
                -- too, so every pebble stays within R of it.
                local s = r:chance(0.5) and r:log(0.5, 2) or 1
                peb = pebbleSet(r, R / 2 / s)
                c.pebbles = peb
                if s ~= 1 then c.scale = s end
                for _, p in ipairs(peb) do pmin = math.min(pmin, p[3] * s) end
                local u = r:u()
                if sphere or u > 0.85 then
                    c.mass_mode = "direct"
                    c.mass = rho * math.pi * R * R * r:uniform(0.3, 1)
                    c.inertia = 0.5 * c.mass * (R / 2) ^ 2 * r:log(0.5, 2)
                    if r:chance(0.5) then
                        local a = r:uniform(0, 2 * math.pi)
                        c.centroid = { 0.1 * R / s * math.cos(a), 0.1 * R / s * math.sin(a) }
                    end
                elseif u > 0.7 then
                    c.mass_mode, c.density = "sum", rho
                    mass_factor = math.max(mass_factor, 1.25) -- at most 5 pebbles of R/2
                else
                    if r:chance(0.5) then c.mass_mode = "union" end
                    c.density = rho
                end
            end
            if r:chance(0.7) then c.angle = r:uniform(-math.pi, math.pi) end
            if not c.fix and r:chance(0.05) then c.fix = r:pick({ { "spin" }, { "x", "y" }, true }) end
            c.fapp, c.mapp = b.fapp, b.mapp
            if r:chance(0.05) then
                local mass = rho * math.pi * R * R
                c.fapp, c.mapp = { mass * r:uniform(-20, 20), mass * r:uniform(-20, 20) }, rho * R ^ 4 * r:uniform(-100, 100)
            end
            S.clumps[i] = c
        end
    end
    -- Clumps of existing balls: a ball and its 1-3 nearest neighbours that are still balls.
    if #S.balls > 1 and r:chance(0.4) then
        for _ = 1, r:int(1, 3) do
            local i = r:int(1, #S.balls)
            if not S.clumps[i] and not S.absorbed[i] then
                local near = {}
                for k, q in ipairs(S.balls) do
                    if k ~= i and not S.clumps[k] and not S.absorbed[k] then
                        near[#near + 1] = { (q.pos[1] - S.balls[i].pos[1]) ^ 2 + (q.pos[2] - S.balls[i].pos[2]) ^ 2, k }
                    end
                end
                table.sort(near, function(a, b) return a[1] < b[1] end)
                local set = { i }
                for k = 1, math.min(#near, r:int(1, 3)) do set[#set + 1] = near[k][2] end
                if #set > 1 then
                    local fb = { balls = set }
                    local j = #S.fromballs + 1
                    for _, k in ipairs(set) do S.absorbed[k] = j end
                    if r:chance(0.3) then fb.density = S.balls[i].density or 1000 end
                    if sphere then fb = nil end -- union mass of spheres: refused
                    if fb then S.fromballs[j] = fb else for _, k in ipairs(set) do S.absorbed[k] = nil end end
                end
            end
        end
    end
    -- A clump's mass may exceed its ball's (sum mode) and its pebbles are smaller than the
    -- scene's balls: raise the stiffness floor again for them.
    if S._impact and pmin < math.huge then
        local e = S._impact
        stiffen(S.model, S.props, e.mass * mass_factor, e.v, 0.1 * math.min(rmin, pmin), math.min(rmin, pmin) / 2)
        if S.rule then stiffen(S.rule.model, S.rule.props, e.mass * mass_factor, e.v, 0.1 * math.min(rmin, pmin), math.min(rmin, pmin) / 2) end
    end
    -- The budget counts pebbles: a clump of five pebbles costs about what five balls cost.
    local bodies = 0
    for i in ipairs(S.balls) do
        local c = S.clumps[i]
        bodies = bodies + (c and #(c.pebbles or S.template.pebbles) or 1)
    end
    S.steps = math.max(200, math.min(10000, S._budget // math.max(1, bodies)))
    -- Redirect the ball deletion to the clump a ball became a pebble of.
    for _, ev in ipairs(S.events) do
        if ev.kind == "delete" and S.absorbed[ev.ball] then ev.kind, ev.fromballs, ev.ball = "cdelete", S.absorbed[ev.ball], nil end
        if ev.kind == "delete" and S.clumps[ev.ball] then ev.kind = "cdelete" end
    end
    if r:chance(0.2) then
        local ids = {}
        for i in pairs(S.clumps) do ids[#ids + 1] = i end
        table.sort(ids)
        local ev = { chunk = r:int(1, 6), kind = r:chance(0.6) and "release" or "cdelete" }
        if #S.fromballs > 0 and (#ids == 0 or r:chance(0.3)) then
            ev.fromballs = r:int(1, #S.fromballs)
        elseif #ids > 0 then
            ev.ball = ids[r:int(1, #ids)]
        end
        if ev.ball or ev.fromballs then S.events[#S.events + 1] = ev end
    end
end

--- Groups for the group-wise energy books (docs/physics/energy.md "Energy per group"): in ~30%
--- of the scenes 1-4 names g1..g4; in 80% of those every body (ball, clump, wall) gets exactly
--- one (a partition, so that the group books must sum to the whole model's), otherwise some
--- bodies get two and some none. Draws only from `r` (the group sub-stream).
addGroups = function(S, r)
    if not r:chance(0.3) then return end
    local k = r:int(1, 4)
    local names = {}
    for i = 1, k do names[i] = "g" .. i end
    local partition = r:chance(0.8)
    local function draw()
        if not partition then
            local u = r:u()
            if u < 0.1 then return {} end
            if u < 0.25 and k > 1 then
                local a = r:int(1, k)
                local b = 1 + (a + r:int(0, k - 2)) % k
                return { names[a], names[b] }
            end
        end
        return { names[r:int(1, k)] }
    end
    local G = { names = names, partition = partition, balls = {}, walls = {}, fromballs = {} }
    for i = 1, #S.balls do G.balls[i] = draw() end
    for i = 1, #S.walls do G.walls[i] = draw() end
    for j = 1, #(S.fromballs or {}) do G.fromballs[j] = draw() end
    -- Only the names some body got exist in the model (m:energies("g4") is an error otherwise).
    local used = {}
    for _, list in ipairs({ G.balls, G.walls, G.fromballs }) do
        for i, l in pairs(list) do
            if not (list == G.balls and S.absorbed and S.absorbed[i]) then for _, g in ipairs(l) do used[g] = true end end
        end
    end
    G.names = {}
    for _, g in ipairs(names) do if used[g] then G.names[#G.names + 1] = g end end
    if #G.names > 0 then S.groups = G end
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
        -- A sawtooth floor: every tooth tip is a convex vertex.
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
    S.overlap = r:chance(0.05) -- bodies may be born overlapping
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
    local fixities = r:chance(0.15) -- scene-level, so that most scenes have none
    local loads = r:chance(0.15)
    S.balls = {}
    local placed = {}
    local function free(x, y, rad)
        if S.overlap then
            -- born overlapping, but not through a wall: a centre within half its radius of a
            -- segment is refused at placement (docs/physics/walls.md)
            for _, sg in ipairs(segs) do if segDist2(x, y, sg) <= 0.25 * rad * rad then return false end end
            return true
        end
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
    -- Idle start: no gravity and nothing moving for a while, then gravity.
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
        S._impact = { mass = mmax, v = v }
    end

    local budget = opts.budget or 600000
    S.steps = math.max(200, math.min(10000, budget // math.max(1, #S.balls)))
    S._budget = budget
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
    -- Clumps and groups come from sub-streams of their own, drawn after everything above: a seed
    -- that draws neither builds exactly the scene it built before they existed (same calls, same
    -- state digest).
    addClumps(S, gen.rng(seed ~ 0x3C6EF372FE94F82B), rmin)
    addGroups(S, gen.rng(seed ~ 0x510E527FADE682D1))
    S._impact, S._budget = nil, nil
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
    local walls, balls, fromballs = {}, {}, {}
    for _, wl in ipairs(S.walls) do walls[#walls + 1] = m:wall(wl) end
    local template = S.template and m:clump_template(S.template)
    for i, b in ipairs(S.balls) do
        local d = S.clumps and S.clumps[i] and ballDef(S.clumps[i]) or ballDef(b)
        local fapp, mapp = d.fapp, d.mapp
        d.fapp, d.mapp = nil, nil
        if d.template then d.template = template end
        local ball = S.clumps and S.clumps[i] and m:clump(d) or m:ball(d)
        if fapp then ball.fapp = fapp end
        if mapp then ball.mapp = mapp end
        balls[#balls + 1] = ball
    end
    for j, fb in ipairs(S.fromballs or {}) do
        local d = { balls = {}, density = fb.density }
        for _, k in ipairs(fb.balls) do d.balls[#d.balls + 1] = balls[k] end
        fromballs[j] = m:clump(d)
    end
    -- Groups of the energy books, named before tracing starts (a group named later starts with
    -- empty books). A ball that became a pebble takes its clump's groups.
    local G = S.groups
    if G then
        for i, h in ipairs(balls) do
            if not (S.absorbed and S.absorbed[i]) then for _, g in ipairs(G.balls[i]) do h:add_group(g) end end
        end
        for i, h in ipairs(walls) do for _, g in ipairs(G.walls[i]) do h:add_group(g) end end
        for j, h in ipairs(fromballs) do for _, g in ipairs(G.fromballs[j]) do h:add_group(g) end end
    end
    S.handles = { balls = balls, walls = walls, fromballs = fromballs }
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
            -- A body released or deleted by an earlier event is left alone.
            local h = ev.fromballs and S.handles.fromballs[ev.fromballs] or (ev.ball and S.handles.balls[ev.ball])
            if (ev.kind == "delete" or ev.kind == "cdelete") and h.alive then
                h:delete()
            elseif ev.kind == "release" and h.alive then
                h:release()
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
    if S.template then w("local T = m:clump_template" .. lit(S.template)) end
    for i, b in ipairs(S.balls) do
        local c = S.clumps and S.clumps[i]
        local d = ballDef(c or b)
        local fapp, mapp = d.fapp, d.mapp
        d.fapp, d.mapp = nil, nil
        local tpl = d.template
        d.template = nil
        local line = "B[#B + 1] = m:" .. (c and "clump" or "ball") .. lit(d)
        if tpl then line = line:gsub("^(B%[#B %+ 1%] = m:clump{ )", "%1template = T, ") end
        if fapp then line = line .. "; B[#B].fapp = " .. lit(fapp) end
        if mapp then line = line .. "; B[#B].mapp = " .. lit(mapp) end
        w(line)
    end
    w("local C = {}")
    for j, fb in ipairs(S.fromballs or {}) do
        local parts = {}
        for _, k in ipairs(fb.balls) do parts[#parts + 1] = "B[" .. k .. "]" end
        w(string.format("C[%d] = m:clump{ balls = {%s}%s }", j, table.concat(parts, ", "),
            fb.density and (", density = " .. num(fb.density)) or ""))
    end
    local G = S.groups
    if G then
        for i in ipairs(S.balls) do
            if not (S.absorbed and S.absorbed[i]) then
                for _, g in ipairs(G.balls[i]) do w(string.format("B[%d]:add_group(%q)", i, g)) end
            end
        end
        for i in ipairs(S.walls) do for _, g in ipairs(G.walls[i]) do w(string.format("W[%d]:add_group(%q)", i, g)) end end
        for j in ipairs(S.fromballs or {}) do for _, g in ipairs(G.fromballs[j]) do w(string.format("C[%d]:add_group(%q)", j, g)) end end
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
    if G then
        w("  for _, g in ipairs(" .. lit(G.names) .. ") do")
        w("    local f = m:energies(g)")
        w("    print(string.format('  %s: kinetic %.6g strain %.6g body %.6g boundary %.6g exchanged %.6g balance_error %.6g J', g, f.kinetic, f.strain, f.body, f.boundary, f.exchanged, f.balance_error))")
        w("  end")
    end
    w("end")
    for i, k in ipairs(gen.plan(S)) do
        w(string.format("m:cycle(%d) report()", k))
        if i == 1 and S.idle then w(string.format("m:gravity(%s)", lit(S.gravity))) end
        for _, ev in ipairs(S.events or {}) do
            if ev.chunk == i and ev.kind ~= "wallvel" then
                local h = ev.fromballs and string.format("C[%d]", ev.fromballs) or string.format("B[%d]", ev.ball)
                w(string.format("if %s.alive then %s:%s() end", h, h, ev.kind == "release" and "release" or "delete"))
            end
            if ev.chunk == i and ev.kind == "wallvel" then w(string.format("W[%d].vel = %s", ev.wall, lit(ev.vel))) end
        end
    end
    return table.concat(out, "\n") .. "\n"
end

return gen
