-- SPDX-License-Identifier: MIT
-- calibrate/apparent.lua: a slope material fitted to a target apparent Rn, the one its rocks show on
-- the slope itself. RocFall's Rn is an apparent restitution (a lumped mass); a clump's centroid
-- rebounds with another ratio than its material's, because it hits on corners away from its
-- centroid (docs/rockfall.md, "Rn of rocks that are not disks"). So the fit runs the analysis'
-- own rocks, shapes and slope: a Monte Carlo per trial value, the statistic over the impacts on
-- the material, a root of statistic - target.
local Opt = require("talus_util.options")
local Optim = require("talus_util.optimize")
local S = require("talus_util.stats")
local raise = require("talus_util.errors").raise

local C = {}

local KEYS = { "analysis", "material", "target", "prop", "lo", "hi", "n", "shape", "statistic",
    "tol", "max_iter", "jobs" }

--- The apparent Rn of the impacts on `material` (of `shape`, or every shape) in records:
--- statistic "median" (default) or "mean"; returns it, the impacts counted, and the median's
--- confidence interval.
function C.apparent_rn(records, material, shape, statistic)
    local rn = {}
    for _, r in ipairs(records) do
        if shape == nil or r.shape == shape then
            for _, im in ipairs(r.impacts or {}) do
                if im.material == material and S.isnum(im.rn) and im.ended ~= false then
                    rn[#rn + 1] = im.rn
                end
            end
        end
    end
    local d = S.describe(rn, { 0.5 })
    local value = (statistic or "median") == "mean" and d.mean or d.median
    return value, d.n, d.median_lo, d.median_hi
end

--- Fits one property of one slope material (dp_nratio by default) so that the apparent Rn of the
--- impacts on it equals `target`. spec: analysis (the options table given to rockfall.analysis,
--- not changed), material (a name in it), target, prop ("dp_nratio"), lo, hi (the bracket,
--- default 0.01 and 0.9), n (rocks per trial, default 100), shape (count only this shape's
--- impacts), statistic ("median" or "mean"), tol (on the statistic, default 0.005), max_iter
--- (default 12), jobs (talus.map workers). The rocks are the same in every trial (the
--- analysis' seed), so the statistic moves with the property, not with new draws.
--- Returns { value =, rn =, impacts =, rn_lo =, rn_hi = (the median's interval), trials =
--- {{value, rn, impacts}}, note = (when the target is out of reach) }.
function C.fit_apparent_rn(spec)
    local rockfall = require("rockfall")
    local msg = Opt.unknown(spec, KEYS, "calibrate.fit_apparent_rn")
    if msg then raise(msg) end
    local opts, mat = spec.analysis, spec.material
    if type(opts) ~= "table" or type(opts.materials) ~= "table" or type(opts.materials[mat]) ~= "table" then
        raise("calibrate.fit_apparent_rn: analysis must be rockfall.analysis's options with materials."
            .. tostring(mat))
    end
    if type(spec.target) ~= "number" or spec.target <= 0 then
        raise("calibrate.fit_apparent_rn: target must be a positive apparent Rn")
    end
    local prop = spec.prop or "dp_nratio"
    local n, trials = spec.n or 100, {}
    local function run(x)
        local o = Opt.merged(opts, {})
        o.materials = Opt.merged(opts.materials, {})
        local m = Opt.merged(opts.materials[mat], {})
        m.props = Opt.merged(m.props, { [prop] = x })
        o.materials[mat] = m
        local recs = rockfall.monte_carlo(rockfall.analysis(o), { n = n, quiet = true, stats = false,
            jobs = spec.jobs })
        local rn, count, lo, hi = C.apparent_rn(recs, mat, spec.shape, spec.statistic)
        -- No impact that ended: every rock that touched the material stayed on it, none
        -- rebounded, an apparent Rn of 0 as far as the fit is concerned.
        if count == 0 then rn, lo, hi = 0, 0, 0 end
        trials[#trials + 1] = { value = x, rn = rn, impacts = count, rn_lo = lo, rn_hi = hi }
        return rn - spec.target
    end
    local lo, hi = spec.lo or 0.01, spec.hi or 0.9
    local flo, fhi = run(lo), run(hi)
    local out = { trials = trials }
    local function result(t)
        out.value, out.rn, out.impacts, out.rn_lo, out.rn_hi = t.value, t.rn, t.impacts, t.rn_lo, t.rn_hi
        return out
    end
    if (flo > 0) == (fhi > 0) then
        out.note = string.format("out of reach: apparent Rn %.4g at %s = %g and %.4g at %g (target %g)",
            trials[1].rn, prop, lo, trials[2].rn, hi, spec.target)
        return result(math.abs(flo) < math.abs(fhi) and trials[1] or trials[2])
    end
    -- The statistic of a fixed set of rocks is a step function of the property (the rocks' paths
    -- change with it), so the root is only as sharp as tol; the bracket's evaluations are reused.
    local known = { [lo] = flo, [hi] = fhi }
    Optim.root(function(x) return known[x] or run(x) end, lo, hi,
        { ftol = spec.tol or 0.005, xtol = 1e-4 * (hi - lo), max_iter = spec.max_iter or 12 })
    local best = trials[1]
    for _, t in ipairs(trials) do
        if math.abs(t.rn - spec.target) < math.abs(best.rn - spec.target) then best = t end
    end
    return result(best)
end

return C
