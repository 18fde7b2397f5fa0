-- SPDX-License-Identifier: MIT
--
-- calibrate.lua: fit contact-model parameters to a target restitution against impact velocity
-- (An 2006, chapter 6 and appendix C; docs/rockfall-calibration.md).
--
--   local C = require("calibrate")
--   local rn = C.rocfall()                               -- Rn(v) = 0.53 / (1 + (v/9.144)^2)
--   local rig = C.impact_rig{ model = "power", props = { kn = 6.4e10, transition = 3500 },
--                             radius = 0.04 }
--   local rows = C.fit_param{ rig = rig, param = "exponent", lo = 1, hi = 400,
--                             target = rn, velocities = {1, 2, 3} }
--   C.print_table(rows, { "v", "target", "value", "e" })
--
-- Pieces:
--   C.root(f, a, b, opts)        bracketing root finder (Illinois regula falsi), own code
--   C.target(t)                  a function e(v) from a function or a table {{v, e}, ...}
--   C.rocfall(rn, vref)          RocFall's velocity-scaled restitution (Pfeiffer & Bowen 1989)
--   C.impact_rig{...}            e(params, v) from one impact on talus.impact{}
--   C.clump_drop_rig{...}        e(params, v) of a clump dropped onto a horizontal wall
--   C.fit_param{...}             one parameter per impact velocity (root of e - target)
--   C.fit_lsq{...}               several parameters over a table (least squares, Nelder-Mead)
--   C.fit_linear_dp_nratio{...}  linear's damping ratio for a restitution (rig and closed form)
--   C.follow{...}                what a fixed parameter set gives over a table (auto exp modes)
--   C.runout_rig{...}, C.fit_runout{...}  a property (rrlinear's rr_fric, ...) from a run-out
--   C.nelder_mead(f, x0, step, opts)  the simplex minimiser fit_lsq uses
--   C.design(p)                  a two-level fractional factorial design with a centre point
--   C.fit_targets{...}           several parameters to several targets at once: a design, then
--                                power-law response surfaces in a trust region (expensive,
--                                noisy evaluations such as laboratory tests on a DEM specimen)
--   C.print_table(rows, cols), C.write_csv(file, rows, cols [, number_format])

local C = {}

-- ------------------------------------------------------------------ root finder

--- Illinois regula falsi on a bracket [a, b] with f(a) f(b) <= 0. Regula falsi keeps the
--- bracket (so it cannot diverge, unlike the secant method); the Illinois change halves the
--- function value kept at the end that was retained twice in a row, which removes plain regula
--- falsi's one-sided, linear convergence (order about 1.44 on smooth roots). A bisection step
--- whenever two steps did not halve the bracket bounds the cost by about twice bisection's.
--- opts: xtol (absolute, default 1e-12 (|a| + |b|) + 1e-300), ftol (|f| <= ftol stops; default
--- 0), max_iter (default 200). Returns x, { iterations =, fx =, a =, b = } (the final bracket).
function C.root(f, a, b, opts)
    opts = opts or {}
    assert(type(f) == "function", "calibrate.root: f must be a function")
    assert(type(a) == "number" and type(b) == "number" and a == a and b == b,
        "calibrate.root: the bracket must be two numbers")
    local xtol = opts.xtol or (1e-12 * (math.abs(a) + math.abs(b)) + 1e-300)
    local ftol = opts.ftol or 0
    local max_iter = opts.max_iter or 200
    local fa, fb = f(a), f(b)
    if fa == 0 then return a, { iterations = 0, fx = 0, a = a, b = a } end
    if fb == 0 then return b, { iterations = 0, fx = 0, a = b, b = b } end
    if fa ~= fa or fb ~= fb then
        error(string.format("calibrate.root: f is NaN at the bracket ends (f(%g) = %g, f(%g) = %g)",
            a, fa, b, fb), 2)
    end
    if (fa > 0) == (fb > 0) then
        error(string.format("calibrate.root: [%g, %g] does not bracket a root: f(%g) = %g and "
            .. "f(%g) = %g have the same sign", a, b, a, fa, b, fb), 2)
    end
    local side = 0 -- which end was kept last time: -1 = a, +1 = b
    local x, fx = a, fa
    -- Safeguard (as in Brent's method): at a multiple root (f ~ (x - r)^3) the Illinois steps
    -- can shrink the bracket slowly; if two steps together did not halve it, bisect once.
    local widths = { math.abs(b - a), math.abs(b - a) }
    for it = 1, max_iter do
        local w = math.abs(b - a)
        if w > 0.5 * widths[1] then
            x = 0.5 * (a + b)
        else
            x = (a * fb - b * fa) / (fb - fa)
        end
        widths[1], widths[2] = widths[2], w
        -- guard against round-off putting the estimate on or outside an end
        if not (x > math.min(a, b) and x < math.max(a, b)) then x = 0.5 * (a + b) end
        fx = f(x)
        if fx ~= fx then error(string.format("calibrate.root: f(%g) is NaN", x), 2) end
        if fx == 0 or math.abs(fx) <= ftol then
            return x, { iterations = it, fx = fx, a = x, b = x }
        end
        if (fx > 0) == (fb > 0) then
            b, fb = x, fx
            if side == -1 then fa = 0.5 * fa end
            side = -1
        else
            a, fa = x, fx
            if side == 1 then fb = 0.5 * fb end
            side = 1
        end
        if math.abs(b - a) <= xtol then
            return x, { iterations = it, fx = fx, a = a, b = b }
        end
    end
    return x, { iterations = max_iter, fx = fx, a = a, b = b, unconverged = true }
end

-- ------------------------------------------------------------------ targets

--- RocFall's normal restitution scaled by the impact velocity (Pfeiffer & Bowen
--- 1989): Rn(v) = rn / (1 + (v / vref)^2), rn = 0.53 (clean hard sandstone), vref = 9.144 m/s.
function C.rocfall(rn, vref)
    rn, vref = rn or 0.53, vref or 9.144
    return function(v) return rn / (1 + (v / vref) ^ 2) end
end

--- A target e(v) from a function, or from a table {{v, e}, ...} (sorted by v here; linear
--- interpolation between points; outside the table an error, since extrapolating a measured
--- restitution is a guess the caller should make explicitly).
function C.target(t)
    if type(t) == "function" then return t end
    if type(t) ~= "table" or #t < 1 then
        error("calibrate.target: give a function e(v) or a table {{v, e}, ...}", 2)
    end
    local pts = {}
    for i, p in ipairs(t) do
        local v, e = p[1] or p.v, p[2] or p.e
        if type(v) ~= "number" or type(e) ~= "number" then
            error(string.format("calibrate.target: entry %d must be {v, e} numbers", i), 2)
        end
        pts[#pts + 1] = { v, e }
    end
    table.sort(pts, function(p, q) return p[1] < q[1] end)
    return function(v)
        for i = 1, #pts do
            if v == pts[i][1] then return pts[i][2] end
            if i > 1 and v < pts[i][1] and v > pts[i - 1][1] then
                local p, q = pts[i - 1], pts[i]
                return p[2] + (q[2] - p[2]) * (v - p[1]) / (q[1] - p[1])
            end
        end
        error(string.format("calibrate.target: v = %g is outside the table [%g, %g]", v,
            pts[1][1], pts[#pts][1]), 2)
    end
end

-- velocities of a table target, or the given list
local function velocities_of(spec)
    if spec.velocities then return spec.velocities end
    if type(spec.target) == "table" then
        local vs = {}
        for _, p in ipairs(spec.target) do vs[#vs + 1] = p[1] or p.v end
        table.sort(vs)
        return vs
    end
    error("calibrate: give 'velocities' (the target is a function)", 3)
end

local function merged(a, b)
    local r = {}
    for k, v in pairs(a or {}) do r[k] = v end
    for k, v in pairs(b or {}) do r[k] = v end
    return r
end

-- ------------------------------------------------------------------ rigs

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
            error(string.format("calibrate.impact_rig: no separation at v = %g m/s", v), 2)
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
--- (initial gap of the lowest point, default 1e-3 R), timestep (table for m:timestep), max_time,
--- measure ("vy", default: the centroid's vertical velocity ratio; "energy": sqrt of the
--- kinetic energy after / before, translation and rotation, as An (2006) read it).
function C.clump_drop_rig(opts)
    opts = opts or {}
    local R = opts.radius or 0.04
    local rho = opts.density or 2600
    local pebbles = opts.pebbles or C.triangle_pebbles(R)
    local mass_mode = opts.mass or "disk"
    if opts.measure and opts.measure ~= "vy" and opts.measure ~= "energy" then
        error("calibrate.clump_drop_rig: measure must be 'vy' or 'energy' (got "
            .. tostring(opts.measure) .. ")", 2)
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
        local spec = { pebbles = pebbles, pos = { 0, y0 }, angle = angle, vel = { 0, -v } }
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
            error(string.format("calibrate.clump_drop_rig: no contact at v = %g m/s", v), 2)
        end
        if not left then
            error(string.format("calibrate.clump_drop_rig: the rock did not leave the wall within "
                .. "max_time = %g s at v = %g m/s", max_time, v), 2)
        end
        local vy, vx, w = rock.vel[2], rock.vel[1], rock.spin
        local ke1 = 0.5 * rock.mass * (vx * vx + vy * vy) + 0.5 * rock.inertia * w * w
        local e_energy = math.sqrt(ke1 / ke0)
        return (opts.measure == "energy") and e_energy or vy / v, { vy = vy, vx = vx, spin = w, mass = rock.mass, inertia = rock.inertia,
            e_energy = e_energy, steps = m:step(), time = m:time() }
    end
end

-- ------------------------------------------------------------------ fits

--- One parameter per impact velocity: for each v, the value x in [lo, hi] with
--- rig(fixed + {param = x}, v) = target(v). spec: rig, param, lo, hi, target (function or
--- table), velocities (for a function target), fixed (other properties), tol (on e, default
--- 1e-5), xtol (relative, default 1e-6), log (search in log x; default true when lo > 0).
--- e must be monotonic in x over [lo, hi]. Returns rows { v, target, value, e, iterations,
--- note }; value = nil with a note when the target is out of reach or the rig failed.
function C.fit_param(spec)
    assert(spec.rig and spec.param and spec.lo and spec.hi and spec.target,
        "calibrate.fit_param: needs rig, param, lo, hi, target")
    local target = C.target(spec.target)
    local uselog = spec.log
    if uselog == nil then uselog = spec.lo > 0 end
    local tol = spec.tol or 1e-5
    local rows = {}
    for _, v in ipairs(velocities_of(spec)) do
        local et = target(v)
        local function e_at(x)
            local p = merged(spec.fixed, { [spec.param] = x })
            return (spec.rig(p, v))
        end
        local function g(s)
            return e_at(uselog and math.exp(s) or s) - et
        end
        local a = uselog and math.log(spec.lo) or spec.lo
        local b = uselog and math.log(spec.hi) or spec.hi
        local row = { v = v, target = et }
        local ok, ga = pcall(g, a)
        local okb, gb = pcall(g, b)
        if not ok or not okb then
            row.note = "rig failed: " .. tostring(not ok and ga or gb)
        elseif (ga > 0) == (gb > 0) then
            row.note = string.format("out of reach: e = %.4f at %s = %g, %.4f at %g",
                ga + et, spec.param, spec.lo, gb + et, spec.hi)
        else
            local okr, s, info = pcall(C.root, g, a, b,
                { ftol = tol, xtol = (spec.xtol or 1e-6) * (uselog and 1 or math.abs(b)) })
            if okr then
                row.value = uselog and math.exp(s) or s
                row.e = info.fx + et
                row.iterations = info.iterations
            else
                row.note = "rig failed: " .. tostring(s)
            end
        end
        rows[#rows + 1] = row
    end
    return rows
end

--- Nelder-Mead simplex minimiser (own code) for a few parameters: x0 a list, step the initial
--- simplex's offsets along each axis; opts max_iter (200), ftol (1e-10, relative spread of the
--- simplex's values). Returns x, f(x), iterations.
function C.nelder_mead(f, x0, step, opts)
    local n = #x0
    local pts, vals = { x0 }, { f(x0) }
    for i = 1, n do
        local x = {}
        for j = 1, n do x[j] = x0[j] + (i == j and step[j] or 0) end
        pts[#pts + 1], vals[#vals + 1] = x, f(x)
    end
    local max_iter, ftol = opts.max_iter or 200, opts.ftol or 1e-10
    local it = 0
    local function combine(c, x, t) -- c + t (x - c)
        local r = {}
        for j = 1, n do r[j] = c[j] + t * (x[j] - c[j]) end
        return r
    end
    while it < max_iter do
        it = it + 1
        local idx = {}
        for i = 1, n + 1 do idx[i] = i end
        table.sort(idx, function(p, q) return vals[p] < vals[q] end)
        local sp, sv = {}, {}
        for i = 1, n + 1 do sp[i], sv[i] = pts[idx[i]], vals[idx[i]] end
        pts, vals = sp, sv
        if math.abs(vals[n + 1] - vals[1]) <= ftol * (math.abs(vals[1]) + 1e-300) then break end
        local cen = {}
        for j = 1, n do
            local s = 0
            for i = 1, n do s = s + pts[i][j] end
            cen[j] = s / n
        end
        local xr = combine(cen, pts[n + 1], -1)
        local fr = f(xr)
        if fr < vals[1] then
            local xe = combine(cen, pts[n + 1], -2)
            local fe = f(xe)
            if fe < fr then pts[n + 1], vals[n + 1] = xe, fe else pts[n + 1], vals[n + 1] = xr, fr end
        elseif fr < vals[n] then
            pts[n + 1], vals[n + 1] = xr, fr
        else
            local xc = combine(cen, pts[n + 1], fr < vals[n + 1] and -0.5 or 0.5)
            local fc = f(xc)
            if fc < math.min(fr, vals[n + 1]) then
                pts[n + 1], vals[n + 1] = xc, fc
            else -- shrink towards the best
                for i = 2, n + 1 do
                    pts[i] = combine(pts[1], pts[i], 0.5)
                    vals[i] = f(pts[i])
                end
            end
        end
    end
    local best = 1
    for i = 2, n + 1 do if vals[i] < vals[best] then best = i end end
    return pts[best], vals[best], it
end

--- Several parameters at once over a table: minimises sum over v of (rig(p, v) - target(v))^2.
--- spec: rig, target, velocities, fixed, params = { {name =, lo =, hi =, start =}, ... }
--- (searched in log space between lo and hi, which must be > 0; values are clamped to
--- [lo, hi]), max_iter. Returns { values = {name = x}, rms =, rows = { {v, target, e} },
--- evaluations =, iterations = }.
function C.fit_lsq(spec)
    assert(spec.rig and spec.target and spec.params, "calibrate.fit_lsq: needs rig, target, params")
    local target = C.target(spec.target)
    local vs = velocities_of(spec)
    local np = #spec.params
    local evals = 0
    local function props_of(s)
        local p = merged(spec.fixed, {})
        for j, d in ipairs(spec.params) do
            local lo, hi = math.log(d.lo), math.log(d.hi)
            p[d.name] = math.exp(math.min(hi, math.max(lo, s[j])))
        end
        return p
    end
    local function cost(s)
        local p, sum = props_of(s), 0
        for _, v in ipairs(vs) do
            evals = evals + 1
            local ok, e = pcall(spec.rig, p, v)
            if not ok then return math.huge end
            sum = sum + (e - target(v)) ^ 2
        end
        return sum
    end
    local x0, step = {}, {}
    for j, d in ipairs(spec.params) do
        assert(d.lo > 0 and d.hi > d.lo, "calibrate.fit_lsq: each param needs 0 < lo < hi")
        x0[j] = math.log(d.start or math.sqrt(d.lo * d.hi))
        step[j] = 0.25 * (math.log(d.hi) - math.log(d.lo))
    end
    local best, val, it = C.nelder_mead(cost, x0, step, { max_iter = spec.max_iter or 150 })
    local p = props_of(best)
    local out = { values = {}, rms = math.sqrt(val / #vs), rows = {}, evaluations = evals,
        iterations = it }
    for j = 1, np do out.values[spec.params[j].name] = p[spec.params[j].name] end
    for _, v in ipairs(vs) do
        out.rows[#out.rows + 1] = { v = v, target = target(v), e = (spec.rig(p, v)) }
    end
    return out
end

--- The linear model's normal damping ratio for a restitution e (dp_mode 0, the dashpot may
--- pull until the overlap is back to zero): closed form beta = -ln e / sqrt(pi^2 + ln^2 e)
--- (docs/models/linear.md, the closed form of a linear spring-dashpot).
function C.linear_beta(e)
    local l = math.log(e)
    return -l / math.sqrt(math.pi ^ 2 + l * l)
end

--- Inverse check: e = exp(-pi beta / sqrt(1 - beta^2)).
function C.linear_e(beta)
    return math.exp(-math.pi * beta / math.sqrt(1 - beta * beta))
end

--- Fits linear's dp_nratio to a target restitution per velocity on a rig (default: a ball on a
--- wall, R = 0.1 m, kn = 1e8 N/m, dp_mode 0). Returns fit_param rows with the closed form added
--- (row.closed = C.linear_beta(target), exact for dp_mode 0).
function C.fit_linear_dp_nratio(spec)
    local rig = spec.rig or C.impact_rig{ model = "linear",
        props = merged({ kn = 1e8, dp_mode = 0 }, spec.props), radius = spec.radius or 0.1 }
    local rows = C.fit_param{ rig = rig, param = "dp_nratio", lo = 0, hi = spec.hi or 0.99,
        log = false, target = spec.target, velocities = spec.velocities or { 1 },
        tol = spec.tol or 1e-7, fixed = spec.fixed }
    for _, r in ipairs(rows) do r.closed = C.linear_beta(r.target) end
    return rows
end

--- What a parameter set gives over velocities (no fit): rows { v, target, e }. params may be a
--- table or a function params(v) (for example the restitution mode with target_e = Rn(v)).
function C.follow(spec)
    local target = spec.target and C.target(spec.target)
    local rows = {}
    for _, v in ipairs(velocities_of(spec)) do
        local p = type(spec.params) == "function" and spec.params(v) or spec.params
        local ok, e, info = pcall(spec.rig, p, v)
        rows[#rows + 1] = { v = v, target = target and target(v), e = ok and e or nil,
            note = (not ok) and tostring(e) or nil, info = ok and info or nil }
    end
    return rows
end

-- ------------------------------------------------------------------ several targets at once

--- A two-level fractional factorial design for p factors, with a centre point: 2^q runs, q the
--- smallest with 2^q >= p + 2 (at least one degree of freedom beyond a first-order model with
--- its centre); the columns are the q base factors, then products of 3, 5, ... of them (so a
--- main effect is aliased with no two-factor interaction while p <= 2^(q-1): resolution IV),
--- then products of 2, 4, ... (resolution III beyond). Returns the list of points in
--- {-1, 0, +1}^p, the centre {0, ..., 0} first. Columns are orthogonal and balanced, so a
--- first-order least-squares fit on them estimates each main effect independently.
function C.design(p)
    assert(math.type(p) == "integer" and p >= 1 and p <= 15, "calibrate.design: p must be an integer in [1, 15]")
    local q = 1
    while 2 ^ q < p + 2 do q = q + 1 end
    local subsets = {}
    for mask = 1, 2 ^ q - 1 do
        local size = 0
        for j = 0, q - 1 do if mask & (1 << j) ~= 0 then size = size + 1 end end
        subsets[#subsets + 1] = { mask = mask, size = size }
    end
    -- odd sizes first (1, 3, 5, ...), then even (2, 4, ...); within a size by mask
    table.sort(subsets, function(a, b)
        local ao, bo = a.size % 2, b.size % 2
        if ao ~= bo then return ao > bo end
        if a.size ~= b.size then return a.size < b.size end
        return a.mask < b.mask
    end)
    local pts = { {} }
    for j = 1, p do pts[1][j] = 0 end
    for run = 0, 2 ^ q - 1 do
        local x = {}
        for j = 1, p do
            local mask, v = subsets[j].mask, 1
            for b = 0, q - 1 do
                if mask & (1 << b) ~= 0 and run & (1 << b) == 0 then v = -v end
            end
            x[j] = v
        end
        pts[#pts + 1] = x
    end
    return pts
end

-- Solves the n x n system A x = b (Gaussian elimination with partial pivoting); nil when A is
-- singular to working precision.
local function solve_linear(A, b)
    local n = #b
    local M = {}
    for i = 1, n do
        M[i] = {}
        for j = 1, n do M[i][j] = A[i][j] end
        M[i][n + 1] = b[i]
    end
    for k = 1, n do
        local piv = k
        for i = k + 1, n do if math.abs(M[i][k]) > math.abs(M[piv][k]) then piv = i end end
        if M[piv][k] == 0 then return nil end
        M[k], M[piv] = M[piv], M[k]
        for i = k + 1, n do
            local f = M[i][k] / M[k][k]
            for j = k, n + 1 do M[i][j] = M[i][j] - f * M[k][j] end
        end
    end
    local x = {}
    for i = n, 1, -1 do
        local s = M[i][n + 1]
        for j = i + 1, n do s = s - M[i][j] * x[j] end
        x[i] = s / M[i][i]
    end
    return x
end

--- Weighted linear least squares: the coefficients beta minimising sum_i w_i (y_i - X_i beta)^2
--- (normal equations; `ridge` adds ridge * trace/n to the diagonal, default 1e-10, so a design
--- that leaves a coefficient undetermined gives a small one instead of failing).
function C.lsq(X, y, w, ridge)
    local n, m = #X, #X[1]
    local A, b = {}, {}
    for j = 1, m do
        A[j], b[j] = {}, 0
        for k = 1, m do A[j][k] = 0 end
    end
    for i = 1, n do
        local wi = w and w[i] or 1
        for j = 1, m do
            b[j] = b[j] + wi * X[i][j] * y[i]
            for k = 1, m do A[j][k] = A[j][k] + wi * X[i][j] * X[i][k] end
        end
    end
    local tr = 0
    for j = 1, m do tr = tr + A[j][j] end
    for j = 1, m do A[j][j] = A[j][j] + (ridge or 1e-10) * tr / m end
    return solve_linear(A, b)
end

local kTargetsKnown = { params = true, targets = true, evaluate = true, budget = true, radius = true,
    min_radius = true, max_radius = true, design = true, on_point = true }

--- Fits p parameters to several targets at once, for expensive and noisy evaluations (a DEM
--- material's laboratory tests): a design of experiments, then power-law response surfaces
--- fitted in log space and minimised in a trust region, each step evaluated and the surfaces
--- refitted (docs/material.md, "Calibration against several targets").
---
--- spec:
---   params  = {{name =, lo =, hi =, start =, spread =}, ...}: searched in s = ln x within
---             [ln lo, ln hi] (0 < lo < hi), from start (default sqrt(lo hi)); spread = the
---             design's half-width in ln x (default 0.35: x e^{+-0.35}, about x1.4)
---   targets = {{name =, value =, weight = 1, tol = 0.05}, ...}: the outputs wanted (> 0); the
---             misfit is F = sum_j weight_j ln(y_j / value_j)^2; a target is met when
---             |y_j / value_j - 1| <= tol_j
---   evaluate(points, batch) -> a list of outputs, one table {name = y} per point (nil, or a
---             missing or non-positive y: the point failed). points = {{name = x}, ...}; batch
---             counts the calls from 1 (a name for a checkpoint: the calls are the same on a
---             rerun, as the method is deterministic given the outputs)
---   budget  = the number of points evaluated at most (default design + 3 p)
---   radius  = the first trust radius, in spreads (default 2); min_radius (0.1), max_radius (4)
---   design  = a list of points in spreads (default C.design(p): the centre and a fractional
---             factorial at +-1 spread)
---   on_point(row): called after each evaluated point (progress, a report)
---
--- The method. (1) The design is evaluated in one batch. (2) Each output is fitted as a power
--- law of the parameters, ln y_j = a_j + sum_k b_jk u_k (u = (s - s_c) / spread, about the
--- best point so far s_c), by weighted least squares, the points weighted by a Gaussian of their
--- distance from s_c with a width of twice the trust radius (far points count less as the
--- search closes in). (3) The surfaces' misfit is minimised (Nelder-Mead) over u within the
--- bounds and |u_k| <= radius. (4) That point is evaluated; if it lowers the misfit it becomes
--- the best point and a step that reached the trust region's edge doubles the radius, else the
--- radius halves. It stops when every target is met at the best point ("targets"), when the
--- budget is spent ("budget"), or when the radius falls below min_radius ("radius").
---
--- Returns { best = row, rows = {row, ...}, stop, evaluations, elasticities = {[target] =
--- {[param] = b}} (the last surfaces' d ln y / d ln x) }; a row = { index, batch, phase =
--- "design" | "step", params = {name = x}, out = {name = y}, misfit, met (every target met),
--- predicted (the surfaces' misfit there, steps only), radius }.
function C.fit_targets(spec)
    for k in pairs(spec) do
        if not kTargetsKnown[k] then error("calibrate.fit_targets: unknown option '" .. tostring(k) .. "'", 2) end
    end
    local params, targets, evaluate = spec.params, spec.targets, spec.evaluate
    if type(params) ~= "table" or #params == 0 then error("calibrate.fit_targets: 'params' must be a non-empty list", 2) end
    if type(targets) ~= "table" or #targets == 0 then error("calibrate.fit_targets: 'targets' must be a non-empty list", 2) end
    if type(evaluate) ~= "function" then error("calibrate.fit_targets: 'evaluate' must be a function", 2) end
    local p, nt = #params, #targets
    local s0, spread, ulo, uhi = {}, {}, {}, {}
    for k, d in ipairs(params) do
        if type(d.name) ~= "string" or type(d.lo) ~= "number" or type(d.hi) ~= "number" or not (d.lo > 0 and d.hi > d.lo) then
            error(string.format("calibrate.fit_targets: params[%d] needs a name and 0 < lo < hi", k), 2)
        end
        local start = d.start or math.sqrt(d.lo * d.hi)
        if not (start >= d.lo and start <= d.hi) then
            error(string.format("calibrate.fit_targets: params[%d] ('%s'): start %g is outside [%g, %g]", k, d.name,
                start, d.lo, d.hi), 2)
        end
        s0[k], spread[k] = math.log(start), d.spread or 0.35
        ulo[k], uhi[k] = (math.log(d.lo) - s0[k]) / spread[k], (math.log(d.hi) - s0[k]) / spread[k]
    end
    for j, t in ipairs(targets) do
        if type(t.name) ~= "string" or type(t.value) ~= "number" or not (t.value > 0) then
            error(string.format("calibrate.fit_targets: targets[%d] needs a name and a value > 0", j), 2)
        end
    end
    local design = spec.design or C.design(p)
    local budget = spec.budget or (#design + 3 * p)
    local radius, rmin, rmax = spec.radius or 2, spec.min_radius or 0.1, spec.max_radius or 4
    local rows, batch = {}, 0
    local function clamp_u(u)
        local v = {}
        for k = 1, p do v[k] = math.min(uhi[k], math.max(ulo[k], u[k])) end
        return v
    end
    local function params_of(u)
        local x = {}
        for k, d in ipairs(params) do x[d.name] = math.exp(s0[k] + spread[k] * u[k]) end
        return x
    end
    local function misfit_of(out)
        if type(out) ~= "table" then return math.huge, false end
        local F, met = 0, true
        for _, t in ipairs(targets) do
            local y = out[t.name]
            if type(y) ~= "number" or not (y > 0) or y == math.huge then return math.huge, false end
            F = F + (t.weight or 1) * math.log(y / t.value) ^ 2
            if math.abs(y / t.value - 1) > (t.tol or 0.05) then met = false end
        end
        return F, met
    end
    local function run(us, phase)
        batch = batch + 1
        local pts = {}
        for i, u in ipairs(us) do pts[i] = params_of(u) end
        local outs = evaluate(pts, batch)
        if type(outs) ~= "table" then error("calibrate.fit_targets: evaluate must return a list of outputs", 2) end
        local new = {}
        for i, u in ipairs(us) do
            local F, met = misfit_of(outs[i])
            local row = { index = #rows + 1, batch = batch, phase = phase, u = u, params = pts[i], out = outs[i],
                          misfit = F, met = met, radius = radius }
            rows[#rows + 1] = row
            new[#new + 1] = row
            if spec.on_point then spec.on_point(row) end
        end
        return new
    end
    local function best_row()
        local b
        for _, r in ipairs(rows) do
            if not b or r.misfit < b.misfit then b = r end
        end
        return b
    end
    -- (1) the design, about the start, clamped to the bounds
    local dus = {}
    for i, d in ipairs(design) do
        if i > budget then break end
        dus[i] = clamp_u(d)
    end
    run(dus, "design")
    local stop = "budget"
    local surf -- the last surfaces: a[j], b[j][k] about uc
    local function fit_surfaces(uc)
        local X, w, ok = {}, {}, {}
        for _, r in ipairs(rows) do
            if r.misfit < math.huge then
                local x, d2 = { 1 }, 0
                for k = 1, p do x[k + 1] = r.u[k] - uc[k]; d2 = d2 + x[k + 1] ^ 2 end
                X[#X + 1] = x
                w[#w + 1] = math.max(1e-3, math.exp(-0.5 * d2 / (2 * radius) ^ 2))
                ok[#ok + 1] = r
            end
        end
        if #X < p + 1 then return nil end
        local s = { a = {}, b = {}, uc = uc }
        for j, t in ipairs(targets) do
            local y = {}
            for i, r in ipairs(ok) do y[i] = math.log(r.out[t.name]) end
            local beta = C.lsq(X, y, w)
            if not beta then return nil end
            s.a[j], s.b[j] = beta[1], {}
            for k = 1, p do s.b[j][k] = beta[k + 1] end
        end
        return s
    end
    local function predicted(s, u)
        local F = 0
        for j, t in ipairs(targets) do
            local ly = s.a[j]
            for k = 1, p do ly = ly + s.b[j][k] * (u[k] - s.uc[k]) end
            F = F + (t.weight or 1) * (ly - math.log(t.value)) ^ 2
        end
        return F
    end
    while true do
        local best = best_row()
        if best.met then stop = "targets"; break end
        if #rows >= budget then stop = "budget"; break end
        if radius < rmin then stop = "radius"; break end
        local uc = best.u
        surf = fit_surfaces(uc)
        if not surf then stop = "failed"; break end
        -- (3) the surfaces' minimum within the bounds and the trust region (a point outside is
        -- taken to the nearest inside, so the minimiser sees a continuous function)
        local function inside(v)
            local w = {}
            for k = 1, p do
                w[k] = math.min(uhi[k], math.max(ulo[k], math.min(uc[k] + radius, math.max(uc[k] - radius, v[k]))))
            end
            return w
        end
        local function fhat(v) return predicted(surf, inside(v)) end
        local step = {}
        for k = 1, p do step[k] = 0.5 * radius end
        local ustar = uc
        for _ = 1, 3 do -- restarts from the last minimum: a simplex may collapse on a bound
            local x = C.nelder_mead(fhat, ustar, step, { max_iter = 2000, ftol = 1e-14 })
            ustar = inside(x)
        end
        local moved = 0
        for k = 1, p do moved = math.max(moved, math.abs(ustar[k] - uc[k])) end
        local fpred = predicted(surf, ustar)
        if moved < 1e-6 or fpred >= predicted(surf, uc) then
            -- the surfaces see no better point here: look closer
            radius = 0.5 * radius
        else
            local r = run({ ustar }, "step")[1]
            r.predicted = fpred
            if r.misfit < best.misfit then
                if moved >= 0.9 * radius then radius = math.min(rmax, 2 * radius) end
            else
                radius = 0.5 * radius
            end
        end
    end
    local out = { best = best_row(), rows = rows, stop = stop, evaluations = #rows, elasticities = {} }
    if surf then
        for j, t in ipairs(targets) do
            out.elasticities[t.name] = {}
            for k, d in ipairs(params) do out.elasticities[t.name][d.name] = surf.b[j][k] / spread[k] end
        end
    end
    return out
end

-- ------------------------------------------------------------------ run-out

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
            error("calibrate.runout_rig: rock must be 'ball' or 'pair' (got " .. tostring(rock_kind)
                .. ")", 2)
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

--- Fits one property (rrlinear's rr_fric, or any other) to a measured run-out distance:
--- spec = { model =, prop =, measured = (m), lo =, hi =, props = {...}, rig options (slope, v0,
--- rock, radius, density, mass) }. The run-out must fall as the property grows over [lo, hi].
--- Returns value, { distance =, iterations =, d_lo =, d_hi = }.
function C.fit_runout(spec)
    assert(spec.model and spec.prop and spec.measured and spec.lo and spec.hi,
        "calibrate.fit_runout: needs model, prop, measured, lo, hi")
    local ok, info = pcall(talus.contact_model_info, spec.model)
    if not ok then
        error(string.format("calibrate.fit_runout: contact model '%s' is not available (%s)",
            spec.model, tostring(info)), 2)
    end
    local rig = C.runout_rig(merged(spec, { model = spec.model }))
    local function d(x)
        local dist, inf = rig({ [spec.prop] = x })
        if not inf.stopped then return math.huge end
        return dist
    end
    local tol = spec.tol or 1e-4 * spec.measured
    local function g(s) return d(math.exp(s)) - spec.measured end
    local x, info2 = C.root(g, math.log(spec.lo), math.log(spec.hi), { ftol = tol })
    local value = math.exp(x)
    return value, { distance = info2.fx + spec.measured, iterations = info2.iterations }
end

-- ------------------------------------------------------------------ output

local function fmt(x)
    if x == nil then return "-" end
    if type(x) == "number" then
        if x == math.floor(x) and math.abs(x) < 1e6 then return string.format("%d", x) end
        return string.format("%.5g", x)
    end
    return tostring(x)
end

--- Prints rows as a Markdown table with the given columns ({key, ...} or {{key, title}, ...}).
function C.print_table(rows, cols, out)
    out = out or io.write
    local keys, titles = {}, {}
    for i, c in ipairs(cols) do
        keys[i] = type(c) == "table" and c[1] or c
        titles[i] = type(c) == "table" and c[2] or c
    end
    out("| " .. table.concat(titles, " | ") .. " |\n")
    out(string.rep("|---", #cols) .. "|\n")
    for _, r in ipairs(rows) do
        local cells = {}
        for i, k in ipairs(keys) do cells[i] = fmt(r[k]) end
        out("| " .. table.concat(cells, " | ") .. " |\n")
    end
end

--- Writes rows as CSV (numbers at full precision unless `number_format` is given, strings quoted,
--- missing values empty).
function C.write_csv(file, rows, cols, number_format)
    number_format = number_format or "%.17g"
    local f = assert(io.open(file, "w"))
    f:write(table.concat(cols, ","), "\n")
    for _, r in ipairs(rows) do
        local cells = {}
        for i, k in ipairs(cols) do
            local x = r[k]
            cells[i] = x == nil and "" or (type(x) == "number" and string.format(number_format, x)
                or '"' .. tostring(x):gsub('"', '""') .. '"')
        end
        f:write(table.concat(cells, ","), "\n")
    end
    f:close()
end

return C
