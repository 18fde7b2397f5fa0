-- SPDX-License-Identifier: MIT
--
-- rockfall.lua: the rockfall workflow. Slope profiles split into material zones,
-- optional roughness, rock shapes (balls and clumps), point and line seeders with random
-- distributions, collectors, barriers, per-rock impacts and trajectories, end rules, mass
-- release and a Monte Carlo driver. docs/rockfall.md is the user's page; this header is the map.
--
--   local rockfall = require("rockfall")
--   local an = rockfall.analysis{ profile = {...}, materials = {...}, zones = {...},
--                                 seeders = {...}, collectors = {...}, barriers = {...}, seed = 1 }
--   local rec = rockfall.run_rock(an, 1)                  -- one independent rock
--   local recs = rockfall.monte_carlo(an, { n = 300, outdir = "out" })
--   local recs = rockfall.mass_release(an, { n = 50 })     -- rocks together, rock-rock contact
--
-- Units SI (m, kg, s, J, rad, rad/s); 2D bodies of unit thickness, so a rock's "volume" is its
-- area [m^2] and its mass density x area. Profiles run toward +x: rocks travel to larger x.
--
-- Every random draw of rock i comes from generators seeded by (analysis seed, i, purpose), so a
-- rock does not depend on how many rocks the analysis has, on their order, or on how they are
-- shared among workers (talus.map).

local rockfall = {}
rockfall.version = "1.0"

-- --------------------------------------------------------------------------------- errors

-- Input errors are raised as tables by `fail` and turned into ordinary messages by the public
-- entry points (`api`), whose `error(msg, 2)` names the user's script line that made the call.
local function fail(fmt, ...)
    error({ rockfall = true, msg = string.format(fmt, ...) }, 0)
end

local function api(name, fn)
    return function(...)
        local res = table.pack(pcall(fn, ...))
        if res[1] then return table.unpack(res, 2, res.n) end
        local e = res[2]
        if type(e) == "table" and e.rockfall then error("rockfall." .. name .. ": " .. e.msg, 2) end
        error(e, 0)
    end
end

