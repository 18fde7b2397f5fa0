-- SPDX-License-Identifier: MIT
-- rockfall/breakable.lua: a rock that breaks. The rock's shape (any rockfall shape) filled with
-- balls by the material library's genesis, bonded with a named or given bonded material
-- (parallel bonds or flat joints), released like a rigid rock and run to rest; its fragments
-- (fragments.lua) found at every breakage episode ("impact") and at the end.
local K = require("rockfall.check")
local Model = require("rockfall.model")
local Shapes = require("rockfall.shapes")
local Fr = require("rockfall.fragments")
local fail, check_keys, num = K.fail, K.check_keys, K.num

local B = {}

local KEYS = { "material", "balls", "size", "emod", "bond", "seed", "break_gap", "min_fragment", "slope_kn", "settle", "safety" }

-- The default modulus of the balls' contacts and bonds [Pa]: a rock of 500 balls runs to rest
-- on a slope in about a minute of CPU at this stiffness (docs/rockfall.md, "Rocks that break").
B.DEFAULT_EMOD = 1e8

-- The normal stiffness of a ball's contact with the slope [N/m] (ks half of it; the slope
-- material's damping, friction and rolling resistance are kept), when `slope_kn` is given:
-- otherwise the material's own. Stiffer than the balls' bonds it is resolved in fewer than 10
-- steps (B.TIMESTEP); much softer, a heavy rock's first balls may be pushed through it.
B.SLOPE_KN = nil

