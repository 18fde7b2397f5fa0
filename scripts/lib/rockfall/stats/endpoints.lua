-- SPDX-License-Identifier: MIT
-- rockfall/stats/endpoints.lua: where the rocks stopped: percentiles of the end point, histogram, reach
-- probability, stop rules.
local S = require("talus_util.stats")
local M = require("rockfall.stats.defaults")
local R = require("rockfall.stats.records")
local NaN, INF = 0 / 0, math.huge
local check_records, direction_of = R.check_records, R.direction_of
local envelope_of, x_far, nice_width = R.envelope_of, R.x_far, R.nice_width

--- End-point statistics. opts (all optional):
---   confidence   level of the intervals (default 0.95)
---   percentiles  probabilities of end_x (default M.PERCENTILES)
---   bins         histogram {x0 =, x1 =, dx =}; default opts.envelope, else automatic
---   envelope     the analysis envelope (default bins and reach grid)
---   reach_x      list of x for the reach probability; default the bin edges
---   direction    +1 / -1 downslope direction along x (default +1, or from opts.profile)
---   profile      the analysis profile (for the direction)
--- Returns { n, confidence, direction, end_x (record order), x_far, percentiles = {{p, name,
--- x, lo, hi, coverage}}, hist = {x0, dx, below, above, bins = {{k, x_lo, x_hi, count,
--- fraction, cumulative}}}, reach = {{x, count, reach, lo, hi}}, stops = {{rule, count,
--- fraction}} }.
function M.endpoints(records, opts)
    local where = "endpoints"
    opts = opts or {}
    check_records(records, where)
    local level = opts.confidence or M.CONFIDENCE
    local d = direction_of({ direction = opts.direction, profile = opts.profile }, where)
    local n = #records
    local res = { n = n, confidence = level, direction = d, end_x = {}, x_far = {} }

    -- Percentiles of the runout coordinate s = d x (so that p90 is the point 90 % of the rocks
    -- do not pass, whichever way the slope runs), mapped back to x.
    local s = {}
    for i, r in ipairs(records) do
        res.end_x[i] = r.end_x
        res.x_far[i] = x_far(r, d)
        s[i] = d * r.end_x
    end
    table.sort(s)
    res.percentiles = {}
    for i, p in ipairs(opts.percentiles or M.PERCENTILES) do
        local lo, hi, coverage = S.quantile_ci(s, p, level)
        local x = d * S.quantile(s, p)
        lo, hi = d * lo, d * hi
        if d < 0 then lo, hi = hi, lo end
        res.percentiles[i] = { p = p, name = S.qname(p), x = x, lo = lo, hi = hi,
            coverage = coverage }
    end

    -- Histogram bins along x.
    local x0, dx, K
    if opts.bins then
        x0, dx, K = envelope_of(opts.bins, where)
    elseif opts.envelope then
        x0, dx, K = envelope_of(opts.envelope, where)
    elseif n > 0 then
        local lo, hi = INF, -INF
        for _, r in ipairs(records) do
            lo, hi = math.min(lo, r.end_x), math.max(hi, r.end_x)
        end
        -- square-root rule for the number of bins, rounded to a nice width
        dx = nice_width((hi - lo) / math.ceil(math.sqrt(n)))
        x0 = math.floor(lo / dx) * dx
        K = math.max(1, math.floor((hi - x0) / dx) + 1)
    end
    local hist = { x0 = x0, dx = dx, below = 0, above = 0, bins = {} }
    if K then
        for k = 1, K do
            hist.bins[k] = { k = k, x_lo = x0 + (k - 1) * dx, x_hi = x0 + k * dx, count = 0 }
        end
        for _, r in ipairs(records) do
            local k = math.floor((r.end_x - x0) / dx) + 1
            if k < 1 then
                hist.below = hist.below + 1
            elseif k > K then
                hist.above = hist.above + 1
            else
                hist.bins[k].count = hist.bins[k].count + 1
            end
        end
        local cum = hist.below
        for k = 1, K do
            local b = hist.bins[k]
            cum = cum + b.count
            b.fraction = n > 0 and b.count / n or NaN
            b.cumulative = n > 0 and cum / n or NaN -- fraction with end_x < x_hi
        end
    end
    res.hist = hist

    -- Reach probability: fraction of the N rocks whose farthest downslope point is at or
    -- beyond x (d x_far >= d x).
    local grid = opts.reach_x
    if not grid then
        grid = {}
        if K then
            for k = 0, K do grid[#grid + 1] = x0 + k * dx end
        end
    end
    res.reach = {}
    for i, x in ipairs(grid) do
        local count = 0
        for _, xf in ipairs(res.x_far) do
            if d * xf >= d * x then count = count + 1 end
        end
        local lo, hi = S.wilson(count, n, level)
        res.reach[i] = { x = x, count = count, reach = n > 0 and count / n or NaN, lo = lo,
            hi = hi }
    end

    -- Stop-rule counts: the four rules always, other names in order of appearance.
    local counts, order = {}, {}
    for _, rule in ipairs(M.STOP_RULES) do
        counts[rule] = 0
        order[#order + 1] = rule
    end
    for _, r in ipairs(records) do
        local rule = r.stop ~= nil and tostring(r.stop) or "unknown"
        if counts[rule] == nil then
            counts[rule] = 0
            order[#order + 1] = rule
        end
        counts[rule] = counts[rule] + 1
    end
    res.stops = {}
    for i, rule in ipairs(order) do
        res.stops[i] = { rule = rule, count = counts[rule],
            fraction = n > 0 and counts[rule] / n or NaN }
    end
    res.stop_count = counts
    return res
end

return M
