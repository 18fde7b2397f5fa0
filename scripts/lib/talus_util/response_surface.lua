-- SPDX-License-Identifier: MIT
-- talus_util/response_surface.lua: several parameters fitted to several targets at once, for
-- expensive and noisy evaluations (calibrate.fit_targets, material.calibrate): a design, then
-- power-law response surfaces minimised in a trust region (own code, on optimize.lua's designs,
-- least squares and simplex).
local Opt = require("talus_util.options")
local raise = require("talus_util.errors").raise
local C = require("talus_util.optimize")

local RS = {}

local kTargetsKnown = { params = true, targets = true, evaluate = true, budget = true, radius = true,
    min_radius = true, max_radius = true, design = true, on_point = true }

-- fit_targets' steps, over one state table `ft`.

--- The checked spec as the state of a fit: parameters as u = (ln x - ln start) / spread within
--- their bounds [ulo, uhi], the design, the budget and the trust radius.
local function targets_state(spec)
    Opt.check(spec, kTargetsKnown, nil, "calibrate.fit_targets: ")
    local params, targets, evaluate = spec.params, spec.targets, spec.evaluate
    if type(params) ~= "table" or #params == 0 then
        raise("calibrate.fit_targets: 'params' must be a non-empty list")
    end
    if type(targets) ~= "table" or #targets == 0 then
        raise("calibrate.fit_targets: 'targets' must be a non-empty list")
    end
    if type(evaluate) ~= "function" then raise("calibrate.fit_targets: 'evaluate' must be a function") end
    local p = #params
    local s0, spread, ulo, uhi = {}, {}, {}, {}
    for k, d in ipairs(params) do
        if type(d.name) ~= "string" or type(d.lo) ~= "number" or type(d.hi) ~= "number"
            or not (d.lo > 0 and d.hi > d.lo) then
            raise("calibrate.fit_targets: params[%d] needs a name and 0 < lo < hi", k)
        end
        local start = d.start or math.sqrt(d.lo * d.hi)
        if not (start >= d.lo and start <= d.hi) then
            raise("calibrate.fit_targets: params[%d] ('%s'): start %g is outside [%g, %g]", k, d.name, start, d.lo,
                d.hi)
        end
        s0[k], spread[k] = math.log(start), d.spread or 0.35
        ulo[k], uhi[k] = (math.log(d.lo) - s0[k]) / spread[k], (math.log(d.hi) - s0[k]) / spread[k]
    end
    for j, t in ipairs(targets) do
        if type(t.name) ~= "string" or type(t.value) ~= "number" or not (t.value > 0) then
            raise("calibrate.fit_targets: targets[%d] needs a name and a value > 0", j)
        end
    end
    local design = spec.design or C.design(p)
    return {
        spec = spec, params = params, targets = targets, evaluate = evaluate, p = p,
        s0 = s0, spread = spread, ulo = ulo, uhi = uhi, design = design,
        budget = spec.budget or (#design + 3 * p),
        radius = spec.radius or 2, rmin = spec.min_radius or 0.1, rmax = spec.max_radius or 4,
        rows = {}, batch = 0,
    }
end

local function clamp_u(ft, u)
    local v = {}
    for k = 1, ft.p do v[k] = math.min(ft.uhi[k], math.max(ft.ulo[k], u[k])) end
    return v
end

local function params_of(ft, u)
    local x = {}
    for k, d in ipairs(ft.params) do x[d.name] = math.exp(ft.s0[k] + ft.spread[k] * u[k]) end
    return x
end

--- The misfit F = sum_j weight_j ln(y_j / value_j)^2 of one output, and whether every target
--- is met; an output that failed gives huge and false.
local function misfit_of(ft, out)
    if type(out) ~= "table" then return math.huge, false end
    local F, met = 0, true
    for _, t in ipairs(ft.targets) do
        local y = out[t.name]
        if type(y) ~= "number" or not (y > 0) or y == math.huge then return math.huge, false end
        F = F + (t.weight or 1) * math.log(y / t.value) ^ 2
        if math.abs(y / t.value - 1) > (t.tol or 0.05) then met = false end
    end
    return F, met
end

--- Evaluates the points `us` as one batch; their rows, also appended to ft.rows.
local function run_batch(ft, us, phase)
    ft.batch = ft.batch + 1
    local pts = {}
    for i, u in ipairs(us) do pts[i] = params_of(ft, u) end
    local outs = ft.evaluate(pts, ft.batch)
    if type(outs) ~= "table" then raise("calibrate.fit_targets: evaluate must return a list of outputs") end
    local new = {}
    for i, u in ipairs(us) do
        local F, met = misfit_of(ft, outs[i])
        local row = { index = #ft.rows + 1, batch = ft.batch, phase = phase, u = u, params = pts[i], out = outs[i],
                      misfit = F, met = met, radius = ft.radius }
        ft.rows[#ft.rows + 1] = row
        new[#new + 1] = row
        if ft.spec.on_point then ft.spec.on_point(row) end
    end
    return new
end

local function best_row(ft)
    local b
    for _, r in ipairs(ft.rows) do
        if not b or r.misfit < b.misfit then b = r end
    end
    return b
end

--- (2) Each output as a power law about uc, ln y_j = a_j + sum_k b_jk (u_k - uc_k), by least
--- squares weighted by a Gaussian of the distance from uc (width twice the trust radius); nil
--- when too few points succeeded or the fit is singular.
local function fit_surfaces(ft, uc)
    local p = ft.p
    local X, w, ok = {}, {}, {}
    for _, r in ipairs(ft.rows) do
        if r.misfit < math.huge then
            local x, d2 = { 1 }, 0
            for k = 1, p do x[k + 1] = r.u[k] - uc[k]; d2 = d2 + x[k + 1] ^ 2 end
            X[#X + 1] = x
            w[#w + 1] = math.max(1e-3, math.exp(-0.5 * d2 / (2 * ft.radius) ^ 2))
            ok[#ok + 1] = r
        end
    end
    if #X < p + 1 then return nil end
    local s = { a = {}, b = {}, uc = uc }
    for j, t in ipairs(ft.targets) do
        local y = {}
        for i, r in ipairs(ok) do y[i] = math.log(r.out[t.name]) end
        local beta = C.lsq(X, y, w)
        if not beta then return nil end
        s.a[j], s.b[j] = beta[1], {}
        for k = 1, p do s.b[j][k] = beta[k + 1] end
    end
    return s
end

--- The surfaces' misfit at u.
local function predicted(ft, s, u)
    local F = 0
    for j, t in ipairs(ft.targets) do
        local ly = s.a[j]
        for k = 1, ft.p do ly = ly + s.b[j][k] * (u[k] - s.uc[k]) end
        F = F + (t.weight or 1) * (ly - math.log(t.value)) ^ 2
    end
    return F
end

--- (3) The surfaces' minimum within the bounds and the trust region about uc (a point outside
--- is taken to the nearest inside, so the minimiser sees a continuous function).
local function surface_minimum(ft, surf, uc)
    local p, radius = ft.p, ft.radius
    local function inside(v)
        local w = {}
        for k = 1, p do
            w[k] = math.min(ft.uhi[k], math.max(ft.ulo[k], math.min(uc[k] + radius, math.max(uc[k] - radius, v[k]))))
        end
        return w
    end
    local function fhat(v) return predicted(ft, surf, inside(v)) end
    local step = {}
    for k = 1, p do step[k] = 0.5 * radius end
    local ustar = uc
    for _ = 1, 3 do -- restarts from the last minimum: a simplex may collapse on a bound
        local x = C.nelder_mead(fhat, ustar, step, { max_iter = 2000, ftol = 1e-14 })
        ustar = inside(x)
    end
    return ustar
end

--- (3) and (4): one trust-region step from the best row; the radius doubles after a step to the
--- edge that lowered the misfit and halves after one that did not (or when the surfaces see no
--- better point). Returns the surfaces, or nil when they could not be fitted.
local function trust_step(ft, best)
    local uc = best.u
    local surf = fit_surfaces(ft, uc)
    if not surf then return nil end
    local ustar = surface_minimum(ft, surf, uc)
    local moved = 0
    for k = 1, ft.p do moved = math.max(moved, math.abs(ustar[k] - uc[k])) end
    local fpred = predicted(ft, surf, ustar)
    if moved < 1e-6 or fpred >= predicted(ft, surf, uc) then
        ft.radius = 0.5 * ft.radius -- the surfaces see no better point here: look closer
    else
        local r = run_batch(ft, { ustar }, "step")[1]
        r.predicted = fpred
        if r.misfit < best.misfit then
            if moved >= 0.9 * ft.radius then ft.radius = math.min(ft.rmax, 2 * ft.radius) end
        else
            ft.radius = 0.5 * ft.radius
        end
    end
    return surf
end

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
function RS.fit_targets(spec)
    local ft = targets_state(spec)
    -- (1) the design, about the start, clamped to the bounds
    local dus = {}
    for i, d in ipairs(ft.design) do
        if i > ft.budget then break end
        dus[i] = clamp_u(ft, d)
    end
    run_batch(ft, dus, "design")
    local stop, surf = "budget", nil -- surf: the last surfaces fitted
    while true do
        local best = best_row(ft)
        if best.met then stop = "targets"; break end
        if #ft.rows >= ft.budget then stop = "budget"; break end
        if ft.radius < ft.rmin then stop = "radius"; break end
        surf = trust_step(ft, best)
        if not surf then stop = "failed"; break end
    end
    local out = { best = best_row(ft), rows = ft.rows, stop = stop, evaluations = #ft.rows, elasticities = {} }
    if surf then
        for j, t in ipairs(ft.targets) do
            out.elasticities[t.name] = {}
            for k, d in ipairs(ft.params) do out.elasticities[t.name][d.name] = surf.b[j][k] / ft.spread[k] end
        end
    end
    return out
end

return RS
