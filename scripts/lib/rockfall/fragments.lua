-- SPDX-License-Identifier: MIT
-- rockfall/fragments.lua: the fragments of a bonded rock (the connected pieces of its intact
-- bonds), each with its mass, centre, velocity and energy, and the statistics of a set of
-- fragments: the cumulative mass curve, the largest fragment's share and a Rosin-Rammler fit.

local F = {}

--- Union-find over the balls of a rock: `index[ball.id]` -> 1..n, joined along every intact
--- bond (a contact of the bond model with bonded = 1 between two of the balls). Returns the
--- root of each ball (a list indexed like `balls`).
local function components(m, balls, bond_model)
    local n = #balls
    local parent, index = {}, {}
    for k = 1, n do
        parent[k] = k
        index[balls[k].id] = k
    end
    local function find(k)
        while parent[k] ~= k do
            parent[k] = parent[parent[k]]
            k = parent[k]
        end
        return k
    end
    for c in m:contacts{ model = bond_model } do
        local b2 = c.ball2
        if b2 and c:prop("bonded") == 1 then
            local i, j = index[c.ball1.id], index[b2.id]
            if i and j then
                local ri, rj = find(i), find(j)
                if ri ~= rj then
                    if ri < rj then parent[rj] = ri else parent[ri] = rj end
                end
            end
        end
    end
    local root = {}
    for k = 1, n do root[k] = find(k) end
    return root
end

--- The fragments of the live balls `balls` (a list of ball handles) joined by intact bonds of
--- `bond_model`: a list, largest first (ties by the lowest ball index), of
--- { balls = {k, ...} (indices into `balls`), n, mass, x, y (centre of mass), vx, vy (its
---   velocity: momentum / mass), ke (the balls' kinetic energy, spin included), ke_centre
---   (1/2 mass v_centre^2), size (equivalent diameter 2 sqrt(area / pi) of the balls' area) }.
function F.find(m, balls, bond_model)
    local root = components(m, balls, bond_model)
    local by_root, list = {}, {}
    for k, b in ipairs(balls) do
        local r = root[k]
        local f = by_root[r]
        if not f then
            f = { balls = {}, n = 0, mass = 0, mx = 0, my = 0, px = 0, py = 0, ke = 0, area = 0, first = k }
            by_root[r] = f
            list[#list + 1] = f
        end
        local mass, p, v, w, rad = b.mass, b.pos, b.vel, b.spin, b.radius
        f.n = f.n + 1
        f.balls[f.n] = k
        f.mass = f.mass + mass
        f.mx, f.my = f.mx + mass * p[1], f.my + mass * p[2]
        f.px, f.py = f.px + mass * v[1], f.py + mass * v[2]
        f.ke = f.ke + 0.5 * mass * (v[1] * v[1] + v[2] * v[2]) + 0.5 * b.inertia * w * w
        f.area = f.area + math.pi * rad * rad
    end
    for _, f in ipairs(list) do
        f.x, f.y = f.mx / f.mass, f.my / f.mass
        f.vx, f.vy = f.px / f.mass, f.py / f.mass
        f.ke_centre = 0.5 * f.mass * (f.vx * f.vx + f.vy * f.vy)
        f.size = 2 * math.sqrt(f.area / math.pi)
        f.mx, f.my, f.px, f.py = nil, nil, nil, nil
    end
    table.sort(list, function(a, b)
        if a.mass ~= b.mass then return a.mass > b.mass end
        return a.first < b.first
    end)
    return list
end

--- Order of fragments: larger mass first, ties by the centre's x (deterministic).
function F.larger(a, b)
    if a.mass ~= b.mass then return a.mass > b.mass end
    return a.x < b.x
end

--- Least-squares line y = a + b x; nil with fewer than two distinct x.
local function line_fit(xs, ys)
    local n = #xs
    if n < 2 then return nil end
    local sx, sy, sxx, sxy = 0, 0, 0, 0
    for k = 1, n do
        sx, sy = sx + xs[k], sy + ys[k]
        sxx, sxy = sxx + xs[k] * xs[k], sxy + xs[k] * ys[k]
    end
    local d = n * sxx - sx * sx
    if not (d > 1e-12 * math.max(1, n * sxx)) then return nil end
    local b = (n * sxy - sx * sy) / d
    return (sy - b * sx) / n, b
end
F.line_fit = line_fit

--- The mass distribution of fragments `frags` (each with mass and size): the cumulative curve
--- (size ascending, passing = the mass share of fragments no larger), the largest fragment's
--- share, and the Rosin-Rammler law P(d) = 1 - exp(-(d / d0)^n) fitted by least squares on
--- ln(-ln(1 - P)) against ln d over the curve's points below P = 1 (Rosin & Rammler 1933), with
--- its parameters d0 [m] and n; nil parameters when the curve has fewer than two such points
--- (the rock did not break, or broke into two).
function F.distribution(frags)
    local total = 0
    for _, f in ipairs(frags) do total = total + f.mass end
    local sorted = {}
    for k, f in ipairs(frags) do sorted[k] = f end
    table.sort(sorted, function(a, b) return a.size < b.size end)
    local curve, acc = {}, 0
    for _, f in ipairs(sorted) do
        acc = acc + f.mass
        local last = curve[#curve]
        if last and last.size == f.size then last.passing = acc / total
        else curve[#curve + 1] = { size = f.size, passing = acc / total } end
    end
    local xs, ys = {}, {}
    for _, p in ipairs(curve) do
        if p.passing < 1 - 1e-12 then
            xs[#xs + 1] = math.log(p.size)
            ys[#ys + 1] = math.log(-math.log(1 - p.passing))
        end
    end
    local a, n = line_fit(xs, ys)
    local d0 = n and n ~= 0 and math.exp(-a / n) or nil
    local largest = 0
    for _, f in ipairs(frags) do largest = math.max(largest, f.mass) end
    return { curve = curve, total = total, largest_share = total > 0 and largest / total or 0,
        rr_d0 = d0, rr_n = n }
end

return F
