-- SPDX-License-Identifier: MIT
-- talus_util/optimize.lua: the optimisers the calibrations share (own code): a bracketing root
-- finder, the Nelder-Mead simplex, two-level designs, weighted least squares
-- (response_surface.lua builds the fit of several parameters to several targets on them).
local raise = require("talus_util.errors").raise

local C = {}

--- Illinois regula falsi on a bracket [a, b] with f(a) f(b) <= 0. Regula falsi keeps the
--- bracket (so it cannot diverge, unlike the secant method); the Illinois change halves the
--- function value kept at the end that was retained twice in a row, which removes plain regula
--- falsi's one-sided, linear convergence (order about 1.44 on smooth roots). A bisection step
--- whenever two steps did not halve the bracket bounds the cost by about twice bisection's.
--- opts: xtol (absolute, default 1e-12 (|a| + |b|) + 1e-300), ftol (|f| <= ftol stops; default
--- 0), max_iter (default 200). Returns x, { iterations =, fx =, a =, b = } (the final bracket).
function C.root(f, a, b, opts)
    opts = opts or {}
    if not (type(f) == "function") then raise("calibrate.root: f must be a function") end
    if not (type(a) == "number" and type(b) == "number" and a == a and b == b) then
        raise("calibrate.root: the bracket must be two numbers")
    end
    local xtol = opts.xtol or (1e-12 * (math.abs(a) + math.abs(b)) + 1e-300)
    local ftol = opts.ftol or 0
    local max_iter = opts.max_iter or 200
    local fa, fb = f(a), f(b)
    if fa == 0 then return a, { iterations = 0, fx = 0, a = a, b = a } end
    if fb == 0 then return b, { iterations = 0, fx = 0, a = b, b = b } end
    if fa ~= fa or fb ~= fb then
        raise(string.format("calibrate.root: f is NaN at the bracket ends (f(%g) = %g, f(%g) = %g)",
            a, fa, b, fb))
    end
    if (fa > 0) == (fb > 0) then
        raise(string.format("calibrate.root: [%g, %g] does not bracket a root: f(%g) = %g and "
            .. "f(%g) = %g have the same sign", a, b, a, fa, b, fb))
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
        if fx ~= fx then raise(string.format("calibrate.root: f(%g) is NaN", x)) end
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

--- A two-level fractional factorial design for p factors, with a centre point: 2^q runs, q the
--- smallest with 2^q >= p + 2 (at least one degree of freedom beyond a first-order model with
--- its centre); the columns are the q base factors, then products of 3, 5, ... of them (so a
--- main effect is aliased with no two-factor interaction while p <= 2^(q-1): resolution IV),
--- then products of 2, 4, ... (resolution III beyond). Returns the list of points in
--- {-1, 0, +1}^p, the centre {0, ..., 0} first. Columns are orthogonal and balanced, so a
--- first-order least-squares fit on them estimates each main effect independently.
function C.design(p)
    if not (math.type(p) == "integer" and p >= 1 and p <= 15) then
        raise("calibrate.design: p must be an integer in [1, 15]")
    end
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

return C