-- The strengths a softened material scales by sqrt(E' / E).
local STRENGTHS = { "pb_ten", "pb_coh", "fj_ten", "fj_coh", "cb_tenf", "cb_shearf" }

--- Softens material `mat` to modulus `emod` (its contacts' and bonds' deformability modulus,
--- PFC's kn = emod x area / length) and scales its strengths by sqrt(emod / E), E the
--- material's own modulus (mat.kn). Why: an elastic rock hitting the ground at speed v carries a
--- stress rho c v, c = sqrt(E / rho), and at failure stores sigma^2 / (2 E) per unit volume
--- against its kinetic energy 1/2 rho v^2; both ratios, sigma / (v sqrt(rho E)) and
--- sigma^2 / (E rho v^2), stay the same when sigma scales with sqrt(E). So a softer rock breaks
--- at the same impact speeds as the stiff one, with a time step sqrt(E / emod) times longer;
--- what changes is the strain at failure (sigma / E grows by sqrt(E / emod)) and the impact's
--- duration.
function B.soften(mat, emod)
    local E = mat.kn
    local kr = mat.ks and mat.kn and mat.kn / mat.ks or 2.5
    mat.kn, mat.ks = emod, emod / kr
    mat.bond = mat.bond or {}
    for _, name in ipairs({ "emod", "pb_emod", "fj_emod" }) do
        if mat.bond[name] ~= nil then mat.bond[name] = emod end
    end
    local f = math.sqrt(emod / E)
    for _, name in ipairs(STRENGTHS) do
        local v = mat.bond[name]
        if type(v) == "number" then
            mat.bond[name] = v * f
        elseif type(v) == "table" then
            mat.bond[name] = { mean = v.mean * f, sd = v.sd and v.sd * f, dist = v.dist }
        end
    end
    mat.strength_factor = f
    return mat
end

-- The step of a bonded rock: the stability rule only. The resolution rule (the rigid rock's 20
-- steps per contact duration, or even the guard's 10) reads each bond as an impact and takes a
-- step 6 times smaller than the stability rule's. A ball's impact on the slope is resolved by
-- the stability step all the same while the slope is softer than the ball's bonds: about
-- 2.5 pi sqrt(sum of the ball's bond stiffnesses / slope kn) steps, about 20 at the default
-- slope_kn. The safety factor 0.5 (the engine's is 0.8) keeps the books of a hard impact on an
-- unbroken rock within 1 % (2.1 % at 0.8; tests/scripting/regress/rockfall_breakable_energy.lua).
B.TIMESTEP = { resolution = 0, safety = 0.5 }

--- The named bonded materials: the material library's Lac du Bonnet granite with parallel bonds
--- (Potyondy & Cundall 2004) or flat joints (Potyondy 2012). A material is a table as
--- M.specimen takes it: { model =, kn =, ks =, fric =, bond = {...}, slit = ... }.
local function named_material(name)
    local M = require("material")
    if name == "lac_du_bonnet" or name == "lac_du_bonnet_pbond" then return (M.lac_du_bonnet("pbond")) end
    if name == "lac_du_bonnet_fjoint" then return (M.lac_du_bonnet("fjoint")) end
    return nil
end
B.MATERIALS = { "lac_du_bonnet", "lac_du_bonnet_pbond", "lac_du_bonnet_fjoint" }

local function copy(t)
    local o = {}
    for k, v in pairs(t) do o[k] = type(v) == "table" and copy(v) or v end
    return o
end

--- Checks a seeder's `breakable` option; returns the resolved settings.
function B.check(spec, where)
    check_keys(spec, KEYS, where)
    local mat = spec.material or "lac_du_bonnet"
    if type(mat) == "string" then
        local named = named_material(mat)
        if not named then
            fail("%s.material: unknown material '%s' (known: %s)", where, mat, table.concat(B.MATERIALS, ", "))
        end
        mat = named
    elseif type(mat) ~= "table" or type(mat.model) ~= "string" then
        fail("%s.material must be a material name or a table {model =, kn =, ks =, fric =, bond = {...}}", where)
    else
        mat = copy(mat)
    end
    if spec.balls ~= nil and spec.size ~= nil then fail("%s: give balls or size, not both", where) end
    local o = { material = mat, seed = spec.seed or 1, min_fragment = spec.min_fragment or 1 }
    if spec.balls ~= nil then
        if math.type(spec.balls) ~= "integer" or spec.balls < 2 then
            fail("%s.balls must be an integer >= 2 (got %s)", where, tostring(spec.balls))
        end
        o.balls = spec.balls
    elseif spec.size ~= nil then
        o.size = num(spec.size, where .. ".size", 1e-9)
    else
        o.balls = 300
    end
    if math.type(o.seed) ~= "integer" then fail("%s.seed must be an integer", where) end
    if spec.emod ~= false then
        o.emod = num(spec.emod or B.DEFAULT_EMOD, where .. ".emod", 1)
        B.soften(mat, o.emod)
    end
    for k, v in pairs(spec.bond or {}) do
        mat.bond = mat.bond or {}
        mat.bond[k] = v
    end
    o.slope_kn = spec.slope_kn and num(spec.slope_kn, where .. ".slope_kn", 1) or B.SLOPE_KN
    o.break_gap = spec.break_gap and num(spec.break_gap, where .. ".break_gap", 0) or 0.1
    if spec.settle ~= nil and type(spec.settle) ~= "boolean" then fail("%s.settle must be true or false", where) end
    o.settle = spec.settle ~= false
    o.safety = spec.safety and num(spec.safety, where .. ".safety", 1e-3) or B.TIMESTEP.safety
    if o.safety > 1 then fail("%s.safety must be in (0, 1] (got %s)", where, tostring(o.safety)) end
    return o
end

-- ------------------------------------------------------------------ the rock's balls

-- Packings of unit geometries, made once per process (a genesis costs seconds).
local packing_cache = {}

--- The ball radius range for about `n` balls in area `area` (radii uniform in [a, 1.66 a], P&C's
--- ratio; the genesis' porosity target 0.16): n = 0.84 area / (pi E[r^2]), E[r^2] = 1.805 a^2.
local function radius_for(area, n)
    return math.sqrt(0.84 * area / (math.pi * 1.805 * n))
end

--- Whether (x, y) lies inside the union of the disks `peb`.
local function inside(peb, x, y)
    for _, p in ipairs(peb) do
        local dx, dy = x - p[1], y - p[2]
        if dx * dx + dy * dy < p[3] * p[3] then return true end
    end
    return false
end

--- The largest set of balls joined by touching (within `gap`) pairs: a rock in one piece.
local function connected(balls, gap)
    local n = #balls
    local parent = {}
    for k = 1, n do parent[k] = k end
    local function find(k)
        while parent[k] ~= k do parent[k] = parent[parent[k]]; k = parent[k] end
        return k
    end
    for i = 1, n do
        local a = balls[i]
        for j = i + 1, n do
            local b = balls[j]
            local dx, dy, rr = a[1] - b[1], a[2] - b[2], a[3] + b[3] + gap
            if dx * dx + dy * dy <= rr * rr then
                local ri, rj = find(i), find(j)
                if ri ~= rj then parent[math.max(ri, rj)] = math.min(ri, rj) end
            end
        end
    end
    local size = {}
    for k = 1, n do local r = find(k); size[r] = (size[r] or 0) + 1 end
    local best, bn = 1, 0
    for r, c in pairs(size) do if c > bn or (c == bn and r < best) then best, bn = r, c end end
    local out = {}
    for k = 1, n do if find(k) == best then out[#out + 1] = balls[k] end end
    return out
end

--- The rock's balls at unit scale: a box genesis over the shape's bounding box, the balls whose
--- centres lie inside the shape, its largest touching piece; centred on its centre of area.
local function unit_balls(geom, br, a)
    local key = string.format("%d|%.12g|", br.seed, a)
    for _, p in ipairs(geom) do key = key .. string.format("%.12g,%.12g,%.12g;", p[1], p[2], p[3]) end
    if packing_cache[key] then return packing_cache[key] end
    local xmin, ymin, xmax, ymax = math.huge, math.huge, -math.huge, -math.huge
    for _, p in ipairs(geom) do
        xmin, xmax = math.min(xmin, p[1] - p[3]), math.max(xmax, p[1] + p[3])
        ymin, ymax = math.min(ymin, p[2] - p[3]), math.max(ymax, p[2] + p[3])
    end
    local M = require("material")
    local rmax = 1.66 * a
    local pad = 2 * rmax
    -- the genesis' stiffness only sets the overlaps at its 0.1 MPa (reset when bonded)
    local pk = M.genesis{ width = xmax - xmin + 2 * pad, height = ymax - ymin + 2 * pad, rmin = a, rmax = rmax,
        porosity = 0.16, kn = 1e10 * (a / 0.01), ks = 4e9 * (a / 0.01), density = 2600, seed = br.seed }
    local x0, y0 = pk.box[1], pk.box[2]
    local kept = {}
    for _, p in ipairs(pk.balls) do
        local x, y = p[1] - x0 + xmin - pad, p[2] - y0 + ymin - pad
        if inside(geom, x, y) then kept[#kept + 1] = { x, y, p[3] } end
    end
    kept = connected(kept, 1e-3 * a)
    local ax, ay, at = 0, 0, 0
    for _, p in ipairs(kept) do
        local w = p[3] * p[3]
        ax, ay, at = ax + w * p[1], ay + w * p[2], at + w
    end
    ax, ay = ax / at, ay / at
    for _, p in ipairs(kept) do p[1], p[2] = p[1] - ax, p[2] - ay end
    packing_cache[key] = kept
    return kept
end

--- The unit-scale balls of rock `rk` (make_rock's) for settings `br`.
function B.rock_balls(rk, br)
    local geom = rk.pebbles
    local a
    if br.balls then
        a = radius_for(Shapes.union_area(geom), br.balls)
    else
        a = br.size / 1.33 / rk.scale -- the mean radius of [a, 1.66 a] is 1.33 a
    end
    return unit_balls(geom, br, a)
end

--- Places the rock's balls at its release state (rigid motion: v + w x r) and bonds them.
--- Returns the ball list and the ball density (the rigid rock's mass over the balls' area).
local function place_balls(m, s, br)
    local rk, rel = s.rock, s.release
    local unit = B.rock_balls(rk, br)
    local sc, ca, sa = rk.scale, math.cos(rk.angle), math.sin(rk.angle)
    local area = 0
    for _, p in ipairs(unit) do area = area + math.pi * (p[3] * sc) ^ 2 end
    -- the balls' density makes the rock's mass the rigid rock's (its pores are not rock)
    local density = rk.mass / area
    local balls = {}
    for k, p in ipairs(unit) do
        local dx, dy = sc * (ca * p[1] - sa * p[2]), sc * (sa * p[1] + ca * p[2])
        balls[k] = m:ball{ pos = { rel.x + dx, rel.y + dy }, radius = p[3] * sc, density = density,
            vel = { rel.vx - rel.spin * dy, rel.vy + rel.spin * dx }, spin = rel.spin, group = "rock" }
    end
    return balls, density
end

--- Bonds the rock: the contacts of the packing are made by one step (they start overlapping by
--- the genesis' tiny amount, on purpose) and the material's bonds installed stress-free at every
--- contact and near-contact (the material library's install_bonds).
local function bond_rock(m, br, balls)
    local rmin = math.huge
    for _, b in ipairs(balls) do rmin = math.min(rmin, b.radius) end
    local was = m:placement_warning(false)
    m:cycle(1)
    m:placement_warning(was)
    local mat = br.material
    local M = require("material")
    local n = M.install_bonds(m, { model = mat.model, kn = mat.kn, ks = mat.ks, fric = mat.fric, bond = mat.bond,
        slit = mat.slit, seed = br.seed }, mat.gap or 1e-3 * rmin)
    m:timestep{ max = B.bond_step(m, balls, mat, br.safety) }
    return n
end

--- The stable step of the bonded balls: safety x min over balls of sqrt(m / sum k), k of each
--- bond its linear part's kn plus the bond's normal stiffness (pb_kn x its area 2 pb_rad, per
--- unit thickness; fj_kn likewise). A cap on the automatic step: bonds installed across a gap
--- (near-contacts) were not all seen by the engine's stability rule, whose step then grew in a
--- fall until a hard impact at emod = 1e9 Pa pushed a ball through the slope.
function B.bond_step(m, balls, mat, safety)
    local ksum = {}
    for c in m:contacts{ model = mat.model } do
        if c.ball2 and c:prop("bonded") == 1 then
            local p = c:props()
            local k = (p.kn or 0) + (p.pb_kn or 0) * 2 * (p.pb_rad or 0) + (p.fj_kn or 0) * 2 * (p.fj_radius or 0)
            for _, b in ipairs({ c.ball1, c.ball2 }) do ksum[b.id] = (ksum[b.id] or 0) + k end
        end
    end
    local dt = math.huge
    for _, b in ipairs(balls) do
        local k = ksum[b.id]
        if k and k > 0 then dt = math.min(dt, math.sqrt(b.mass / k)) end
    end
    return (safety or B.TIMESTEP.safety) * dt
end

-- ------------------------------------------------------------------ the run

--- The analysis as the bonded rock's slope sees it: every material's kn set to br.slope_kn and
--- its ks to half of it, the rest as given.
function B.slope_view(an, br)
    local mats = {}
    for name, mat in pairs(an.materials) do
        local props = {}
        for k, v in pairs(mat.props or {}) do props[k] = v end
        if br.slope_kn then props.kn, props.ks = br.slope_kn, 0.5 * br.slope_kn end
        mats[name] = { model = mat.model, props = props }
    end
    return setmetatable({ materials = mats }, { __index = an })
end

--- The energy items of group "rock" now.
local function books(m)
    local e = m:energies("rock")
    return { t = m:time(), kinetic = e.kinetic, body = e.body, slip = e.slip, dashpot = e.dashpot,
        damping = e.damping, released = e.released, strain = e.strain, bond = e.bond, plastic = e.plastic,
        exchanged = e.exchanged, deleted = e.deleted, balance_error = e.balance_error }
end

--- The energy split of one breakage episode from the books before and after it.
local function split(b0, b1)
    local d = function(k) return b1[k] - b0[k] end
    return { ke_before = b0.kinetic, ke_after = b1.kinetic, gravity = d("body"), released = d("released"),
        slip = d("slip"), dashpot = d("dashpot"), damping = d("damping"), plastic = d("plastic"),
        strain = d("strain"), bond = d("bond"),
        residual = b0.kinetic + d("body") + d("exchanged") - (b1.kinetic + d("strain") + d("bond") + d("slip")
            + d("dashpot") + d("damping") + d("plastic") + d("released") + d("deleted")) }
end

--- Rows of the fragments for a record: mass, centre, velocity, energy, size, balls.
local function fragment_rows(frags, stop, t_end)
    local rows = {}
    for k, f in ipairs(frags) do
        rows[k] = { fragment = k, balls = f.n, mass = f.mass, size = f.size, x = f.x, y = f.y, vx = f.vx, vy = f.vy,
            ke = f.ke, ke_centre = f.ke_centre, stop = f.stop or stop, t_end = f.t_end or t_end }
    end
    return rows
end

--- One breakage episode's record: its times, broken bonds, the energy split, the fragments
--- then and their distribution.
local function episode_record(m, st, ep)
    local frags = st.fragments()
    for _, f in ipairs(st.left) do frags[#frags + 1] = f end
    for _, f in ipairs(st.settled) do frags[#frags + 1] = f end
    table.sort(frags, Fr.larger)
    local dist = Fr.distribution(frags)
    local big = 0
    for _, f in ipairs(frags) do if f.n >= st.min_fragment then big = big + 1 end end
    local rec = { t_start = ep.t_start, t_end = ep.t_last, broken = ep.broken, fragments = big,
        pieces = #frags, largest_share = dist.largest_share, rr_d0 = dist.rr_d0, rr_n = dist.rr_n,
        x = frags[1] and frags[1].x, y = frags[1] and frags[1].y,
        energy = split(ep.before, books(m)), curve = dist.curve }
    rec.energy_per_mass = rec.energy.ke_before / st.mass
    return rec
end

--- The run's state: balls, what leaves the slope, the books and the episodes.
local function new_state(m, an, s, br, balls)
    local st = { m = m, balls = balls, alive = {}, left = {}, settled = {}, rest_since = {}, mass = s.rock.mass,
        bond_model = br.material.model, min_fragment = br.min_fragment, episodes = {}, broken = 0 }
    for k = 1, #balls do st.alive[k] = true end
    --- The live balls and, for each, its index in st.balls.
    function st.live()
        local out, index = {}, {}
        for k, b in ipairs(st.balls) do
            if st.alive[k] then out[#out + 1] = b; index[#out] = k end
        end
        return out, index
    end
    --- The fragments of the live balls, each with `members` (its balls' indices in st.balls).
    function st.fragments()
        local live, index = st.live()
        local frags = Fr.find(m, live, st.bond_model)
        for _, f in ipairs(frags) do
            f.members = {}
            for i, j in ipairs(f.balls) do f.members[i] = index[j] end
        end
        return frags, live
    end
    st.lines = an.collectors and require("rockfall.tracking").rock_lines(an) or {}
    st.last_x, st.cross = {}, {}
    for k, b in ipairs(balls) do st.last_x[k] = b.pos[1] end
    local pts = s.points
    st.points = pts
    st.x_lo, st.x_hi = pts[1][1], pts[#pts][1]
    st.y_lo = an.y_min - 2 * s.rock.r_eq - 1
    local v = an.rest_speed
    st.ke_rest = an.rest_ke or 0.75 * st.mass * v * v
    return st
end

--- Balls that left the slope (beyond its ends or below it): the fragment each belongs to is
--- recorded (stop "left") and its balls deleted (their kinetic energy is booked as deleted).
local function remove_left(st)
    local out = false
    local lines, t = st.lines, nil
    for k, b in ipairs(st.balls) do
        if st.alive[k] then
            local p = b.pos
            local x, x0 = p[1], st.last_x[k]
            if x < st.x_lo or x > st.x_hi or p[2] < st.y_lo then out = true end
            -- the collector and barrier lines this ball crossed toward +x since the last sample
            -- (its first crossing of each counts, as for a rigid rock)
            for li, line in ipairs(lines) do
                if x0 < line.x and x >= line.x then
                    local c = st.cross[k] or {}
                    st.cross[k] = c
                    if not c[li] then
                        t = t or st.m:time()
                        local v, w, mass = b.vel, b.spin, b.mass
                        c[li] = { t = t, y = p[2], vx = v[1], vy = v[2], mass = mass,
                            ke = 0.5 * mass * (v[1] * v[1] + v[2] * v[2]) + 0.5 * b.inertia * w * w }
                    end
                end
            end
            st.last_x[k] = x
        end
    end
    if not out then return end
    for _, f in ipairs(st.fragments()) do
        local x = f.x
        if x < st.x_lo or x > st.x_hi or f.y < st.y_lo then
            f.stop, f.t_end = "left", st.m:time()
            st.left[#st.left + 1] = f
            for _, k in ipairs(f.members) do
                st.alive[k] = false
                st.balls[k]:delete()
            end
        end
    end
end

--- The crossings of the collector and barrier lines by fragment `f` (its member balls'
--- crossings, recorded whatever piece they belonged to then): a line counts when balls holding at
--- least half its mass crossed it; t, y, vx, vy are their mass-weighted means, ke their kinetic
--- energies' sum, height the centre's height above the ground less half the fragment's size.
local function fragment_crossings(st, f)
    local out = {}
    for li, line in ipairs(st.lines) do
        local m, t, y, vx, vy, ke = 0, 0, 0, 0, 0, 0
        for _, k in ipairs(f.members) do
            local c = st.cross[k] and st.cross[k][li]
            if c then
                m, t, y = m + c.mass, t + c.mass * c.t, y + c.mass * c.y
                vx, vy, ke = vx + c.mass * c.vx, vy + c.mass * c.vy, ke + c.ke
            end
        end
        if m >= 0.5 * f.mass then
            t, y, vx, vy = t / m, y / m, vx / m, vy / m
            out[#out + 1] = { line = line.name, kind = line.kind, t = t, x = line.x, y = y,
                height = y - require("rockfall.profile").ground_at(st.points, line.x) - 0.5 * f.size,
                vx = vx, vy = vy, v = math.sqrt(vx * vx + vy * vy), ke = ke,
                ke_trans = 0.5 * f.mass * (vx * vx + vy * vy) }
        end
    end
    return out
end

-- Simulated seconds between two looks for fragments at rest (settle): a look walks every contact
-- in Lua, a few milliseconds for a 500-ball rock.
B.SETTLE_EVERY = 0.25

--- Fragments at rest leave the model: the live balls' fragments (intact bonds) joined into
--- clusters by touching ball-ball contacts (fragments that lean on each other go together); a
--- cluster whose kinetic energy stayed below the rest rule (an.rest_speed, as for the whole
--- rock: 0.75 m v^2, or an.rest_ke x its mass share) for an.rest_time is recorded fragment by
--- fragment with stop "rest" and its balls deleted (their contacts' stored energy is booked as
--- released, their kinetic energy as deleted). Why: the rock's run lasts until its last moving
--- piece stops, and resting pieces cost as much per step as moving ones; with them gone a
--- 500-ball rock's steps cost what its moving balls cost. What it changes: a piece that comes
--- later cannot hit a removed one (the rigid workflow runs every rock alone for the same reason).
local function settle(st, an, t)
    local frags, live = st.fragments()
    if #frags == 0 then return end
    local frag_of = {}
    for fi, f in ipairs(frags) do
        for _, j in ipairs(f.balls) do frag_of[live[j].id] = fi end
    end
    local parent = {}
    for fi = 1, #frags do parent[fi] = fi end
    local function find(k)
        while parent[k] ~= k do parent[k] = parent[parent[k]]; k = parent[k] end
        return k
    end
    for c in st.m:contacts{} do
        local b2 = c.ball2
        if b2 and c.overlap > 0 then
            local a, b = frag_of[c.ball1.id], frag_of[b2.id]
            if a and b and a ~= b then
                local ra, rb = find(a), find(b)
                if ra ~= rb then parent[math.max(ra, rb)] = math.min(ra, rb) end
            end
        end
    end
    local clusters, order = {}, {}
    for fi, f in ipairs(frags) do
        local r = find(fi)
        local cl = clusters[r]
        if not cl then
            cl = { frags = {}, mass = 0, ke = 0, key = math.huge }
            clusters[r] = cl
            order[#order + 1] = r
        end
        cl.frags[#cl.frags + 1] = f
        cl.mass, cl.ke = cl.mass + f.mass, cl.ke + f.ke
        for _, j in ipairs(f.balls) do cl.key = math.min(cl.key, live[j].id) end
    end
    local since = {}
    for _, r in ipairs(order) do
        local cl = clusters[r]
        local v = an.rest_speed
        local limit = an.rest_ke and an.rest_ke * cl.mass / st.mass or 0.75 * cl.mass * v * v
        if cl.ke < limit then
            local t0 = st.rest_since[cl.key] or t
            since[cl.key] = t0
            if t - t0 >= an.rest_time then
                for _, f in ipairs(cl.frags) do
                    f.stop, f.t_end = "rest", t
                    st.settled[#st.settled + 1] = f
                    f.shapes = {}
                    for i, k in ipairs(f.members) do
                        local b = st.balls[k]
                        local p = b.pos
                        f.shapes[i] = { p[1], p[2], b.radius, b.density }
                    end
                    for _, k in ipairs(f.members) do
                        st.alive[k] = false
                        st.balls[k]:delete()
                    end
                end
                since[cl.key] = nil
            end
        end
    end
    st.rest_since = since
end

--- Runs the rock's model until it rests, leaves or runs out of time; breakage episodes are
--- opened by the first bond break after `break_gap` s without one (the books before are those
--- of the last sample at which the rock did not touch the slope, or the one before the break)
--- and closed `break_gap` s after their last break.
local function run_to_rest(m, an, st, br)
    local dt_sample = 0.005
    local last_free = books(m)
    local prev = last_free
    local ep, rest_since = nil, nil
    local t_max = an.t_max
    local next_settle = m:time() + B.SETTLE_EVERY
    while true do
        local t0 = m:time()
        local before_breaks = st.broken
        local n = math.max(1, math.floor(dt_sample / math.max(m:timestep().dt, 1e-12)))
        m:cycle(n)
        local now = books(m)
        local t = now.t
        local broke = st.broken > before_breaks
        if broke then
            if not ep then
                local base = (prev.t - last_free.t <= 0.2) and last_free or prev
                ep = { t_start = t, before = base, broken = 0, broken0 = before_breaks }
            end
            ep.t_last = t
        end
        if ep and t - ep.t_last >= br.break_gap then
            ep.broken = st.broken - ep.broken0
            st.episodes[#st.episodes + 1] = episode_record(m, st, ep)
            ep = nil
        end
        -- free flight: no dissipation at the slope in the sample
        if now.slip == prev.slip and now.dashpot == prev.dashpot and not ep then last_free = now end
        prev = now
        remove_left(st)
        if br.settle and t >= next_settle then
            settle(st, an, t)
            next_settle = t + B.SETTLE_EVERY
        end
        if #st.live() == 0 then return #st.settled > 0 and "rest" or "left", t end
        if now.kinetic < st.ke_rest then
            rest_since = rest_since or t
            if t - rest_since >= an.rest_time and not ep then return "rest", t end
        else
            rest_since = nil
        end
        if t >= t_max then
            if ep then
                ep.broken = st.broken - ep.broken0
                st.episodes[#st.episodes + 1] = episode_record(m, st, ep)
            end
            return "time", t
        end
    end
end

B.FRAGMENT_HEADER = { "rock", "fragment", "balls", "mass", "size", "x", "y", "vx", "vy", "ke", "ke_centre", "stop",
    "t_end" }
B.CROSSING_HEADER = { "rock", "fragment", "line", "kind", "t", "x", "y", "height", "vx", "vy", "v", "ke" }
B.BREAKAGE_HEADER = { "rock", "impact", "t_start", "t_end", "broken", "fragments", "pieces", "largest_share",
    "rr_d0", "rr_n", "energy_per_mass", "ke_before", "ke_after", "gravity", "released", "slip", "dashpot",
    "damping", "strain", "bond", "residual" }

--- The rows of rock_fragments.csv and rock_breakage.csv for the breakable rocks of `records`
--- (nil when none is breakable).
function B.csv_rows(records)
    local frs, brs, crs, any = {}, {}, {}, false
    for _, r in ipairs(records) do
        if r.breakable then
            any = true
            for _, f in ipairs(r.fragments) do
                frs[#frs + 1] = { r.rock, f.fragment, f.balls, f.mass, f.size, f.x, f.y, f.vx, f.vy, f.ke, f.ke_centre, f.stop, f.t_end }
            end
            for _, c in ipairs(r.fragment_crossings or {}) do
                crs[#crs + 1] = { r.rock, c.fragment, c.line, c.kind, c.t, c.x, c.y, c.height, c.vx, c.vy, c.v, c.ke }
            end
            for k, ep in ipairs(r.breakage.impacts) do
                local e = ep.energy
                brs[#brs + 1] = { r.rock, k, ep.t_start, ep.t_end, ep.broken, ep.fragments, ep.pieces, ep.largest_share,
                    ep.rr_d0, ep.rr_n, ep.energy_per_mass, e.ke_before, e.ke_after, e.gravity, e.released, e.slip,
                    e.dashpot, e.damping, e.strain, e.bond, e.residual }
            end
        end
    end
    if any then return frs, brs, crs end
end

--- For on_end's pictures and files: the pieces that left the run at rest are put back where they
--- rested, as fixed balls of group "rock" (the run is over: no step follows, and the record's
--- books were read before). Returns the fragment number (in `frags`, the record's order) of
--- every ball of the rock in the model, by ball id.
local function restore_settled(m, st, frags)
    local of = {}
    local was = m:placement_warning(false)
    for k, f in ipairs(frags) do
        if f.shapes then
            for _, p in ipairs(f.shapes) do
                local b = m:ball{ pos = { p[1], p[2] }, radius = p[3], density = p[4], group = "rock" }
                b.fix = true
                of[b.id] = k
            end
        elseif f.stop ~= "left" and f.members then
            for _, j in ipairs(f.members) do of[st.balls[j].id] = k end
        end
    end
    m:placement_warning(was)
    return of
end

--- Runs breakable rock i (draw `s`) alone on its slope; returns its record: the rigid rock's
--- fields (end_x, end_y: the largest fragment's centre; stop, t_end) and `fragments` (rows at the
--- end, largest first), `breakage` (the end's distribution; its `impacts`: the breakage episodes),
--- `balls`, `bonds`, `broken`, `reach_x` (the farthest fragment's end x) and `energy`.
function B.run_rock(an, i, s, opts)
    local br = s.breakable
    local warnings = {}
    -- A broadphase margin of half the balls' mean radius: the rigid rock's margin (its r_eq)
    -- would make every ball a candidate of every ball near it, a force law for each.
    local unit = B.rock_balls(s.rock, br)
    local rsum = 0
    for _, p in ipairs(unit) do rsum = rsum + p[3] end
    local margin = 0.5 * rsum / #unit * s.rock.scale
    local m = Model.new_model(an, margin, warnings, { resolution = B.TIMESTEP.resolution, safety = br.safety })
    -- Balls of the rock that touch (fragments, and the bonded pairs before bonding) meet with the
    -- material's own linear contact and rock_contact's damping: the default rock-rock contact
    -- (1e9 N/m, for rigid rocks) would be ten times stiffer than the rock's bonds.
    local mat = br.material
    m:contact_model("linear", { kn = mat.kn, ks = mat.ks or mat.kn, fric = mat.fric or 0.5,
        dp_nratio = (an.rock_contact.props or {}).dp_nratio or 0 })
    Model.build_slope(m, B.slope_view(an, br), s.points, s.materials)
    local balls = place_balls(m, s, br)
    m:energy{ on = true }
    local bonds = bond_rock(m, br, balls)
    local st = new_state(m, an, s, br, balls)
    m:on_event("bond_break", function() st.broken = st.broken + 1 end)
    if opts.on_model then opts.on_model(m, { rock = i, seed = s.seed, balls = balls, breakable = true }) end
    local stop, t_end = run_to_rest(m, an, st, br)
    local frags = st.fragments()
    for _, f in ipairs(st.left) do frags[#frags + 1] = f end
    for _, f in ipairs(st.settled) do frags[#frags + 1] = f end
    table.sort(frags, Fr.larger)
    local dist = Fr.distribution(frags)
    local rk = s.rock
    -- per-fragment crossings of the collector and barrier lines; the record's own crossings are
    -- the largest fragment's (its end point is the record's)
    local fcross = {}
    for k, f in ipairs(frags) do
        for _, c in ipairs(fragment_crossings(st, f)) do
            c.fragment = k
            fcross[#fcross + 1] = c
        end
    end
    local rec = {
        rock = i, seed = s.seed, seeder = s.seeder, shape = rk.shape, mass = rk.mass, volume = rk.volume,
        r_eq = rk.r_eq, density = rk.density, scale = rk.scale, angle = rk.angle, lifted = s.lifted or nil,
        release = { x = s.release.x, y = s.release.y, vx = s.release.vx, vy = s.release.vy, spin = s.release.spin },
        crossings = {}, barrier = {}, impacts = {}, env_height = {}, env_ke = {}, fragment_crossings = fcross,
        stop = stop, t_end = t_end, balls = #balls, bonds = bonds, broken = st.broken,
        fragments = fragment_rows(frags, stop, t_end),
        breakage = { pieces = #frags, largest_share = dist.largest_share, rr_d0 = dist.rr_d0, rr_n = dist.rr_n,
            curve = dist.curve, impacts = st.episodes },
        breakable = true,
    }
    local big, reach = 0, -math.huge
    for _, f in ipairs(frags) do
        if f.n >= br.min_fragment then big = big + 1 end
        reach = math.max(reach, f.x)
    end
    rec.breakage.fragments = big
    rec.end_x, rec.end_y, rec.reach_x = frags[1].x, frags[1].y, reach
    for _, c in ipairs(fcross) do
        if c.fragment == 1 and c.kind == "collector" then
            rec.crossings[#rec.crossings + 1] = { line = c.line, t = c.t, x = c.x, y = c.y, height = c.height,
                vx = c.vx, vy = c.vy, v = c.v, ke = c.ke, ke_trans = c.ke_trans, ke_rot = c.ke - c.ke_trans }
        end
    end
    local e = m:energies()
    rec.energy = { input = e.input, kinetic = e.kinetic, body = e.body, slip = e.slip, dashpot = e.dashpot,
        strain = e.strain, bond = e.bond, released = e.released, damping = e.damping, deleted = e.deleted,
        balance_error = e.balance_error }
    rec.steps = m:step()
    if #warnings > 0 then rec.warnings = warnings end
    rec.ball_fragment = restore_settled(m, st, frags)
    if opts.on_end then opts.on_end(m, rec) end
    return rec
end

return B
