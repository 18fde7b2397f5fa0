-- SPDX-License-Identifier: MIT
-- material/bodies.lua: what a genesis packs (genesis.lua): single balls, or rigid grains of one
-- to three touching balls (clumps). A kind draws its bodies' sizes, gives the balls of a body
-- placed at a point, makes the bodies in a model, grows and shrinks them, names the bodies of a
-- contact, deletes one, and writes the packing's balls; the genesis steps are the same for all.
local U = require("material.util")

-- The sum over ball-ball contacts of overlap / (R1 + R2), and their count: the mean relative
-- overlap behind both kinds' affine estimate of the bulk stiffness.
local function overlap_sum(m)
    local rel, nc = 0, 0
    for c in m:contacts{} do
        local b2 = c.ball2
        if b2 and c.overlap > 0 then
            rel = rel + c.overlap / (c.ball1.radius + b2.radius); nc = nc + 1
        end
    end
    return rel, nc
end

local B = {}

--- Groups balls into grains of at most kmax touching balls. nbrs[i] lists the balls touching
--- ball i (indices 1..n, any order); u01 a uniform generator. The balls are visited in a
--- random order (Fisher-Yates); a ball not yet in a grain starts one and takes up to kmax - 1
--- of its touching neighbours that are not in a grain either, drawn at random. So every member
--- of a grain touches its first ball, and no ball is in two grains. Returns the grains of two or
--- more balls (lists of indices, ascending; in the order they were made) and counts[k] = the
--- number of grains of k balls (singles included).
function B.group_grains(nbrs, kmax, u01)
    local n = #nbrs
    local order = {}
    for i = 1, n do order[i] = i end
    for i = n, 2, -1 do
        local j = 1 + math.floor(u01() * i)
        order[i], order[j] = order[j], order[i]
    end
    local owner, grains, counts = {}, {}, {}
    for _, i in ipairs(order) do
        if not owner[i] then
            local free, seen = {}, {}
            for _, j in ipairs(nbrs[i]) do
                if not owner[j] and j ~= i and not seen[j] then free[#free + 1] = j; seen[j] = true end
            end
            table.sort(free) -- the neighbour lists' order (contact order) does not matter
            local g = { i }
            for k = 1, math.min(kmax - 1, #free) do
                local r = k + math.floor(u01() * (#free - k + 1))
                free[k], free[r] = free[r], free[k]
                g[#g + 1] = free[k]
            end
            for _, j in ipairs(g) do owner[j] = true end
            counts[#g] = (counts[#g] or 0) + 1
            if #g > 1 then
                table.sort(g)
                grains[#grains + 1] = g
            end
        end
    end
    for k = 1, kmax do counts[k] = counts[k] or 0 end
    return grains, counts
end

--- Single balls with radii uniform in [rmin, rmax]. With clump_max > 1 the packing's touching
--- balls are grouped at random into grains of up to clump_max (B.group_grains), which
--- M.specimen makes rigid; clump_max = nil: no grouping and no `genesis.clump_max` in the
--- packing. `seed`: the genesis seed (the grouping draws from its own stream).
function B.balls(rmin, rmax, clump_max, seed)
    local k = { noun = "ball", movable = true, units = {}, radii = {}, balls = {} }

    -- radii until the balls' area reaches target_area (Potyondy & Cundall 2004: the number
    -- follows from the porosity); the last one is cut to the area left unless below rmin
    function k:draw(u01, target_area)
        local radii, area = self.radii, 0
        while area < target_area do
            local r = rmin + (rmax - rmin) * u01()
            if area + math.pi * r * r > target_area then
                r = math.sqrt((target_area - area) / math.pi)
                if r < rmin then break end
            end
            radii[#radii + 1] = r; area = area + math.pi * r * r
        end
        for i, r in ipairs(radii) do self.units[i] = { bound = r } end
    end

    -- the balls {x, y, r} of unit `u` centred at (x, y) at scale s (draws nothing)
    function k:pebbles_at(u, x, y, s) return { { x, y, u.bound * s } } end

    function k:create(m, rho)
        for i, u in ipairs(self.units) do
            local p = u.pebbles[1]
            self.balls[i] = m:ball{ pos = { p[1], p[2] }, radius = p[3], density = rho, group = "rock" }
        end
    end

    -- radii written in place: the engine re-boxes a ball grown past its broadphase box, and the
    -- contacts are kept
    function k:expand(f)
        for i, b in ipairs(self.balls) do b.radius = self.radii[i] * f end
    end

    function k:shrink(f)
        for i, b in ipairs(self.balls) do
            if b.alive then
                self.radii[i] = self.radii[i] * f
                b.radius = self.radii[i]
            end
        end
    end

    -- The affine estimate of the bulk stiffness, B = sigma / (mean overlap / (R1 + R2)), and
    -- the fraction of the step to take with it (all of it).
    function k:affine_modulus(m, sig)
        local rel, nc = overlap_sum(m)
        rel = nc > 0 and rel / nc or 0
        return rel > 0 and sig / rel or nil, 1
    end

    function k:rmean() return 0.5 * (rmin + rmax) end
    -- the bodies of a contact (the second nil at a wall)
    function k:ends(c)
        local b2 = c.ball2
        return c.ball1.id, b2 and b2.id
    end
    function k:count() return #self.balls end
    function k:alive(i) return self.balls[i].alive end
    function k:id(i) return self.balls[i].id end
    function k:delete(i) self.balls[i]:delete() end

    function k:packing(m, pk, say)
        local out, index_of = {}, {}
        for b in m:balls() do
            local p = b.pos
            out[#out + 1] = { p[1], p[2], b.radius }
            index_of[b.id] = #out
        end
        pk.balls = out
        pk.genesis.clump_max = clump_max
        if not (clump_max and clump_max > 1) then return end
        -- grains (Potyondy & Cundall's clumped grains, "randomly placed clumps of up to 3
        -- balls"): the balls touching at sigma0 (overlap > 0) are grouped, seeded, into clumps
        -- of up to clump_max; M.specimen makes them rigid (m:clump{balls}) before the bonds go
        -- in. Grouping balls that are each in equilibrium needs no relaxation: the forces
        -- between them cancel in the clump's sum, and the specimen starts stress-free anyway
        -- (m:bond reset).
        local nbrs = {}
        for i = 1, #out do nbrs[i] = {} end
        for c in m:contacts{} do
            local b2 = c.ball2
            if b2 and c.overlap > 0 then
                local i, j = index_of[c.ball1.id], index_of[b2.id]
                if i and j then
                    nbrs[i][#nbrs[i] + 1] = j; nbrs[j][#nbrs[j] + 1] = i
                end
            end
        end
        -- its own stream, so the grouping does not shift the other draws of the genesis
        local cu01 = U.drawer((seed * 1000003) ~ 0x636C756D70)
        pk.clumps, pk.grain_counts = B.group_grains(nbrs, clump_max, cu01)
        local f = {}
        for j = 1, clump_max do f[#f + 1] = string.format("%d: %.3f", j, (pk.grain_counts[j] or 0) * j / #out) end
        say("grains: fraction of balls in clumps of " .. table.concat(f, ", "))
    end
    return k
end

-- A grain's template for radii r (1 to 3): the pebble centres relative to the area-weighted
-- centroid, which is where m:clump puts `pos` (union = sum, the pebbles only touch): one ball;
-- two tangent; three mutually tangent (a triangle). Returns the pebbles {x, y, r} and the
-- bounding radius about the centroid.
local function template(r)
    local p
    if #r == 1 then
        p = { { 0, 0, r[1] } }
    elseif #r == 2 then
        p = { { 0, 0, r[1] }, { r[1] + r[2], 0, r[2] } }
    else
        -- mutually tangent: |p1 p2| = r1 + r2, |p1 p3| = r1 + r3, |p2 p3| = r2 + r3
        local d12, d13, d23 = r[1] + r[2], r[1] + r[3], r[2] + r[3]
        local x3 = (d13 * d13 - d23 * d23 + d12 * d12) / (2 * d12)
        p = { { 0, 0, r[1] }, { d12, 0, r[2] }, { x3, math.sqrt(d13 * d13 - x3 * x3), r[3] } }
    end
    local a, sx, sy = 0, 0, 0
    for _, q in ipairs(p) do
        local ai = q[3] * q[3]
        a = a + ai; sx = sx + ai * q[1]; sy = sy + ai * q[2]
    end
    local bound = 0
    for _, q in ipairs(p) do
        q[1], q[2] = q[1] - sx / a, q[2] - sy / a
        bound = math.max(bound, math.sqrt(q[1] * q[1] + q[2] * q[2]) + q[3])
    end
    return p, bound
end

--- Rigid grains of 1, 2 or 3 touching balls with radii uniform in [rmin, rmax], drawn with the
--- grain shares `shares` = {p1, p2, p3} (fractions of the grains). Each is a clump (a grain of
--- one ball too: a one-pebble clump moves as a ball bit for bit, docs/physics/clumps.md), mass
--- mode "sum" as M.specimen's. Growing a grain is re-making it at a larger `scale` about its
--- centroid with its angle and velocity: rigid throughout, and its contacts (frictionless, so
--- without shear history) are found again in the next step. A grain can neither be moved into
--- a cage as a floating ball is, nor grown alone without overlap: not movable.
function B.grains(rmin, rmax, shares)
    local k = { noun = "grain", movable = false, interlocking = true, units = {} }
    local psum = 0
    for _, p in ipairs(shares) do psum = psum + p end

    function k:draw(u01, target_area)
        local area = 0
        while area < target_area do
            local u, n, acc = u01() * psum, #shares, 0
            for i, p in ipairs(shares) do
                acc = acc + p
                if u < acc then n = i; break end
            end
            local r = {}
            for i = 1, n do
                r[i] = rmin + (rmax - rmin) * u01()
                area = area + math.pi * r[i] * r[i]
            end
            local base, bound = template(r)
            self.units[#self.units + 1] = { base = base, bound = bound }
        end
    end

    -- the pebbles of grain `u` with its centroid at (x, y) at scale s, at an angle drawn
    -- uniform in [0, 2 pi)
    function k:pebbles_at(u, x, y, s, u01)
        local th = 2 * math.pi * u01()
        local c, sn = math.cos(th), math.sin(th)
        local pts = {}
        for _, q in ipairs(u.base) do
            pts[#pts + 1] = { x + s * (c * q[1] - sn * q[2]), y + s * (sn * q[1] + c * q[2]), s * q[3] }
        end
        return pts, th
    end

    local m_, rho_
    local function make(g, pos, angle, vel, spin)
        g.c = m_:clump{ pebbles = g.base, pos = pos, angle = angle, scale = k.cur, density = rho_,
                        mass_mode = "sum", vel = vel, spin = spin, group = "rock" }
    end
    local function rescale(f)
        k.cur = f
        for _, g in ipairs(k.units) do
            if not g.dead then
                local c = g.c
                local p, a, v, w = c.pos, c.angle, c.vel, c.spin
                c:delete()
                make(g, p, a, v, w)
            end
        end
    end

    function k:create(m, rho, s)
        m_, rho_, self.cur = m, rho, s
        for _, g in ipairs(self.units) do make(g, g.pos, g.angle, { 0, 0 }, 0) end
    end
    function k:expand(f) rescale(f) end
    function k:shrink(f) rescale(self.cur * f) end

    -- The affine estimate from the mean overlap per pebble-radius sum; a grain's contact gaps
    -- move by more than eps (r1 + r2) when it shrinks about a centroid off the pebble's centre,
    -- so B may be underestimated: only half the step is taken.
    function k:affine_modulus(m, sig)
        local rel, nc = overlap_sum(m)
        return (nc > 0 and rel > 0) and sig * nc / rel or nil, 0.5
    end

    function k:rmean() return 0.5 * (rmin + rmax) * self.cur end
    function k:ends(c)
        local k2 = c.clump2
        return c.clump1.id, k2 and k2.id
    end
    function k:count() return #self.units end
    function k:alive(i) return not self.units[i].dead end
    function k:id(i) return self.units[i].c.id end
    function k:delete(i)
        local g = self.units[i]
        g.c:delete(); g.dead = true
    end

    -- every grain's pebbles in world coordinates (a grain's ball indices consecutive), the
    -- grains of 2 and 3 as index lists for M.specimen
    function k:packing(_, pk, say)
        local out, clumps, counts = {}, {}, {}
        for j = 1, #shares do counts[j] = 0 end
        for _, g in ipairs(self.units) do
            if not g.dead then
                local idx = {}
                for _, p in ipairs(g.c:pebbles()) do
                    out[#out + 1] = { p.pos[1], p.pos[2], p.radius }
                    idx[#idx + 1] = #out
                end
                counts[#idx] = (counts[#idx] or 0) + 1
                if #idx > 1 then clumps[#clumps + 1] = idx end
            end
        end
        pk.balls, pk.clumps, pk.grain_counts = out, clumps, counts
        pk.rmin, pk.rmax, pk.scale = rmin * self.cur, rmax * self.cur, self.cur
        pk.genesis.clump_max, pk.genesis.shares, pk.genesis.method = #shares, shares, "clump_genesis"
        local f = {}
        for j = 1, #shares do f[#f + 1] = string.format("%d: %.3f", j, counts[j] * j / #out) end
        say("fraction of balls in grains of " .. table.concat(f, ", "))
    end
    return k
end

return B
