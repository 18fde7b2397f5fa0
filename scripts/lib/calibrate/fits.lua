-- SPDX-License-Identifier: MIT
-- calibrate/fits.lua: contact-model parameters fitted to a restitution or a run-out: one parameter
-- per velocity (a root), several over a table (least squares), linear's damping ratio.
local Opt = require("talus_util.options")
local raise = require("talus_util.errors").raise
local Optim = require("talus_util.optimize")
local T = require("calibrate.targets")
local Rigs = require("calibrate.rigs")

local C = {}
local merged = Opt.merged


--- One parameter per impact velocity: for each v, the value x in [lo, hi] with
--- rig(fixed + {param = x}, v) = target(v). spec: rig, param, lo, hi, target (function or
--- table), velocities (for a function target), fixed (other properties), tol (on e, default
--- 1e-5), xtol (relative, default 1e-6), log (search in log x; default true when lo > 0).
--- e must be monotonic in x over [lo, hi]. Returns rows { v, target, value, e, iterations,
--- note }; value = nil with a note when the target is out of reach or the rig failed.
function C.fit_param(spec)
    if not (spec.rig and spec.param and spec.lo and spec.hi and spec.target) then
        raise("calibrate.fit_param: needs rig, param, lo, hi, target")
    end
    local target = T.target(spec.target)
    local uselog = spec.log
    if uselog == nil then uselog = spec.lo > 0 end
    local tol = spec.tol or 1e-5
    local rows = {}
    for _, v in ipairs(T.velocities_of(spec)) do
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
            local okr, s, info = pcall(Optim.root, g, a, b,
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

--- Several parameters at once over a table: minimises sum over v of (rig(p, v) - target(v))^2.
--- spec: rig, target, velocities, fixed, params = { {name =, lo =, hi =, start =}, ... }
--- (searched in log space between lo and hi, which must be > 0; values are clamped to
--- [lo, hi]), max_iter. Returns { values = {name = x}, rms =, rows = { {v, target, e} },
--- evaluations =, iterations = }.
function C.fit_lsq(spec)
    if not (spec.rig and spec.target and spec.params) then raise("calibrate.fit_lsq: needs rig, target, params") end
    local target = T.target(spec.target)
    local vs = T.velocities_of(spec)
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
        if not (d.lo > 0 and d.hi > d.lo) then raise("calibrate.fit_lsq: each param needs 0 < lo < hi") end
        x0[j] = math.log(d.start or math.sqrt(d.lo * d.hi))
        step[j] = 0.25 * (math.log(d.hi) - math.log(d.lo))
    end
    local best, val, it = Optim.nelder_mead(cost, x0, step, { max_iter = spec.max_iter or 150 })
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
    local rig = spec.rig or Rigs.impact_rig{ model = "linear",
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
    local target = spec.target and T.target(spec.target)
    local rows = {}
    for _, v in ipairs(T.velocities_of(spec)) do
        local p = type(spec.params) == "function" and spec.params(v) or spec.params
        local ok, e, info = pcall(spec.rig, p, v)
        rows[#rows + 1] = { v = v, target = target and target(v), e = ok and e or nil,
            note = (not ok) and tostring(e) or nil, info = ok and info or nil }
    end
    return rows
end


--- Fits one property (rrlinear's rr_fric, or any other) to a measured run-out distance:
--- spec = { model =, prop =, measured = (m), lo =, hi =, props = {...}, rig options (slope, v0,
--- rock, radius, density, mass) }. The run-out must fall as the property grows over [lo, hi].
--- Returns value, { distance =, iterations =, d_lo =, d_hi = }.
function C.fit_runout(spec)
    if not (spec.model and spec.prop and spec.measured and spec.lo and spec.hi) then
        raise("calibrate.fit_runout: needs model, prop, measured, lo, hi")
    end
    local ok, info = pcall(talus.contact_model_info, spec.model)
    if not ok then
        raise(string.format("calibrate.fit_runout: contact model '%s' is not available (%s)",
            spec.model, tostring(info)))
    end
    local rig = Rigs.runout_rig(merged(spec, { model = spec.model }))
    local function d(x)
        local dist, inf = rig({ [spec.prop] = x })
        if not inf.stopped then return math.huge end
        return dist
    end
    local tol = spec.tol or 1e-4 * spec.measured
    local function g(s) return d(math.exp(s)) - spec.measured end
    local x, info2 = Optim.root(g, math.log(spec.lo), math.log(spec.hi), { ftol = tol })
    local value = math.exp(x)
    return value, { distance = info2.fx + spec.measured, iterations = info2.iterations }
end

return C