local function sorted_keys(t)
    local k = {}
    for key in pairs(t) do k[#k + 1] = tostring(key) end
    table.sort(k)
    return k
end

--- "; did you mean 'x'?" for an unknown name among `known`, worded as the engine's errors.
local function hint(name, known)
    if type(name) ~= "string" or not (talus and talus.did_you_mean) then return "" end
    return talus.did_you_mean(name, known)
end

--- Refuses unknown option names (a typo is never ignored, as in the engine's API).
local function check_keys(t, known, where)
    if type(t) ~= "table" then fail("%s must be a table (got %s)", where, type(t)) end
    local set = {}
    for _, k in ipairs(known) do set[k] = true end
    for k in pairs(t) do
        if not set[k] then
            fail("unknown option '%s' in %s%s (known: %s)", tostring(k), where, hint(k, known),
                table.concat(known, ", "))
        end
    end
end

local function num(v, where, lo, hi)
    if type(v) ~= "number" or v ~= v then fail("%s must be a number (got %s)", where, tostring(v)) end
    if lo and v < lo then fail("%s must be >= %g (got %g)", where, lo, v) end
    if hi and v > hi then fail("%s must be <= %g (got %g)", where, hi, v) end
    return v
end

local function point(v, where)
    if type(v) ~= "table" or type(v[1]) ~= "number" or type(v[2]) ~= "number" or v[1] ~= v[1]
        or v[2] ~= v[2] then
        fail("%s must be a point {x, y} (got %s)", where, tostring(v))
    end
    return { v[1], v[2] }
end

-- --------------------------------------------------------------------------------- PRNG

-- splitmix64 (Steele, Lea & Flood 2014) on Lua 5.4's 64-bit integers: multiplication and addition
-- wrap modulo 2^64 and `>>` is a logical shift, which is what the algorithm needs. It passes
-- BigCrush, needs one integer of state, and `mix` doubles as the hash that derives seeds.
local GOLDEN = 0x9E3779B97F4A7C15

local function mix(z)
    z = (z ~ (z >> 30)) * 0xBF58476D1CE4E5B9
    z = (z ~ (z >> 27)) * 0x94D049BB133111EB
    return z ~ (z >> 31)
end

local Rng = {}
Rng.__index = Rng

--- A generator with its own stream: r:uniform() in [0, 1), r:normal(), r:range(a, b).
function rockfall.rng(seed)
    if math.type(seed) ~= "integer" then
        if type(seed) == "number" and seed == math.floor(seed) and math.abs(seed) < 2 ^ 63 then
            seed = math.tointeger(seed)
        else
            fail("a seed must be an integer (got %s)", tostring(seed))
        end
    end
    return setmetatable({ state = seed }, Rng)
end

function Rng:next()
    self.state = self.state + GOLDEN
    return mix(self.state)
end

function Rng:uniform()
    -- 53 random bits -> a double in [0, 1), every value equally likely.
    return (self:next() >> 11) * (1.0 / 9007199254740992.0)
end

function Rng:range(a, b) return a + (b - a) * self:uniform() end

function Rng:normal()
    -- Box-Muller with one of the pair: two uniforms per draw, so the number of draws never
    -- depends on earlier values (keeps streams aligned). 1 - u avoids log(0).
    local u1, u2 = 1.0 - self:uniform(), self:uniform()
    return math.sqrt(-2.0 * math.log(u1)) * math.cos(2.0 * math.pi * u2)
end

-- The purposes of a rock's streams: changing how one quantity is drawn never shifts another.
local STREAMS = {
    seeder = 1, position = 2, shape = 3, size = 4, density = 5, angle = 6, vx = 7, vy = 8,
    spin = 9, roughness = 10,
}

--- The integer seed of rock i in an analysis with seed s: a hash of (s, i) only.
function rockfall.rock_seed(s, i)
    return mix(mix(s) + i * GOLDEN)
end

--- The generator of one purpose of one rock (or of the analysis when rock_seed is its seed).
function rockfall.stream(rock_seed, purpose)
    local id = STREAMS[purpose] or fail("unknown random stream '%s'", tostring(purpose))
    return rockfall.rng(mix(rock_seed ~ (id * 0x632BE59BD9B4E019)))
end

-- --------------------------------------------------------------------------------- distributions

local DIST_KEYS = {
    uniform = { "dist", "min", "max" },
    normal = { "dist", "mean", "sd", "min", "max" },
    lognormal = { "dist", "mean", "sd", "mu", "sigma", "min", "max" },
}

--- Checks a quantity spec: a number (fixed) or {dist = "uniform"|"normal"|"lognormal", ...}.
local function check_dist(spec, where, lo)
    if type(spec) == "number" then return num(spec, where, lo) end
    if type(spec) ~= "table" then
        fail("%s must be a number or a distribution {dist = ...} (got %s)", where, tostring(spec))
    end
    local keys = DIST_KEYS[spec.dist]
    if not keys then
        fail("%s: dist must be \"uniform\", \"normal\" or \"lognormal\" (got %s)", where, tostring(spec.dist))
    end
    check_keys(spec, keys, where)
    if spec.dist == "uniform" then
        num(spec.min, where .. ".min")
        num(spec.max, where .. ".max")
        if spec.max < spec.min then fail("%s: max < min", where) end
        if lo and spec.min < lo then fail("%s: min must be >= %g (got %g)", where, lo, spec.min) end
    elseif spec.dist == "normal" then
        num(spec.mean, where .. ".mean")
        num(spec.sd, where .. ".sd", 0)
    else
        if spec.mu ~= nil or spec.sigma ~= nil then
            if spec.mean ~= nil or spec.sd ~= nil then
                fail("%s: give mean and sd, or mu and sigma (of log), not both", where)
            end
            num(spec.mu, where .. ".mu")
            num(spec.sigma, where .. ".sigma", 0)
        else
            num(spec.mean, where .. ".mean", 1e-300)
            num(spec.sd, where .. ".sd", 0)
        end
    end
    if spec.dist ~= "uniform" then
        if spec.min ~= nil then num(spec.min, where .. ".min") end
        if spec.max ~= nil then num(spec.max, where .. ".max") end
        local a, b = rockfall.bounds(spec)
        if b < a then fail("%s: max < min", where) end
        if lo and a < lo then
            if spec.min ~= nil or spec.dist == "normal" then
                fail("%s: the distribution reaches %g, below the allowed %g (set min)", where, a, lo)
            end
        end
    end
    return spec
end

--- The range a distribution is truncated to. Normal: mean -/+ 3 sd unless min/max are given
--- (0.27% of an untruncated normal lies outside; a rock with a negative mass is never drawn).
--- Lognormal: (0, inf) unless given.
function rockfall.bounds(spec)
    if type(spec) == "number" then return spec, spec end
    if spec.dist == "uniform" then return spec.min, spec.max end
    if spec.dist == "normal" then
        return spec.min or (spec.mean - 3 * spec.sd), spec.max or (spec.mean + 3 * spec.sd)
    end
    return spec.min or 0, spec.max or math.huge
end

local function lognormal_params(spec)
    if spec.mu then return spec.mu, spec.sigma end
    -- Moments of the variable itself: sigma^2 = ln(1 + (sd/mean)^2), mu = ln(mean) - sigma^2/2.
    local s2 = math.log(1 + (spec.sd / spec.mean) ^ 2)
    return math.log(spec.mean) - s2 / 2, math.sqrt(s2)
end

--- One draw of a quantity spec from generator r. Truncation by rejection (at most 10000
--- tries, then an error: a window that far in the tail is an input mistake).
function rockfall.draw(spec, r)
    if type(spec) == "number" then return spec end
    if spec.dist == "uniform" then return r:range(spec.min, spec.max) end
    local a, b = rockfall.bounds(spec)
    for _ = 1, 10000 do
        local v
        if spec.dist == "normal" then
            v = spec.mean + spec.sd * r:normal()
        else
            local mu, sigma = lognormal_params(spec)
            v = math.exp(mu + sigma * r:normal())
        end
        if v >= a and v <= b then return v end
    end
    fail("distribution %s: no draw fell in [%g, %g] in 10000 tries", spec.dist, a, b)
end

-- --------------------------------------------------------------------------------- profiles

--- Reads x,y points from a CSV file (a header line is allowed; '#' lines are comments).
local function read_csv(file)
    local f, err = io.open(file, "r")
    if not f then fail("cannot read profile '%s' (%s)", file, tostring(err)) end
    local pts, n = {}, 0
    for line in f:lines() do
        n = n + 1
        local s = line:gsub("#.*$", ""):gsub("^%s+", ""):gsub("%s+$", "")
        if s ~= "" then
            local a, b = s:match("^([^,;%s]+)[,;%s]+([^,;%s]+)")
            local x, y = tonumber(a), tonumber(b)
            if x and y then
                pts[#pts + 1] = { x, y }
            elseif #pts > 0 or not (a and b) then
                f:close()
                fail("profile '%s' line %d: expected two numbers x,y (got %q)", file, n, line)
            end -- else: the header
        end
    end
    f:close()
    return pts
end

local function check_points(pts, where)
    if type(pts) ~= "table" or #pts < 2 then
        fail("%s needs at least 2 points {x, y} (got %s)", where, type(pts) == "table" and #pts or tostring(pts))
    end
    local out = {}
    for k, p in ipairs(pts) do
        out[k] = point(p, string.format("%s point %d", where, k))
        if k > 1 then
            local q = out[k - 1]
            -- Toward +x, vertical steps allowed, no overhangs: ground(x) must be a function.
            if out[k][1] < q[1] then
                fail("%s: x must not decrease (point %d at x = %g follows x = %g); profiles run "
                    .. "toward +x without overhangs", where, k, out[k][1], q[1])
            end
            if out[k][1] == q[1] and out[k][2] == q[2] then
                fail("%s: points %d and %d coincide at (%g, %g)", where, k - 1, k, q[1], q[2])
            end
        end
    end
    return out
end

--- Height of polyline pts under x (segments searched by bisection; a vertical step gives its
--- lower end, so a rock on top of a step is measured from the step's foot only past it).
local function ground_at(pts, x)
    local n = #pts
    if x <= pts[1][1] then return pts[1][2] end
    if x >= pts[n][1] then return pts[n][2] end
    local lo, hi = 1, n
    while hi - lo > 1 do
        local mid = (lo + hi) // 2
        if pts[mid][1] < x then lo = mid else hi = mid end
    end
    local a, b = pts[lo], pts[hi]
    if b[1] == a[1] then return math.min(a[2], b[2]) end
    return a[2] + (b[2] - a[2]) * (x - a[1]) / (b[1] - a[1])
end
rockfall.ground = ground_at

--- Distance from p to the polyline.
local function polyline_distance(pts, px, py)
    local best = math.huge
    for k = 1, #pts - 1 do
        local a, b = pts[k], pts[k + 1]
        local ex, ey = b[1] - a[1], b[2] - a[2]
        local s = ((px - a[1]) * ex + (py - a[2]) * ey) / (ex * ex + ey * ey)
        s = math.max(0, math.min(1, s))
        local dx, dy = px - a[1] - s * ex, py - a[2] - s * ey
        best = math.min(best, math.sqrt(dx * dx + dy * dy))
    end
    return best
end

--- Subdivides every segment into pieces no longer than `spacing` (for roughness).
local function refine(pts, spacing)
    local out = { { pts[1][1], pts[1][2] } }
    for k = 1, #pts - 1 do
        local a, b = pts[k], pts[k + 1]
        local len = math.sqrt((b[1] - a[1]) ^ 2 + (b[2] - a[2]) ^ 2)
        local m = math.max(1, math.ceil(len / spacing - 1e-9))
        for j = 1, m do
            out[#out + 1] = { a[1] + (b[1] - a[1]) * j / m, a[2] + (b[2] - a[2]) * j / m }
        end
    end
    return out
end

--- RocFall-style roughness: every interior vertex moves along the bisector of its two segments'
--- normals (perpendicular to the slope there) by amplitude x u, u uniform in [-1, 1], so no
--- vertex moves farther than the amplitude. End points stay. Same seed, same profile.
local function roughen(pts, amplitude, seed)
    local r = rockfall.rng(seed)
    local out = { { pts[1][1], pts[1][2] } }
    for k = 2, #pts - 1 do
        local a, p, b = pts[k - 1], pts[k], pts[k + 1]
        local function unit_normal(u, v)
            local tx, ty = v[1] - u[1], v[2] - u[2]
            local l = math.sqrt(tx * tx + ty * ty)
            return -ty / l, tx / l -- the left normal: upward for a profile toward +x
        end
        local n1x, n1y = unit_normal(a, p)
        local n2x, n2y = unit_normal(p, b)
        local nx, ny = n1x + n2x, n1y + n2y
        local l = math.sqrt(nx * nx + ny * ny)
        if l < 1e-12 then nx, ny = n1x, n1y else nx, ny = nx / l, ny / l end
        local off = amplitude * (2 * r:uniform() - 1)
        out[k] = { p[1] + off * nx, p[2] + off * ny }
    end
    out[#pts] = { pts[#pts][1], pts[#pts][2] }
    for k = 2, #out do
        if out[k][1] < out[k - 1][1] then
            fail("roughness amplitude %g m folds the profile near x = %g (vertices %d and %d cross); "
                .. "lower the amplitude or refine more coarsely", amplitude, out[k][1], k - 1, k)
        end
    end
    return out
end

rockfall.read_csv = api("read_csv", read_csv)
rockfall.roughen = api("roughen", roughen)

-- --------------------------------------------------------------------------------- rock shapes

-- Unit geometries: pebbles {x, y, r} about the origin; `size` names what the shape's scale 1
-- means. The clump's centroid (exact union, engine) is put at the release point.
local SHAPES = {}

-- An's (2006, chapter 6) rock: three equal balls in mutual contact (an equilateral triangle of
-- side 2R), R = 0.04 m. Centred on the triangle's centroid. `thesis_a` is its older name, still
-- accepted.
SHAPES.three_balls = function(spec)
    local R = spec.radius or 0.04
    local h = R * math.sqrt(3) / 3
    return { { -R, -h, R }, { R, -h, R }, { 0, 2 * h, R } }
end
SHAPES.thesis_a = SHAPES.three_balls

SHAPES.ball = function(spec) return { { 0, 0, spec.radius or 0.5 } } end

-- Rounded n-gon of circumradius `radius`: n corner pebbles of radius corner x radius on a
-- circle, a centre pebble reaching the edges' midpoints (the apothem of the corner disks' hull)
-- and `edge_pebbles` more corner-size pebbles evenly along each edge (a ring approximating the
-- polygon with rounded corners).
SHAPES.ngon = function(spec)
    local n, R = spec.n or 6, spec.radius or 0.5
    local rc = (spec.corner or 0.3) * R
    local rr = R - rc
    local peb = {}
    local corners = {}
    for k = 0, n - 1 do
        local a = 2 * math.pi * k / n + math.pi / 2
        corners[#corners + 1] = { rr * math.cos(a), rr * math.sin(a) }
        peb[#peb + 1] = { corners[#corners][1], corners[#corners][2], rc }
    end
    local e = spec.edge_pebbles or 0
    for k = 1, n do
        local a, b = corners[k], corners[k % n + 1]
        for j = 1, e do
            local s = j / (e + 1)
            peb[#peb + 1] = { a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2]), rc }
        end
    end
    peb[#peb + 1] = { 0, 0, rr * math.cos(math.pi / n) + rc }
    return peb
end

-- A rock fitted to L1 x L2 (L1 >= L2): overlapping balls of radius L2/2 along the long axis,
-- the end balls touching the rock's ends, spaced at most L2/4 apart so that the waist between
-- two balls stays above 0.97 L2 (cos(asin(1/4)) = 0.968).
SHAPES.fitted = function(spec)
    local L1, L2 = spec.L1, spec.L2
    local r = L2 / 2
    local span = L1 - L2
    local m = math.max(1, math.ceil(span / (L2 / 4) - 1e-9))
    local peb = {}
    for j = 0, m do
        peb[#peb + 1] = { -span / 2 + span * j / m, 0, r }
    end
    if span <= 0 then peb = { { 0, 0, r } } end
    return peb
end

SHAPES.pebbles = function(spec) return spec.pebbles end

local ROCK_KEYS = {
    "shape", "name", "weight", "radius", "n", "corner", "edge_pebbles", "L1", "L2", "pebbles",
    "scale", "mass", "volume", "density", "angle",
}

local function check_rock(spec, where)
    check_keys(spec, ROCK_KEYS, where)
    local shape = spec.shape or "ball"
    if not SHAPES[shape] then
        fail("%s: unknown shape '%s'%s (known: ball, three_balls, ngon, fitted, pebbles)", where, tostring(shape),
            hint(shape, { "ball", "three_balls", "ngon", "fitted", "pebbles" }))
    end
    if spec.radius ~= nil then num(spec.radius, where .. ".radius", 1e-9) end
    if shape == "ngon" then
        if spec.n ~= nil and (math.type(spec.n) ~= "integer" or spec.n < 3) then
            fail("%s.n must be an integer >= 3 (got %s)", where, tostring(spec.n))
        end
        if spec.corner ~= nil then num(spec.corner, where .. ".corner", 0.01, 1) end
        if spec.edge_pebbles ~= nil and (math.type(spec.edge_pebbles) ~= "integer" or spec.edge_pebbles < 0) then
            fail("%s.edge_pebbles must be an integer >= 0", where)
        end
    elseif shape == "fitted" then
        num(spec.L1, where .. ".L1", 1e-9)
        num(spec.L2, where .. ".L2", 1e-9)
        if spec.L2 > spec.L1 then fail("%s: L2 (%g) must not exceed L1 (%g)", where, spec.L2, spec.L1) end
    elseif shape == "pebbles" then
        if type(spec.pebbles) ~= "table" or #spec.pebbles < 1 then
            fail("%s.pebbles must be a list of {x, y, r}", where)
        end
        for k, p in ipairs(spec.pebbles) do
            if type(p) ~= "table" or type(p[1]) ~= "number" or type(p[2]) ~= "number"
                or type(p[3]) ~= "number" or p[3] <= 0 then
                fail("%s.pebbles[%d] must be {x, y, r} with r > 0", where, k)
            end
        end
    end
    if spec.mass ~= nil and spec.volume ~= nil then
        fail("%s: give mass or volume, not both", where)
    end
    if spec.scale ~= nil and (spec.mass ~= nil or spec.volume ~= nil) and shape ~= "fitted" then
        fail("%s: give scale, or mass or volume (which set the scale), not both", where)
    end
    if spec.scale ~= nil then check_dist(spec.scale, where .. ".scale", 1e-9) end
    if spec.mass ~= nil then check_dist(spec.mass, where .. ".mass", 1e-12) end
    if spec.volume ~= nil then check_dist(spec.volume, where .. ".volume", 1e-12) end
    if spec.density ~= nil then check_dist(spec.density, where .. ".density", 1e-9) end
    if spec.angle ~= nil then check_dist(spec.angle, where .. ".angle") end
    if spec.weight ~= nil then num(spec.weight, where .. ".weight", 0) end
    return spec
end

--- Exact area [m^2] of a union of disks: Green's theorem on the free arcs (as the engine does,
--- docs/physics/clumps.md); used to size a rock before the model exists.
local function union_area(peb)
    local area = 0
    for i, p in ipairs(peb) do
        local covered, inside = {}, false
        for j, q in ipairs(peb) do
            if j ~= i then
                local dx, dy = q[1] - p[1], q[2] - p[2]
                local d = math.sqrt(dx * dx + dy * dy)
                local tol = 1e-12 * (p[3] + q[3])
                if d + p[3] <= q[3] + tol and (d > tol or q[3] > p[3] + tol or j < i) then
                    inside = true
                    break
                end
                if d < p[3] + q[3] and d + q[3] > p[3] + tol then
                    local ca = (d * d + p[3] * p[3] - q[3] * q[3]) / (2 * d * p[3])
                    local al = math.acos(math.max(-1, math.min(1, ca)))
                    local phi = math.atan(dy, dx)
                    local a, b = phi - al, phi + al
                    if a < -math.pi then
                        covered[#covered + 1] = { a + 2 * math.pi, math.pi }
                        covered[#covered + 1] = { -math.pi, b }
                    elseif b > math.pi then
                        covered[#covered + 1] = { a, math.pi }
                        covered[#covered + 1] = { -math.pi, b - 2 * math.pi }
                    else
                        covered[#covered + 1] = { a, b }
                    end
                end
            end
        end
        if not inside then
            table.sort(covered, function(u, v) return u[1] < v[1] end)
            local free, cur = {}, -math.pi
            for _, c in ipairs(covered) do
                if c[1] > cur then free[#free + 1] = { cur, c[1] } end
                cur = math.max(cur, c[2])
            end
            if cur < math.pi then free[#free + 1] = { cur, math.pi } end
            -- Area = 1/2 closed integral of (x dy - y dx) over arcs t0..t1 of circle (cx, cy, r):
            -- 1/2 [ r^2 (t1 - t0) + r cx (sin t1 - sin t0) - r cy (cos t1 - cos t0) ].
            local r, cx, cy = p[3], p[1], p[2]
            for _, f in ipairs(free) do
                area = area + 0.5 * (r * r * (f[2] - f[1]) + r * cx * (math.sin(f[2]) - math.sin(f[1]))
                    - r * cy * (math.cos(f[2]) - math.cos(f[1])))
            end
        end
    end
    return area
end
rockfall.union_area = union_area

--- The rock of one draw: pebbles (unit geometry), scale, density, angle, area, mass, r_eq.
local function make_rock(spec, rs)
    local geom = SHAPES[spec.shape or "ball"](spec)
    local area1 = union_area(geom)
    local density = rockfall.draw(spec.density or 2600, rs.density)
    local scale = 1
    local size_r = rs.size
    if spec.shape == "fitted" then
        -- Dimensions given: a mass sets the density, a volume the size.
        if spec.mass ~= nil then density = rockfall.draw(spec.mass, size_r) / area1 end
        if spec.volume ~= nil then scale = math.sqrt(rockfall.draw(spec.volume, size_r) / area1) end
        if spec.scale ~= nil then scale = scale * rockfall.draw(spec.scale, size_r) end
    elseif spec.mass ~= nil then
        scale = math.sqrt(rockfall.draw(spec.mass, size_r) / (density * area1))
    elseif spec.volume ~= nil then
        scale = math.sqrt(rockfall.draw(spec.volume, size_r) / area1)
    elseif spec.scale ~= nil then
        scale = rockfall.draw(spec.scale, size_r)
    end
    local area = area1 * scale * scale
    local bound = 0
    for _, p in ipairs(geom) do
        bound = math.max(bound, math.sqrt(p[1] * p[1] + p[2] * p[2]) + p[3])
    end
    local angle = 0
    if #geom > 1 then
        angle = rockfall.draw(spec.angle or { dist = "uniform", min = 0, max = 2 * math.pi }, rs.angle)
    elseif spec.angle ~= nil then
        angle = rockfall.draw(spec.angle, rs.angle)
    end
    return {
        shape = spec.name or spec.shape or "ball", pebbles = geom, scale = scale, density = density,
        angle = angle, volume = area, mass = density * area, r_eq = math.sqrt(area / math.pi),
        bound = bound * scale, ball = (#geom == 1 and geom[1][1] == 0 and geom[1][2] == 0),
    }
end

-- --------------------------------------------------------------------------------- analysis

local MATERIAL_KEYS = { "model", "props" }
local SEEDER_KEYS = { "kind", "name", "at", "from", "to", "weight", "rock", "vx", "vy", "spin" }
local ANALYSIS_KEYS = {
    "profile", "materials", "zones", "material", "roughness", "seeders", "collectors", "barriers",
    "seed", "n", "envelope", "gravity", "margin", "rest_speed", "rest_ke", "rest_time", "t_max",
    "impact_min_vn", "path_every", "rock_contact", "timestep", "clearance", "shadow_apex",
    "shadow_steep",
}

local function check_model(name, props, where)
    if type(name) ~= "string" then fail("%s.model must be a contact model name", where) end
    local ok, info = pcall(talus.contact_model_info, name)
    if not ok then fail("%s: contact model '%s' is not available (%s)", where, name, tostring(info)) end
    if props ~= nil then
        if type(props) ~= "table" then fail("%s.props must be a table", where) end
        local known, names = {}, {}
        for _, p in ipairs(info.properties) do
            known[p.name:lower()] = true
            if not p.read_only then names[#names + 1] = p.name end
        end
        for k in pairs(props) do
            if type(k) ~= "string" or not known[k:lower()] then
                fail("%s: unknown property '%s' for model '%s'%s (known: %s)", where, tostring(k), name,
                    hint(k, names), table.concat(names, ", "))
            end
        end
        -- A friction angle typed as a coefficient (RocFall gives angles): said once here, not
        -- by every rock's model (run_rock collects the engine's warnings in the record).
        local implausible = {}
        for _, k in ipairs(sorted_keys(props)) do
            local v, key = props[k], k:lower()
            if type(v) == "number" and v > 2 and (key == "fric" or key:match("_fric$")) then
                implausible[#implausible + 1] = v < 90
                    and string.format("%s = %g is a friction coefficient (tan of the friction angle), "
                        .. "not an angle: for a friction angle of %g\u{b0} use %s = tan(%g\u{b0}) = %.3g",
                        k, v, v, k, v, math.tan(math.rad(v)))
                    or string.format("%s = %g is a friction coefficient; above 2 it is not plausible", k, v)
            end
        end
        if #implausible > 0 then
            io.stderr:write(string.format("warning: rockfall.analysis: %s: %s\n", where,
                table.concat(implausible, "; ")))
        end
    end
end

--- Splits the profile into runs of segments of one material; inserts a vertex where a zone
--- boundary cuts a segment. Returns points and one material name per segment.
local function zone_profile(pts, zones, materials, default, where)
    local seg = {}
    if zones == nil then
        if not default then
            if #sorted_keys(materials) ~= 1 then
                fail("%s: give zones (or material = name) to say where each material is", where)
            end
            default = sorted_keys(materials)[1]
        end
        for k = 1, #pts - 1 do seg[k] = default end
        return pts, seg
    end
    if type(zones) ~= "table" or #zones == 0 then fail("%s.zones must be a non-empty list", where) end
    if type(zones[1]) == "string" then
        -- One material name per segment.
        if #zones ~= #pts - 1 then
            fail("%s.zones: %d names for %d segments (one per segment)", where, #zones, #pts - 1)
        end
        for k, z in ipairs(zones) do
            if type(z) ~= "string" or not materials[z] then
                fail("%s.zones[%d]: unknown material '%s'%s (materials: %s)", where, k, tostring(z),
                    hint(z, sorted_keys(materials)), table.concat(sorted_keys(materials), ", "))
            end
            seg[k] = z
        end
        return pts, seg
    end
    local x0, x1 = pts[1][1], pts[#pts][1]
    local list = {}
    for k, z in ipairs(zones) do
        local w = string.format("%s.zones[%d]", where, k)
        check_keys(z, { "material", "name", "x_from", "x_to" }, w)
        local mat = z.material or z.name
        if type(mat) ~= "string" or not materials[mat] then
            fail("%s: unknown material '%s'%s (materials: %s)", w, tostring(mat), hint(mat, sorted_keys(materials)),
                table.concat(sorted_keys(materials), ", "))
        end
        num(z.x_from, w .. ".x_from")
        num(z.x_to, w .. ".x_to")
        if z.x_to <= z.x_from then fail("%s: x_to (%g) must exceed x_from (%g)", w, z.x_to, z.x_from) end
        if z.x_from < x0 - 1e-9 or z.x_to > x1 + 1e-9 then
            fail("%s (material '%s', x %g..%g) lies outside the profile (x %g..%g)", w, mat, z.x_from,
                z.x_to, x0, x1)
        end
        list[#list + 1] = { mat = mat, a = z.x_from, b = z.x_to, k = k }
    end
    table.sort(list, function(u, v) return u.a < v.a end)
    for k = 2, #list do
        if list[k].a < list[k - 1].b - 1e-9 then
            fail("%s.zones[%d] and zones[%d] overlap (x %g..%g and %g..%g)", where, list[k - 1].k, list[k].k,
                list[k - 1].a, list[k - 1].b, list[k].a, list[k].b)
        end
    end
    -- Insert vertices at zone boundaries that cut a segment.
    local cuts = {}
    for _, z in ipairs(list) do cuts[#cuts + 1] = z.a; cuts[#cuts + 1] = z.b end
    local out = { pts[1] }
    for k = 1, #pts - 1 do
        local a, b = pts[k], pts[k + 1]
        local inner = {}
        for _, c in ipairs(cuts) do
            if c > a[1] + 1e-9 and c < b[1] - 1e-9 then inner[#inner + 1] = c end
        end
        table.sort(inner)
        local last = nil
        for _, c in ipairs(inner) do
            if c ~= last then
                out[#out + 1] = { c, a[2] + (b[2] - a[2]) * (c - a[1]) / (b[1] - a[1]) }
                last = c
            end
        end
        out[#out + 1] = b
    end
    for k = 1, #out - 1 do
        local a, b = out[k], out[k + 1]
        local xm = 0.5 * (a[1] + b[1])
        for _, z in ipairs(list) do
            if xm >= z.a - 1e-9 and (xm < z.b - 1e-9 or (z.b >= x1 - 1e-9 and xm <= z.b + 1e-9)) then
                seg[k] = z.mat
                break
            end
        end
        if not seg[k] then
            fail("%s: profile segment %d (x %g..%g) is in no zone", where, k, a[1], b[1])
        end
    end
    return out, seg
end

--- Builds and checks an analysis. See docs/rockfall.md for every option and its default.
local function analysis(opts)
    local W = "analysis"
    check_keys(opts, ANALYSIS_KEYS, W)
    local an = {}
    -- Profile.
    local prof = opts.profile
    if type(prof) == "string" then prof = read_csv(prof) end
    an.points = check_points(prof, W .. ".profile")
    -- Materials.
    local materials = opts.materials or { slope = { model = "linear", props = {} } }
    if type(materials) ~= "table" or next(materials) == nil then fail("%s.materials must be a non-empty table", W) end
    for name, mat in pairs(materials) do
        local w = string.format("%s.materials.%s", W, tostring(name))
        if type(name) ~= "string" then fail("%s: material names must be strings", W) end
        if name == "rock" then fail("%s: 'rock' is the rocks' group; choose another name", w) end
        check_keys(mat, MATERIAL_KEYS, w)
        check_model(mat.model or "linear", mat.props, w)
    end
    an.materials = materials
    if opts.material ~= nil and not materials[opts.material] then
        fail("%s.material: unknown material '%s'", W, tostring(opts.material))
    end
    an.nominal, an.segment_material = zone_profile(an.points, opts.zones, materials, opts.material, W)
    -- Roughness.
    if opts.roughness ~= nil then
        local r = opts.roughness
        check_keys(r, { "amplitude", "spacing", "per_rock" }, W .. ".roughness")
        num(r.amplitude, W .. ".roughness.amplitude", 0)
        if r.spacing ~= nil then num(r.spacing, W .. ".roughness.spacing", 1e-6) end
        an.roughness = { amplitude = r.amplitude, spacing = r.spacing, per_rock = r.per_rock ~= false }
    end
    -- Seed and count.
    an.seed = opts.seed or 1
    if math.type(an.seed) ~= "integer" then
        if type(an.seed) == "number" and an.seed == math.floor(an.seed) then an.seed = math.tointeger(an.seed)
        else fail("%s.seed must be an integer (got %s)", W, tostring(opts.seed)) end
    end
    an.n = opts.n and math.tointeger(num(opts.n, W .. ".n", 1)) or 100
    -- Seeders.
    if type(opts.seeders) ~= "table" or #opts.seeders == 0 then
        fail("%s.seeders must be a non-empty list of seeders", W)
    end
    an.seeders, an.seeder_weight = {}, 0
    for k, s in ipairs(opts.seeders) do
        local w = string.format("%s.seeders[%d]", W, k)
        check_keys(s, SEEDER_KEYS, w)
        local sd = { name = s.name or ("seeder" .. k), weight = s.weight or 1 }
        num(sd.weight, w .. ".weight", 0)
        local kind = s.kind or (s.at and "point") or "line"
        if kind == "point" then
            sd.from = point(s.at, w .. ".at")
            sd.to = sd.from
        elseif kind == "line" then
            sd.from, sd.to = point(s.from, w .. ".from"), point(s.to, w .. ".to")
        else
            fail("%s.kind must be \"point\" or \"line\" (got %s)", w, tostring(kind))
        end
        sd.kind = kind
        local rocks = s.rock or { shape = "ball", radius = 0.5 }
        if rocks.shape or rocks.name or rocks.radius or rocks.pebbles or #rocks == 0 then rocks = { rocks } end
        sd.rocks, sd.rock_weight = {}, 0
        for j, rk in ipairs(rocks) do
            sd.rocks[j] = check_rock(rk, string.format("%s.rock[%d]", w, j))
            sd.rock_weight = sd.rock_weight + (rk.weight or 1)
        end
        sd.vx = check_dist(s.vx or 0, w .. ".vx")
        sd.vy = check_dist(s.vy or 0, w .. ".vy")
        sd.spin = check_dist(s.spin or 0, w .. ".spin")
        an.seeders[k] = sd
        an.seeder_weight = an.seeder_weight + sd.weight
    end
    if an.seeder_weight <= 0 then fail("%s.seeders: the weights sum to 0", W) end
    -- Collectors and barriers.
    local x0, x1 = an.points[1][1], an.points[#an.points][1]
    an.collectors = {}
    for k, c in ipairs(opts.collectors or {}) do
        local w = string.format("%s.collectors[%d]", W, k)
        check_keys(c, { "name", "x" }, w)
        num(c.x, w .. ".x", x0, x1)
        an.collectors[k] = { name = c.name or ("collector" .. k), x = c.x }
    end
    an.barriers = {}
    for k, b in ipairs(opts.barriers or {}) do
        local w = string.format("%s.barriers[%d]", W, k)
        check_keys(b, { "name", "x", "energy", "height" }, w)
        num(b.x, w .. ".x", x0, x1)
        num(b.energy, w .. ".energy", 0)
        num(b.height, w .. ".height", 0)
        an.barriers[k] = { name = b.name or ("barrier" .. k), x = b.x, energy = b.energy, height = b.height }
    end
    table.sort(an.barriers, function(a, b) return a.x < b.x end)
    -- Envelope bins.
    local env = opts.envelope or { x0 = x0, x1 = x1, dx = 1 }
    check_keys(env, { "x0", "x1", "dx" }, W .. ".envelope")
    an.envelope = { x0 = num(env.x0 or x0, W .. ".envelope.x0"), x1 = num(env.x1 or x1, W .. ".envelope.x1"),
        dx = num(env.dx or 1, W .. ".envelope.dx", 1e-9) }
    an.envelope.nbins = math.max(1, math.ceil((an.envelope.x1 - an.envelope.x0) / an.envelope.dx - 1e-9))
    -- Engine and end rules.
    an.gravity = opts.gravity and point(opts.gravity, W .. ".gravity") or { 0, -9.81 }
    an.margin = opts.margin and num(opts.margin, W .. ".margin", 1e-9)
    an.rest_speed = num(opts.rest_speed or 0.1, W .. ".rest_speed", 0)
    an.rest_ke = opts.rest_ke and num(opts.rest_ke, W .. ".rest_ke", 0)
    an.rest_time = num(opts.rest_time or 0.5, W .. ".rest_time", 0)
    an.t_max = num(opts.t_max or 120, W .. ".t_max", 1e-9)
    an.impact_min_vn = num(opts.impact_min_vn or 0.5, W .. ".impact_min_vn", 0)
    an.path_every = opts.path_every and math.tointeger(num(opts.path_every, W .. ".path_every", 1)) or 10
    an.clearance = num(opts.clearance or 1e-3, W .. ".clearance", 0)
    if opts.timestep ~= nil and type(opts.timestep) ~= "table" then fail("%s.timestep must be a table", W) end
    an.timestep = opts.timestep
    local rc = opts.rock_contact or {}
    check_keys(rc, MATERIAL_KEYS, W .. ".rock_contact")
    an.rock_contact = { model = rc.model or "linear",
        props = rc.props or { kn = 1e9, ks = 5e8, fric = 0.5, dp_nratio = 0.3 } }
    check_model(an.rock_contact.model, an.rock_contact.props, W .. ".rock_contact")
    -- Shadow angles (rockfall_stats): the apex, or the steepness from which a downslope
    -- segment counts as the cliff whose toe is the apex.
    if opts.shadow_apex ~= nil then an.shadow_apex = point(opts.shadow_apex, W .. ".shadow_apex") end
    if opts.shadow_steep ~= nil then
        an.shadow_steep = num(opts.shadow_steep, W .. ".shadow_steep", 1e-9, 90)
    end
    an.y_min = math.huge
    for _, p in ipairs(an.points) do an.y_min = math.min(an.y_min, p[2]) end
    an.is_analysis = true
    return an
end
rockfall.analysis = api("analysis", analysis)

--- The analysis description the statistics module (rockfall_stats) receives.
function rockfall.describe(an)
    local cols, bars = {}, {}
    for k, c in ipairs(an.collectors) do cols[k] = { name = c.name, x = c.x } end
    for k, b in ipairs(an.barriers) do
        bars[k] = { name = b.name, x = b.x, energy = b.energy, height = b.height }
    end
    local sx, sy, sw = 0, 0, 0
    for _, s in ipairs(an.seeders) do
        sx = sx + s.weight * 0.5 * (s.from[1] + s.to[1])
        sy = sy + s.weight * 0.5 * (s.from[2] + s.to[2])
        sw = sw + s.weight
    end
    local prof = {}
    for k, p in ipairs(an.points) do prof[k] = { p[1], p[2] } end
    return {
        profile = prof, envelope = { x0 = an.envelope.x0, x1 = an.envelope.x1, dx = an.envelope.dx },
        collectors = cols, barriers = bars, release = { x = sx / sw, y = sy / sw }, seed = an.seed, n = an.n,
        shadow_apex = an.shadow_apex and { an.shadow_apex[1], an.shadow_apex[2] } or nil,
        shadow_steep = an.shadow_steep,
    }
end

local function need_analysis(an)
    if type(an) ~= "table" or not an.is_analysis then
        fail("the first argument must be an analysis from rockfall.analysis{} (got %s)", tostring(an))
    end
end

-- --------------------------------------------------------------------------------- one rock's draw

local function weighted(list, total, weight_of, r)
    local u = r:uniform() * total
    for k, item in ipairs(list) do
        u = u - weight_of(item)
        if u < 0 then return item, k end
    end
    return list[#list], #list
end

--- The profile rock i meets: the nominal one, or roughened with the rock's (or the analysis')
--- roughness stream.
local function rock_profile(an, seed)
    if not an.roughness or an.roughness.amplitude == 0 then return an.nominal, an.segment_material end
    local pts, mats = an.nominal, an.segment_material
    if an.roughness.spacing then
        local out, om = { { pts[1][1], pts[1][2] } }, {}
        for k = 1, #pts - 1 do
            local piece = refine({ pts[k], pts[k + 1] }, an.roughness.spacing)
            for j = 2, #piece do
                out[#out + 1] = piece[j]
                om[#om + 1] = mats[k]
            end
        end
        pts, mats = out, om
    end
    local s = an.roughness.per_rock and seed or rockfall.rock_seed(an.seed, 0)
    return roughen(pts, an.roughness.amplitude, rockfall.stream(s, "roughness"):next()), mats
end

--- Everything random about rock i: its seed, seeder, shape, size, release state and profile.
local function sample(an, i)
    local seed = rockfall.rock_seed(an.seed, i)
    local rs = {}
    for name in pairs(STREAMS) do rs[name] = rockfall.stream(seed, name) end
    local sd = weighted(an.seeders, an.seeder_weight, function(s) return s.weight end, rs.seeder)
    local spec = weighted(sd.rocks, sd.rock_weight, function(s) return s.weight or 1 end, rs.shape)
    local rock = make_rock(spec, rs)
    local u = rs.position:uniform()
    local x = sd.from[1] + u * (sd.to[1] - sd.from[1])
    local y = sd.from[2] + u * (sd.to[2] - sd.from[2])
    local pts, mats = rock_profile(an, seed)
    -- A rock seeded into or below the slope is lifted until it clears it (RocFall moves it to
    -- the surface): distance to the polyline >= bounding radius + clearance.
    local lifted = false
    for _ = 1, 100 do
        local d = polyline_distance(pts, x, y)
        local below = y < ground_at(pts, x)
        if not below and d >= rock.bound + an.clearance * 0.999 then break end
        lifted = true
        if below then y = ground_at(pts, x) + rock.bound + an.clearance
        else y = y + (rock.bound + an.clearance - d) + 1e-6 end
    end
    return {
        seed = seed, seeder = sd.name, rock = rock, points = pts, materials = mats, lifted = lifted,
        release = { x = x, y = y, vx = rockfall.draw(sd.vx, rs.vx), vy = rockfall.draw(sd.vy, rs.vy),
            spin = rockfall.draw(sd.spin, rs.spin) },
    }
end
rockfall.sample = api("sample", function(an, i) need_analysis(an) return sample(an, i) end)

-- --------------------------------------------------------------------------------- the model

--- Walls: one per run of consecutive segments of one material, grouped by the material name.
local function build_slope(m, an, pts, mats)
    for name, mat in pairs(an.materials) do
        m:contact_model(mat.model or "linear", mat.props or {}, { groups = { "rock", name } })
    end
    local wall_material = {}
    local k = 1
    while k <= #mats do
        local j = k
        while j < #mats and mats[j + 1] == mats[k] do j = j + 1 end
        local wp = {}
        for v = k, j + 1 do wp[#wp + 1] = pts[v] end
        local w = m:wall{ points = wp, group = mats[k] }
        wall_material[w.id] = mats[k]
        k = j + 1
    end
    return wall_material
end

--- Creates the rock body (a ball, or a clump of its pebbles) in model m.
local function place_rock(m, s)
    local rk, rel = s.rock, s.release
    if rk.ball then
        return m:ball{ pos = { rel.x, rel.y }, radius = rk.pebbles[1][3] * rk.scale, density = rk.density,
            vel = { rel.vx, rel.vy }, spin = rel.spin, group = "rock" }
    end
    return m:clump{ pebbles = rk.pebbles, pos = { rel.x, rel.y }, angle = rk.angle, scale = rk.scale,
        density = rk.density, vel = { rel.vx, rel.vy }, spin = rel.spin, group = "rock" }
end

-- --------------------------------------------------------------------------------- tracking

-- The engine tracks a rock (m:track, docs/lua-api.md "Trackers") at every step, in C++: its
-- touches of the slope (impacts), its crossings of the collector and barrier lines, its
-- envelope, its path and its end rules (left, rest, time). Lua acts only at events -- a barrier
-- crossing, the rock's end -- and fills the record from the tracker's lists at the end; it never
-- looks at the rock and its contacts each step. run_rock tracks its one rock, mass_release
-- every rock of its model, both with these functions.

--- The collector and barrier lines in +x order.
local function rock_lines(an)
    local lines = {}
    for _, c in ipairs(an.collectors) do lines[#lines + 1] = { kind = "collector", name = c.name, x = c.x } end
    for _, b in ipairs(an.barriers) do
        lines[#lines + 1] = { kind = "barrier", name = b.name, x = b.x, energy = b.energy, height = b.height }
    end
    table.sort(lines, function(a, b) return a.x < b.x end)
    return lines
end

--- Starts the engine's tracker of rock i (body `body`, draw `s`) and returns its Lua side:
--- the record it fills and what the events need. `ended(rt)`, if given, is called once when it
--- ends.
local function track_rock(m, an, i, s, body, lines, opts, ended)
    local rk, pts = s.rock, s.points
    local rt = {
        body = body, mass = body.mass, inertia = body.inertia, r_eq = rk.r_eq, pts = pts,
        crossed = {}, done = false,
        record = {
            rock = i, seed = s.seed, seeder = s.seeder, shape = rk.shape, mass = body.mass,
            volume = rk.volume, r_eq = rk.r_eq, density = rk.density, scale = rk.scale,
            angle = rk.angle, lifted = s.lifted or nil,
            release = { x = s.release.x, y = s.release.y, vx = s.release.vx, vy = s.release.vy,
                spin = s.release.spin },
            crossings = {}, barrier = {}, impacts = {}, env_height = {}, env_ke = {},
            path = opts.trajectory and {} or nil,
        },
    }
    local ke_rest = an.rest_ke
    if not ke_rest then
        -- Speed v for the centroid and v / r_eq at the rim: 1/2 m v^2 + 1/2 I (v / r_eq)^2.
        local v = an.rest_speed
        ke_rest = 0.5 * body.mass * v * v + 0.5 * body.inertia * (v / rk.r_eq) ^ 2
    end
    -- Vertical lines reaching far beyond the profile (a rock below it has left; one 10 km
    -- above it does not exist), crossed toward +x: from below to above.
    local y_lo, y_hi = math.huge, -math.huge
    for _, p in ipairs(pts) do y_lo, y_hi = math.min(y_lo, p[2]), math.max(y_hi, p[2]) end
    local tl = {}
    for k, line in ipairs(lines) do
        tl[k] = { from = { line.x, y_lo - 1e4 }, to = { line.x, y_hi + 1e4 }, event = line.kind == "barrier" }
    end
    local env = an.envelope
    local function finish(stop, time, x, y)
        if rt.done then return end
        rt.done = true
        local r = rt.record
        r.stop, r.t_end, r.end_x, r.end_y = stop, time, x, y
        if ended then ended(rt) end
    end
    rt.finish = finish
    local function on_event(tr, ev)
        if rt.done then return end
        if ev.kind == "end" then
            local st = tr:status()
            local stop = ({ exit = "left", rest = "rest", time = "time" })[ev.state] or ev.state
            finish(stop, st.t, st.pos[1], st.pos[2])
            return
        end
        -- A barrier line, crossed for the first time: the capacity rule (docs/rockfall.md).
        if rt.crossed[ev.line] then return end
        rt.crossed[ev.line] = true
        local line, c, r = lines[ev.line], ev.crossing, rt.record
        local ux, uy, yc, tc = c.vel[1], c.vel[2], c.pos[2], c.t
        local kt, kr = c.ke_trans, c.ke_rot
        local ke = kt + kr
        local hit = {
            name = line.name, t = tc, x = line.x, y = yc, height = yc - ground_at(pts, line.x) - rk.r_eq,
            energy = ke, angle = math.deg(math.atan(-uy, ux)), ke_trans = kt, ke_rot = kr,
        }
        r.barrier[#r.barrier + 1] = hit
        if hit.height >= line.height then
            hit.stopped, hit.over = false, true -- flies over: recorded as passed, energy unchanged
        elseif ke > line.energy then
            -- Passes with its energy reduced by the capacity: the body's half-step velocity and
            -- spin scaled by f = sqrt((ke - E_cap) / ke), which takes E_cap from translation and
            -- rotation in proportion (a loss the energy tracing cannot book: barrier_absorbed).
            -- The scaled velocity moves the rock from the next step on; a line crossed later in
            -- this step sees the rock as this step moved it.
            local f = math.sqrt((ke - line.energy) / ke)
            hit.stopped, hit.energy_after = false, ke - line.energy
            local v = body.vel
            body.vel = { v[1] * f, v[2] * f }
            body.spin = body.spin * f
            r.barrier_absorbed = (r.barrier_absorbed or 0) + line.energy
            m:guard{ balance = "off" } -- the barrier's energy is not an engine item
        else
            hit.stopped = true
            tr:stop()
            finish("barrier", tc, line.x, yc)
        end
    end
    rt.tracker = m:track(body, {
        impacts = { with = "walls", min_speed = an.impact_min_vn },
        lines = tl,
        rest = { energy = ke_rest, time = an.rest_time },
        region = { lo = { pts[1][1], an.y_min - 2 * rk.r_eq - 1 }, hi = { pts[#pts][1], math.huge } },
        end_time = an.t_max,
        envelope = { ground = pts, x0 = env.x0, dx = env.dx, bins = env.nbins },
        path = opts.trajectory and an.path_every or nil,
        on_event = on_event,
    })
    return rt
end

--- A rock whose tracker ended at its first sample (when it was made: no event then) ends here.
local function ended_at_start(rt)
    local st = rt.tracker:status()
    if st.state ~= "tracking" then
        local stop = ({ exit = "left", rest = "rest", time = "time" })[st.state] or st.state
        rt.finish(stop, st.t, st.pos[1], st.pos[2])
    end
end

--- Fills rock rt's record from its tracker's records (after the run).
local function collect_rock(rt, lines, wall_material)
    local tr, r = rt.tracker, rt.record
    local first = {}
    for _, c in ipairs(tr:crossings()) do
        local line = lines[c.line]
        if line.kind == "collector" and not first[c.line] then
            first[c.line] = true
            local ux, uy = c.vel[1], c.vel[2]
            r.crossings[#r.crossings + 1] = {
                line = line.name, t = c.t, x = line.x, y = c.pos[2],
                height = c.pos[2] - ground_at(rt.pts, line.x) - rt.r_eq, vx = ux, vy = uy,
                v = math.sqrt(ux * ux + uy * uy), spin = c.spin, ke_trans = c.ke_trans,
                ke_rot = c.ke_rot, ke = c.ke_trans + c.ke_rot,
            }
        end
    end
    local function ke(v, w)
        return 0.5 * rt.mass * (v[1] * v[1] + v[2] * v[2]) + 0.5 * rt.inertia * w * w
    end
    for _, im in ipairs(tr:impacts()) do
        local nx, ny = im.normal[1], im.normal[2]
        local vx, vy = im.vel[1], im.vel[2]
        local rec = { t = im.t, x = im.pos[1], y = im.pos[2], vn_in = vx * nx + vy * ny,
            vt_in = vx * ny - vy * nx, material = wall_material[im.wall.id] }
        if im.t_end then
            -- Closed at the first sample without a touch, or at the rock's last sample (then
            -- it lasted until the rock ended: at a barrier, the crossing's time).
            local ox, oy = im.vel_end[1], im.vel_end[2]
            local vn, vt = ox * nx + oy * ny, ox * ny - oy * nx
            rec.vn_out, rec.vt_out = vn, vt
            rec.rn = rec.vn_in ~= 0 and math.abs(vn / rec.vn_in) or 0
            rec.rt = rec.vt_in ~= 0 and vt / rec.vt_in or 0
            rec.energy_lost = ke(im.vel, im.spin) - ke(im.vel_end, im.spin_end)
            rec.duration = (im.ended and im.t_end or r.t_end) - im.t
            if not im.ended then rec.ended = false end
        end
        r.impacts[#r.impacts + 1] = rec
    end
    local env = tr:envelope()
    for k, h in pairs(env.height) do r.env_height[k] = h - rt.r_eq end
    for k, e in pairs(env.energy) do r.env_ke[k] = e end
    if r.path then
        for _, p in ipairs(tr:path()) do r.path[#r.path + 1] = p end
        r.path[#r.path + 1] = { r.t_end, r.end_x, r.end_y }
    end
end

-- --------------------------------------------------------------------------------- running

--- A rock's model; the engine's warnings (from the first call on) go into `warnings`, which
--- the record carries, instead of one line on stderr per rock.
local function new_model(an, margin, warnings)
    local m = talus.model{ gravity = an.gravity, mass = "disk" }
    m:on_warning(function(text) warnings[#warnings + 1] = text end)
    m:contact_model(an.rock_contact.model, an.rock_contact.props)
    if an.timestep then m:timestep(an.timestep) end
    m:broadphase{ margin = margin }
    return m
end

--- A hook option (on_model, on_end) is a function or absent.
local function check_hook(opts, name, where)
    if opts[name] ~= nil and type(opts[name]) ~= "function" then
        fail("%s.%s must be a function (got %s)", where, name, type(opts[name]))
    end
end

--- Runs rock i of the analysis alone on its own slope; returns its record.
--- opts: trajectory = true records the path every analysis.path_every samples; on_model(m,
--- info) is called once the model is built, before the first step (attach m:vtk, m:picture,
--- m:history there), info = {rock =, seed =, body =}; on_end(m, record) once the rock ended.
local function run_rock(an, i, opts)
    need_analysis(an)
    opts = opts or {}
    check_keys(opts, { "trajectory", "chunk", "on_model", "on_end" }, "run_rock options")
    check_hook(opts, "on_model", "run_rock options")
    check_hook(opts, "on_end", "run_rock options")
    if math.type(i) ~= "integer" or i < 1 then fail("rock index must be an integer >= 1 (got %s)", tostring(i)) end
    local s = sample(an, i)
    -- A margin of the rock's size: free-flight steps grow until the rock would leave its fat box
    -- (the kinematic rule), so a wide box means few steps in flight; a rock has only the slope's
    -- few segments as candidates, so the wider box costs nothing measurable.
    local warnings = {}
    local m = new_model(an, an.margin or math.max(s.rock.r_eq, 1e-3), warnings)
    local wall_material = build_slope(m, an, s.points, s.materials)
    local body = place_rock(m, s)
    m:energy{ on = true }
    if opts.on_model then opts.on_model(m, { rock = i, seed = s.seed, body = body }) end
    -- The tracker comes after on_model, so that the hook may save the model (a model with
    -- trackers is not saved); its first sample is the state the first step starts from.
    local lines = rock_lines(an)
    local rt = track_rock(m, an, i, s, body, lines, opts)
    ended_at_start(rt)
    local chunk = opts.chunk or 50
    while not rt.done do m:cycle(chunk) end
    collect_rock(rt, lines, wall_material)
    m:clear_trackers() -- its records are read; on_end may save the model
    local rec = rt.record
    local e = m:energies()
    rec.energy = { input = e.input, kinetic = e.kinetic, body = e.body, slip = e.slip,
        dashpot = e.dashpot, strain = e.strain, balance_error = e.balance_error }
    rec.steps = m:step()
    if #warnings > 0 then rec.warnings = warnings end
    if opts.on_end then opts.on_end(m, rec) end
    return rec
end
rockfall.run_rock = api("run_rock", run_rock)

-- --------------------------------------------------------------------------------- mass release

--- Releases n rocks at once into one model (rock-rock contact with analysis.rock_contact);
--- returns one record per rock, as run_rock does. All rocks meet the nominal (or the analysis'
--- single roughened) profile: roughness per rock has no meaning in one model.
local function mass_release(an, opts)
    need_analysis(an)
    opts = opts or {}
    check_keys(opts, { "n", "trajectory", "chunk", "on_model", "on_end" }, "mass_release options")
    check_hook(opts, "on_model", "mass_release options")
    check_hook(opts, "on_end", "mass_release options")
    local n = opts.n or an.n
    if math.type(n) ~= "integer" or n < 1 then fail("mass_release: n must be an integer >= 1 (got %s)", tostring(n)) end
    local samples, rsum = {}, 0
    local pts, mats = an.nominal, an.segment_material
    if an.roughness and an.roughness.amplitude > 0 then
        pts, mats = rock_profile({ nominal = an.nominal, segment_material = an.segment_material,
            roughness = { amplitude = an.roughness.amplitude, spacing = an.roughness.spacing,
                per_rock = false }, seed = an.seed }, 0)
    end
    for i = 1, n do
        local si = sample(an, i)
        si.points, si.materials = pts, mats
        rsum = rsum + si.rock.r_eq
        -- Rocks drawn onto each other would start with huge overlaps: a rock whose bounding
        -- circle meets an earlier one's is lifted above it (deterministic: rocks in index order).
        local moved = true
        while moved do
            moved = false
            for j = 1, i - 1 do
                local sj = samples[j]
                local dx, dy = si.release.x - sj.release.x, si.release.y - sj.release.y
                local need = si.rock.bound + sj.rock.bound + an.clearance
                if dx * dx + dy * dy < need * need then
                    si.release.y = sj.release.y + math.sqrt(need * need - dx * dx) + 1e-6
                    si.lifted, moved = true, true
                end
            end
        end
        samples[i] = si
    end
    -- A tenth of the mean rock size. Here some rock always touches something, so contacts set
    -- the step and a wide margin (run_rock's, which lengthens a lone rock's steps in flight)
    -- buys nothing: it only makes candidate pairs of rocks near each other, and at 100 rocks
    -- those cost five times the contacts (docs/rockfall.md, "Mass release").
    local warnings = {}
    local m = new_model(an, an.margin or 0.1 * rsum / n, warnings)
    local wall_material = build_slope(m, an, pts, mats)
    local lines = rock_lines(an)
    local left = n
    local function ended(rt)
        left = left - 1
        -- A rock that left, or that a barrier stopped, leaves the model (after the first
        -- sample: once every rock is placed).
        if rt.placed and rt.record.stop ~= "rest" then rt.body:delete() end
    end
    local rocks = {}
    for i = 1, n do
        local body = place_rock(m, samples[i])
        rocks[i] = track_rock(m, an, i, samples[i], body, lines, opts, ended)
    end
    m:energy{ on = true }
    for _, rt in ipairs(rocks) do
        rt.placed = true
        ended_at_start(rt)
    end
    if opts.on_model then
        local bodies = {}
        for i, rt in ipairs(rocks) do bodies[i] = rt.body end
        opts.on_model(m, { rocks = n, bodies = bodies, mass_release = true })
    end
    local chunk = opts.chunk or 50
    while left > 0 do m:cycle(chunk) end
    local recs = {}
    for i, rt in ipairs(rocks) do
        collect_rock(rt, lines, wall_material)
        rt.record.mass_release = true
        recs[i] = rt.record
    end
    if #warnings > 0 then recs.warnings = warnings end
    if opts.on_end then opts.on_end(m, recs) end
    return recs
end
rockfall.mass_release = api("mass_release", mass_release)

-- --------------------------------------------------------------------------------- output

local function fmt(v)
    if v == nil then return "" end
    if type(v) == "boolean" then return v and "1" or "0" end
    if math.type(v) == "integer" then return string.format("%d", v) end
    if type(v) == "number" then return string.format("%.10g", v) end
    local s = tostring(v)
    if s:find("[,\"\n]") then s = '"' .. s:gsub('"', '""') .. '"' end
    return s
end

local function write_rows(file, header, rows)
    local f, err = io.open(file, "w")
    if not f then fail("cannot write '%s' (%s)", file, tostring(err)) end
    f:write(table.concat(header, ","), "\n")
    for _, row in ipairs(rows) do
        local cells = {}
        for k = 1, #header do cells[k] = fmt(row[k]) end
        f:write(table.concat(cells, ","), "\n")
    end
    assert(f:close())
end

--- Writes the per-rock CSVs into outdir: rock_endpoints.csv, rock_crossings.csv,
--- rock_barriers.csv, rock_profile.csv, and when asked rock_impacts.csv and rock_paths.csv
--- (the prefix keeps them apart from the statistics files of rockfall_stats). Returns the
--- file names.
local function write_csv(records, an, outdir, opts)
    need_analysis(an)
    opts = opts or {}
    talus.mkdir(outdir)
    local files = {}
    local ends, cross, bars, imps, paths = {}, {}, {}, {}, {}
    for _, r in ipairs(records) do
        local top = -math.huge
        for _, h in pairs(r.env_height) do top = math.max(top, h) end
        ends[#ends + 1] = { r.rock, r.seed, r.shape, r.mass, r.volume, r.r_eq, r.release.x, r.release.y,
            r.release.vx, r.release.vy, r.release.spin, r.stop, r.end_x, r.end_y, r.t_end, #r.impacts,
            top > -math.huge and top or nil, r.steps }
        for _, c in ipairs(r.crossings) do
            cross[#cross + 1] = { r.rock, c.line, c.t, c.x, c.y, c.height, c.vx, c.vy, c.v, c.spin,
                c.ke_trans, c.ke_rot, c.ke }
        end
        for _, b in ipairs(r.barrier) do
            bars[#bars + 1] = { r.rock, b.name, b.stopped, b.t, b.x, b.y, b.height, b.energy, b.angle,
                b.energy_after }
        end
        for _, im in ipairs(r.impacts) do
            imps[#imps + 1] = { r.rock, im.t, im.x, im.y, im.vn_in, im.vt_in, im.vn_out, im.vt_out, im.rn,
                im.rt, im.energy_lost, im.material, im.duration }
        end
        if r.path then
            for _, p in ipairs(r.path) do paths[#paths + 1] = { r.rock, p[1], p[2], p[3] } end
        end
    end
    local function out(name, header, rows)
        local file = outdir .. "/" .. name
        write_rows(file, header, rows)
        files[#files + 1] = file
    end
    out("rock_endpoints.csv", { "rock", "seed", "shape", "mass", "volume", "r_eq", "release_x", "release_y",
        "release_vx", "release_vy", "release_spin", "stop", "end_x", "end_y", "t_end", "impacts",
        "max_height", "steps" }, ends)
    out("rock_crossings.csv", { "rock", "line", "t", "x", "y", "height", "vx", "vy", "v", "spin", "ke_trans",
        "ke_rot", "ke" }, cross)
    out("rock_barriers.csv", { "rock", "barrier", "stopped", "t", "x", "y", "height", "energy", "angle",
        "energy_after" }, bars)
    local prof = {}
    for k, p in ipairs(an.nominal) do prof[k] = { p[1], p[2], an.segment_material[k] or "" } end
    out("rock_profile.csv", { "x", "y", "material" }, prof)
    if opts.impacts then
        out("rock_impacts.csv", { "rock", "t", "x", "y", "vn_in", "vt_in", "vn_out", "vt_out", "rn", "rt",
            "energy_lost", "material", "duration" }, imps)
    end
    if opts.trajectories then out("rock_paths.csv", { "rock", "t", "x", "y" }, paths) end
    return files
end
rockfall.write_csv = api("write_csv", write_csv)

local function serial_map(n, fn)
    local r = {}
    for i = 1, n do r[i] = fn(i) end
    return r
end

--- A fixed text of a plain value (keys sorted, numbers exact): the analysis' fingerprint.
local function canonical(v, out)
    local t = type(v)
    if t == "table" then
        local keys = {}
        for k in pairs(v) do keys[#keys + 1] = k end
        table.sort(keys, function(a, b)
            if type(a) ~= type(b) then return type(a) < type(b) end
            return a < b
        end)
        out[#out + 1] = "{"
        for _, k in ipairs(keys) do
            canonical(k, out)
            out[#out + 1] = "="
            canonical(v[k], out)
            out[#out + 1] = ";"
        end
        out[#out + 1] = "}"
    elseif t == "number" then
        out[#out + 1] = math.type(v) == "integer" and string.format("%d", v) or string.format("%a", v)
    else
        out[#out + 1] = t:sub(1, 1) .. tostring(v)
    end
    return out
end

--- 64-bit FNV-1a hash of a string, as 16 hex digits (Lua integers wrap modulo 2^64).
local function fnv1a(text)
    local h = -3750763034362895579 -- 0xcbf29ce484222325
    for k = 1, #text do h = (h ~ text:byte(k)) * 0x100000001b3 end
    return string.format("%016x", h)
end

--- Runs the analysis' rocks independently (talus.map when present: all cores, MPI ranks),
--- writes the CSVs on rank 0, then the statistics of rockfall_stats when that module exists.
--- opts: n, outdir, jobs, impacts (bool), trajectories (bool, or a number of rocks to keep
--- paths of: the first k), quiet, stats, on_model / on_end (run_rock's hooks, called in the
--- process that runs the rock), resume (default true with an outdir: rocks a previous run of
--- the same analysis wrote are taken from outdir/checkpoint, not run again).
--- A rock that fails (an error in its run or in a hook) is recorded in info.failed ({rock =,
--- seed =, message =}) and in outdir/rock_failed.csv; the others go on. Returns the records of
--- the rocks that ran, in rock order, and info.
local function monte_carlo(an, opts)
    need_analysis(an)
    opts = opts or {}
    check_keys(opts, { "n", "outdir", "jobs", "impacts", "trajectories", "quiet", "stats", "on_model",
        "on_end", "resume" }, "monte_carlo options")
    check_hook(opts, "on_model", "monte_carlo options")
    check_hook(opts, "on_end", "monte_carlo options")
    local n = opts.n or an.n
    if math.type(n) ~= "integer" or n < 1 then fail("monte_carlo: n must be an integer >= 1 (got %s)", tostring(n)) end
    local traj = opts.trajectories
    local keep = traj == true and n or (type(traj) == "number" and traj or 0)
    local clock = os.clock()
    local run = function(i)
        return run_rock(an, i, { trajectory = i <= keep, on_model = opts.on_model, on_end = opts.on_end })
    end
    local results
    if talus.map then
        local mopts = { jobs = opts.jobs }
        if opts.outdir and opts.resume ~= false then
            -- Each finished rock is kept on disk at once; the key ties it to this analysis, so a
            -- changed analysis in the same outdir runs every rock again.
            mopts.checkpoint = opts.outdir .. "/checkpoint"
            mopts.key = "rockfall " .. rockfall.version .. " talus " .. tostring(talus.version) .. " "
                .. fnv1a(table.concat(canonical(an, {})))
                .. " paths " .. keep
        end
        results = talus.map(n, run, mopts)
    else
        results = serial_map(n, run)
    end
    local cpu = os.clock() - clock
    -- The rocks that ran, in order; the failed ones with their seeds.
    local records, failed = {}, nil
    for i = 1, n do
        if results[i] ~= nil then records[#records + 1] = results[i] end
    end
    if results.failed then
        failed = {}
        for k, f in ipairs(results.failed) do
            failed[k] = { rock = f.index, seed = rockfall.rock_seed(an.seed, f.index), message = f.message }
        end
    end
    local rank = talus.rank and talus.rank() or 0
    local info = { cpu = cpu, files = {}, parallel = talus.map ~= nil, failed = failed }
    if failed and not opts.quiet and rank == 0 then
        print(string.format("rockfall: %d of %d rocks failed; the first, rock %d (seed %d): %s%s", #failed, n,
            failed[1].rock, failed[1].seed, failed[1].message,
            opts.outdir and "; all in " .. opts.outdir .. "/rock_failed.csv; a rerun into the same outdir runs "
                .. "only the rocks not written" or ""))
    end
    if opts.outdir and rank == 0 then
        info.files = write_csv(records, an, opts.outdir, { impacts = opts.impacts, trajectories = keep > 0 })
        local rows = {}
        for k, f in ipairs(failed or {}) do rows[k] = { f.rock, f.seed, f.message } end
        local file = opts.outdir .. "/rock_failed.csv"
        if #rows > 0 then
            write_rows(file, { "rock", "seed", "message" }, rows)
            info.files[#info.files + 1] = file
        else
            os.remove(file) -- from an earlier run whose failed rocks ran now
        end
        if opts.stats ~= false then
            local ok, stats = pcall(require, "rockfall_stats")
            if ok and type(stats) == "table" and stats.write then
                local summary = stats.write(records, rockfall.describe(an), opts.outdir)
                info.stats = true
                info.apex, info.shadow_note = summary.apex, summary.shadow_note
                if not opts.quiet then
                    -- The apex decides every shadow angle: say which one was used.
                    local a = summary.apex
                    print(a and string.format("rockfall: shadow angles from the apex (%.4g, %.4g): %s",
                        a.x, a.y, a.rule)
                        or "rockfall: no shadow angles (no steep downslope segment and no shadow_apex)")
                    if summary.shadow_note then print("rockfall: note: " .. summary.shadow_note) end
                end
            elseif not opts.quiet then
                print("rockfall: statistics module rockfall_stats not found; wrote per-rock CSVs only")
            end
        end
    end
    return records, info
end
rockfall.monte_carlo = api("monte_carlo", monte_carlo)

-- --------------------------------------------------------------------------------- helpers

--- Damping ratio of a linear dashpot that gives normal restitution e for a contact that lasts
--- until the overlap is back to zero: e = exp(-pi beta / sqrt(1 - beta^2)), inverted.
function rockfall.dp_nratio(e)
    if type(e) ~= "number" or e <= 0 or e > 1 then error("rockfall.dp_nratio: e must be in (0, 1] (got " .. tostring(e) .. ")", 2) end
    local l = math.log(e)
    return -l / math.sqrt(math.pi * math.pi + l * l)
end

--- A short text summary of records (counts per stop rule, run-out percentiles, barrier counts).
function rockfall.summary(records, an)
    local counts, xs, nb_stop, nb_pass = {}, {}, 0, 0
    for _, r in ipairs(records) do
        counts[r.stop] = (counts[r.stop] or 0) + 1
        xs[#xs + 1] = r.end_x
        for _, b in ipairs(r.barrier) do
            if b.stopped then nb_stop = nb_stop + 1 else nb_pass = nb_pass + 1 end
        end
    end
    table.sort(xs)
    local function q(p) return xs[math.max(1, math.min(#xs, math.ceil(p * #xs)))] end
    local parts = {}
    for _, k in ipairs(sorted_keys(counts)) do parts[#parts + 1] = k .. " " .. counts[k] end
    return string.format("%d rocks: %s; end x median %.1f m, 90%% %.1f m, 95%% %.1f m, max %.1f m; "
        .. "barrier hits: %d stopped, %d passed", #records, table.concat(parts, ", "), q(0.5), q(0.9),
        q(0.95), xs[#xs], nb_stop, nb_pass)
end

rockfall.shapes = SHAPES
return rockfall
