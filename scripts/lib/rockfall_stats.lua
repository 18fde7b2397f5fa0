-- SPDX-License-Identifier: MIT
--
-- rockfall_stats: Monte Carlo statistics of a rockfall analysis, over the per-rock
-- records of scripts/lib/rockfall.lua (one plain table per rock: end point, stop rule,
-- collector crossings, barrier impacts, envelope maxima; docs/rockfall-statistics.md).
--
--   local stats = require("rockfall_stats")
--   local summary = stats.write(records, analysis, "out/rockfall")   -- CSV files, rank 0 only
--   stats.print_summary(summary)
--
-- Every definition, the quantile rule and the confidence-interval methods are in
-- docs/rockfall-statistics.md. In short:
--   * quantiles: Hyndman & Fan (1996) type 7 (linear interpolation between order statistics,
--     the default of R and numpy);
--   * confidence interval of a quantile: the distribution-free interval [x_(l), x_(u)] between
--     two order statistics, with the ranks taken from the binomial distribution of the number
--     of observations below the quantile, each tail at most (1 - level)/2 (Hahn & Meeker 1991,
--     section 5.2; Conover 1999, section 3.2). Where the sample is too small for a side, that
--     side is NaN (there is no order statistic that bounds the quantile at the asked level);
--   * confidence interval of a probability (reach, fraction stopped): Wilson's score interval
--     (Wilson 1927; recommended by Brown, Cai & DasGupta 2001).
-- NaN marks "not defined" everywhere (no rock in the bin, interval side out of reach); the CSV
-- files write it as `nan`.

local M = {}

local NaN = 0 / 0
local INF = math.huge

--- Defaults (documented in docs/rockfall-statistics.md).
M.CONFIDENCE = 0.95
M.PERCENTILES = { 0.5, 0.9, 0.95, 0.98, 0.99 } -- of the end point
M.QUANTILES = { 0.5, 0.9, 0.95, 0.98 } -- of envelopes, collectors and barriers (RAMMS + 98 %)
M.ANGLE_PERCENTILES = { 0.01, 0.02, 0.05, 0.1, 0.5 } -- low angles are the far-reaching rocks
M.STOP_RULES = { "rest", "left", "time", "barrier" }
M.SHADOW_STEEP_DEG = 45 -- a profile segment at least this steep is "cliff" for the apex rule
M.COLLECTOR_QUANTITIES = { "height", "ke_trans", "ke_rot", "ke", "v", "spin" }
M.BARRIER_QUANTITIES = { "energy", "height", "angle" }

-- ------------------------------------------------------------------ small helpers

local function isnum(v) return type(v) == "number" and v == v end

--- Raises "rockfall_stats.<where>: <message>" at the first caller outside this module, so the
--- position names the user's script line.
local function fail(where, fmt, ...)
    local level, here = 2, debug.getinfo(1, "S").source
    while true do
        local info = debug.getinfo(level, "S")
        if not info or info.source ~= here then break end
        level = level + 1
    end
    error("rockfall_stats." .. where .. ": " .. string.format(fmt, ...), level)
end

--- The numbers of a list, NaN and non-numbers dropped, sorted ascending (a new table).
local function sorted_numbers(list)
    local s = {}
    for _, v in ipairs(list) do
        if isnum(v) then s[#s + 1] = v end
    end
    table.sort(s)
    return s
end

--- Column / field name of a probability: 0.5 -> "median", 0.95 -> "q95", 0.995 -> "q99.5",
--- 0.01 -> "q01" (two digits, so that names sort as the probabilities do).
function M.qname(p)
    if p == 0.5 then return "median" end
    local pct = p * 100
    local r = math.floor(pct + 0.5)
    if math.abs(pct - r) < 1e-9 then return string.format("q%02d", r) end
    return "q" .. string.format("%g", pct)
end

--- Quantile of a SORTED list, Hyndman & Fan type 7: h = (n - 1) p + 1, linear interpolation
--- between x_(floor h) and x_(floor h + 1). NaN for an empty list.
function M.quantile(sorted, p)
    local n = #sorted
    if n == 0 then return NaN end
    local h = (n - 1) * p + 1
    local j = math.floor(h)
    if j >= n then return sorted[n] end
    if j < 1 then return sorted[1] end
    return sorted[j] + (h - j) * (sorted[j + 1] - sorted[j])
end

-- Cache of order-statistic ranks: they depend on n, p and the level only.
local rank_cache = {}

--- Ranks (l, u) of the distribution-free confidence interval [x_(l), x_(u)] of the p-quantile
--- from n observations, and its coverage. B ~ Binomial(n, p) counts the observations below the
--- quantile, F its CDF. P(x_(l) > xi_p) = F(l - 1) and P(x_(u) < xi_p) = 1 - F(u - 1), so l is
--- the largest rank with F(l - 1) <= alpha/2 and u the smallest with F(u - 1) >= 1 - alpha/2
--- (alpha = 1 - level). l = nil when F(0) > alpha/2 (too few observations for a lower bound),
--- u = nil when F(n - 1) < 1 - alpha/2. coverage = F(u - 1) - F(l - 1) (a missing side counts
--- as an infinite bound: F = 0 below, 1 above), >= level when both ranks exist.
function M.quantile_ci_ranks(n, p, level)
    level = level or M.CONFIDENCE
    local key = n .. ":" .. p .. ":" .. level
    local c = rank_cache[key]
    if c then return c[1], c[2], c[3] end
    local half = (1 - level) / 2
    local l, u, Fl, Fu = nil, nil, 0, 1
    if n >= 1 and p > 0 and p < 1 then
        -- pmf(k) from its logarithm (no underflow of (1 - p)^n for large n), summed in order.
        local logpmf = n * math.log(1 - p)
        local logratio = math.log(p / (1 - p))
        local F = 0
        for k = 0, n - 1 do
            F = F + math.exp(logpmf)
            if F <= half then l, Fl = k + 1, F end
            if not u and F >= 1 - half then
                u, Fu = k + 1, F
                break
            end
            logpmf = logpmf + math.log((n - k) / (k + 1)) + logratio
        end
    end
    local coverage = n >= 1 and (Fu - Fl) or NaN
    rank_cache[key] = { l, u, coverage }
    return l, u, coverage
end

--- Confidence interval of the p-quantile of a SORTED list: lo, hi (NaN where not available),
--- and the coverage of the interval.
function M.quantile_ci(sorted, p, level)
    local l, u, coverage = M.quantile_ci_ranks(#sorted, p, level)
    return l and sorted[l] or NaN, u and sorted[u] or NaN, coverage
end

--- Standard normal quantile (Acklam's rational approximation, relative error < 1.2e-9, far
--- below any statistical error here). Used for Wilson's interval.
function M.normal_quantile(q)
    if q <= 0 then return -INF end
    if q >= 1 then return INF end
    local a = { -3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
        1.383577518672690e+02, -3.066479806614716e+01, 2.506628277459239e+00 }
    local b = { -5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
        6.680131188771972e+01, -1.328068155288572e+01 }
    local c = { -7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
        -2.549732539343734e+00, 4.374664141464968e+00, 2.938163982698783e+00 }
    local d = { 7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
        3.754408661907416e+00 }
    local lowq = 0.02425
    if q < lowq or q > 1 - lowq then
        local t = math.sqrt(-2 * math.log(q < lowq and q or 1 - q))
        local x = (((((c[1] * t + c[2]) * t + c[3]) * t + c[4]) * t + c[5]) * t + c[6]) /
            ((((d[1] * t + d[2]) * t + d[3]) * t + d[4]) * t + 1)
        return q < lowq and x or -x
    end
    local t = q - 0.5
    local r = t * t
    return (((((a[1] * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * r + a[6]) * t /
        (((((b[1] * r + b[2]) * r + b[3]) * r + b[4]) * r + b[5]) * r + 1)
end

--- Wilson score interval of a probability from k successes in n trials:
--- (k/n + z^2/2n -+ z sqrt(k/n (1 - k/n)/n + z^2/4n^2)) / (1 + z^2/n), z the (1+level)/2
--- normal quantile. NaN, NaN for n = 0.
function M.wilson(k, n, level)
    if n == 0 then return NaN, NaN end
    local z = M.normal_quantile((1 + (level or M.CONFIDENCE)) / 2)
    local ph = k / n
    local z2 = z * z
    local centre = (ph + z2 / (2 * n)) / (1 + z2 / n)
    local halfw = z / (1 + z2 / n) * math.sqrt(ph * (1 - ph) / n + z2 / (4 * n * n))
    return math.max(0, centre - halfw), math.min(1, centre + halfw)
end

--- Summary of a list of values: n, mean, min, max, and for each probability p of `probs` the
--- type-7 quantile with its order-statistic interval, as fields qname(p), qname(p).."_lo",
--- qname(p).."_hi" (and the list `q` = { {p=, value=, lo=, hi=, coverage=}, ... }).
--- NaN values and non-numbers are ignored; an empty list gives n = 0 and NaN everywhere.
function M.describe(values, probs, level)
    probs = probs or M.QUANTILES
    local s = sorted_numbers(values)
    local n = #s
    local d = { n = n, mean = NaN, min = NaN, max = NaN, q = {} }
    if n > 0 then
        local sum = 0
        for i = 1, n do sum = sum + s[i] end
        d.mean, d.min, d.max = sum / n, s[1], s[n]
    end
    for i, p in ipairs(probs) do
        local value = M.quantile(s, p)
        local lo, hi, coverage = M.quantile_ci(s, p, level)
        local name = M.qname(p)
        d[name], d[name .. "_lo"], d[name .. "_hi"] = value, lo, hi
        d.q[i] = { p = p, name = name, value = value, lo = lo, hi = hi, coverage = coverage }
    end
    return d
end

-- ------------------------------------------------------------------ records and analysis

local function point_xy(pt)
    if type(pt) ~= "table" then return nil end
    return pt.x or pt[1], pt.y or pt[2]
end

--- The profile as a list of {x, y} in the order given, or nil.
local function profile_points(analysis, where)
    local prof = analysis and analysis.profile
    if prof == nil then return nil end
    if type(prof) ~= "table" then fail(where, "analysis.profile must be a list of {x, y}") end
    local pts = {}
    for i, pt in ipairs(prof) do
        local x, y = point_xy(pt)
        if not (isnum(x) and isnum(y)) then
            fail(where, "analysis.profile[%d] must be {x, y} numbers", i)
        end
        pts[i] = { x, y }
    end
    if #pts < 2 then fail(where, "analysis.profile needs at least 2 points (got %d)", #pts) end
    return pts
end

--- Downslope direction along x: analysis.direction (+1 or -1), else +1 when the profile's
--- first point is higher than its last, -1 when lower, else +1.
local function direction_of(analysis, where)
    local d = analysis and analysis.direction
    if d ~= nil then
        if d ~= 1 and d ~= -1 then
            fail(where, "analysis.direction must be 1 or -1 (got %s)", tostring(d))
        end
        return d
    end
    local pts = profile_points(analysis, where)
    if pts and pts[#pts][2] > pts[1][2] then return -1 end
    return 1
end

--- Surface height of the profile at x (linear between points; the first segment found that
--- spans x; NaN outside the profile).
local function profile_y(pts, x)
    for i = 1, #pts - 1 do
        local x1, y1, x2, y2 = pts[i][1], pts[i][2], pts[i + 1][1], pts[i + 1][2]
        if (x >= x1 and x <= x2) or (x >= x2 and x <= x1) then
            if x1 == x2 then return math.min(y1, y2) end
            return y1 + (x - x1) / (x2 - x1) * (y2 - y1)
        end
    end
    return NaN
end

local function check_records(records, where)
    if type(records) ~= "table" then
        fail(where, "records must be a list of per-rock tables (got %s)", type(records))
    end
    for i, r in ipairs(records) do
        if type(r) ~= "table" then fail(where, "record %d is a %s, not a table", i, type(r)) end
        if not isnum(r.end_x) then
            fail(where, "record %d (rock %s): end_x must be a number (got %s)", i,
                tostring(r.rock or i), tostring(r.end_x))
        end
    end
end

--- The envelope description {x0, x1, dx} (named or positional) -> x0, dx, number of bins K.
local function envelope_of(env, where)
    if type(env) ~= "table" then return nil end
    local x0, x1, dx = env.x0 or env[1], env.x1 or env[2], env.dx or env[3]
    if not (isnum(x0) and isnum(x1) and isnum(dx)) or dx <= 0 or x1 <= x0 then
        fail(where, "envelope must be {x0 =, x1 =, dx =} with x1 > x0 and dx > 0 (got %s, %s, %s)",
            tostring(x0), tostring(x1), tostring(dx))
    end
    -- K bins [x0 + (k-1) dx, x0 + k dx); the tolerance keeps (x1 - x0)/dx = 10.000000001 at 10.
    local K = math.ceil((x1 - x0) / dx - 1e-9)
    return x0, dx, K
end

--- Farthest downslope x of a rock: the extreme (along the direction d) of end_x and of the x of
--- every recorded impact, collector crossing and trajectory point. Barrier impacts are left
--- out: a rock stopped by a barrier touched its line but did not pass it.
local function x_far(r, d)
    local best = r.end_x
    local function see(x)
        if isnum(x) and d * x > d * best then best = x end
    end
    for _, e in ipairs(r.impacts or {}) do see(e.x) end
    for _, e in ipairs(r.crossings or {}) do see(e.x) end
    for _, e in ipairs(r.path or {}) do see(e.x or e[2]) end
    return best
end

--- A "nice" bin width near `w`: 1, 2 or 5 times a power of ten.
local function nice_width(w)
    if not (w > 0) then return 1 end
    local e = 10 ^ math.floor(math.log(w, 10))
    for _, m in ipairs({ 1, 2, 5, 10 }) do
        if m * e >= w * (1 - 1e-12) then return m * e end
    end
    return 10 * e
end

-- ------------------------------------------------------------------ end points

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
        local lo, hi, coverage = M.quantile_ci(s, p, level)
        local x = d * M.quantile(s, p)
        lo, hi = d * lo, d * hi
        if d < 0 then lo, hi = hi, lo end
        res.percentiles[i] = { p = p, name = M.qname(p), x = x, lo = lo, hi = hi,
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
        local lo, hi = M.wilson(count, n, level)
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

-- ------------------------------------------------------------------ envelopes

--- Value of a sparse per-bin table (integer keys; string keys accepted, should a transport
--- turn them into strings).
local function bin_value(t, k)
    if type(t) ~= "table" then return nil end
    local v = t[k]
    if v == nil then v = t[tostring(k)] end
    return v
end

--- Envelopes along x (analysis.envelope = {x0, x1, dx}): per bin k, over the rocks that have
--- an entry env_height[k] or env_ke[k] (the rocks that reached the bin), the count and
--- describe() of the bounce heights and of the total kinetic energies. opts: confidence,
--- quantiles (default M.QUANTILES). Returns { confidence, n = N, bins = {{k, x_lo, x_hi, x_mid,
--- n, reach, height = describe, ke = describe}} }.
function M.envelopes(records, analysis, opts)
    local where = "envelopes"
    opts = opts or {}
    check_records(records, where)
    if not (analysis and analysis.envelope) then
        fail(where, "analysis.envelope = {x0 =, x1 =, dx =} is required")
    end
    local x0, dx, K = envelope_of(analysis.envelope, where)
    local level = opts.confidence or analysis.confidence or M.CONFIDENCE
    local probs = opts.quantiles or M.QUANTILES
    local N = #records
    local res = { confidence = level, n = N, bins = {} }
    for k = 1, K do
        local h, e, n = {}, {}, 0
        for _, r in ipairs(records) do
            local vh, ve = bin_value(r.env_height, k), bin_value(r.env_ke, k)
            if vh ~= nil or ve ~= nil then n = n + 1 end
            if isnum(vh) then h[#h + 1] = vh end
            if isnum(ve) then e[#e + 1] = ve end
        end
        local xl = x0 + (k - 1) * dx
        res.bins[k] = { k = k, x_lo = xl, x_hi = xl + dx, x_mid = xl + dx / 2, n = n,
            reach = N > 0 and n / N or NaN, height = M.describe(h, probs, level),
            ke = M.describe(e, probs, level) }
    end
    return res
end

-- ------------------------------------------------------------------ collectors and barriers

--- Names in the analysis order, then names seen only in the records (order of appearance).
local function names_of(list, records, field, key)
    local names, xs, seen = {}, {}, {}
    for _, c in ipairs(list or {}) do
        if c.name ~= nil and not seen[c.name] then
            names[#names + 1] = c.name
            xs[c.name] = c.x
            seen[c.name] = true
        end
    end
    for _, r in ipairs(records) do
        for _, e in ipairs(r[field] or {}) do
            local name = e[key]
            if name ~= nil and not seen[name] then
                names[#names + 1] = name
                seen[name] = true
            end
        end
    end
    return names, xs
end

--- The first event (smallest t, else first listed) of each rock with e[key] == name.
local function first_events(records, field, key, name)
    local events, firsts = 0, {}
    for _, r in ipairs(records) do
        local first
        for _, e in ipairs(r[field] or {}) do
            if e[key] == name then
                events = events + 1
                if not first or (isnum(e.t) and isnum(first.t) and e.t < first.t) then first = e end
            end
        end
        if first then firsts[#firsts + 1] = { rec = r, e = first } end
    end
    return events, firsts
end

--- Per collector (analysis.collectors, plus lines met only in the records): crossings (all
--- events), rocks (distinct rocks), fraction = rocks / N, and describe() of height, ke_trans,
--- ke_rot, ke, v and spin (|spin|, rad/s) over each rock's FIRST crossing of the line.
function M.collectors(records, analysis, opts)
    local where = "collectors"
    opts = opts or {}
    check_records(records, where)
    local level = opts.confidence or (analysis and analysis.confidence) or M.CONFIDENCE
    local probs = opts.quantiles or M.QUANTILES
    local N = #records
    local names, xs = names_of(analysis and analysis.collectors, records, "crossings", "line")
    local res = {}
    for i, name in ipairs(names) do
        local events, firsts = first_events(records, "crossings", "line", name)
        local c = { name = name, x = xs[name] or NaN, crossings = events, rocks = #firsts,
            fraction = N > 0 and #firsts / N or NaN, stats = {} }
        c.lo, c.hi = M.wilson(#firsts, N, level)
        for _, q in ipairs(M.COLLECTOR_QUANTITIES) do
            local vals = {}
            for _, f in ipairs(firsts) do
                local v = f.e[q]
                if q == "spin" and isnum(v) then v = math.abs(v) end
                vals[#vals + 1] = v
            end
            c.stats[q] = M.describe(vals, probs, level)
        end
        res[i] = c
    end
    return res
end

--- Per barrier (analysis.barriers, plus names met only in the records): rocks = distinct rocks
--- with an impact, stopped = rocks with an impact flagged stopped, passed = rocks - stopped,
--- not_reached = N - rocks, impacts = all events, and describe() of energy, height and angle
--- over each rock's FIRST impact on the barrier.
function M.barriers(records, analysis, opts)
    local where = "barriers"
    opts = opts or {}
    check_records(records, where)
    local level = opts.confidence or (analysis and analysis.confidence) or M.CONFIDENCE
    local probs = opts.quantiles or M.QUANTILES
    local N = #records
    local names, xs = names_of(analysis and analysis.barriers, records, "barrier", "name")
    local res = {}
    for i, name in ipairs(names) do
        local events, firsts = first_events(records, "barrier", "name", name)
        local stopped = 0
        for _, f in ipairs(firsts) do
            for _, e in ipairs(f.rec.barrier) do
                if e.name == name and e.stopped then
                    stopped = stopped + 1
                    break
                end
            end
        end
        local b = { name = name, x = xs[name] or NaN, impacts = events, rocks = #firsts,
            stopped = stopped, passed = #firsts - stopped, not_reached = N - #firsts,
            fraction_stopped = N > 0 and stopped / N or NaN,
            fraction_passed = N > 0 and (#firsts - stopped) / N or NaN, stats = {} }
        for _, q in ipairs(M.BARRIER_QUANTITIES) do
            local vals = {}
            for _, f in ipairs(firsts) do vals[#vals + 1] = f.e[q] end
            b.stats[q] = M.describe(vals, probs, level)
        end
        res[i] = b
    end
    return res
end

-- ------------------------------------------------------------------ angles

--- The profile's points in the order a rock travelling along d meets them.
local function travel_order(pts, d)
    if d * (pts[#pts][1] - pts[1][1]) >= 0 then return pts end
    local r = {}
    for i = #pts, 1, -1 do r[#r + 1] = pts[i] end
    return r
end

--- The shadow-angle apex: analysis.shadow_apex ({x, y} or {x =, y =}) when given; else the
--- lower end (the toe) of the last DOWNSLOPE segment, in the direction of travel, whose
--- inclination is at least analysis.shadow_steep degrees (default M.SHADOW_STEEP_DEG). A
--- segment that rises in the direction of travel (the far wall of a ditch, the face of a
--- berm) is never a cliff the rocks fell from, so it never defines the apex. nil when neither.
function M.shadow_apex(analysis)
    local where = "shadow_apex"
    if analysis and analysis.shadow_apex ~= nil then
        local x, y = point_xy(analysis.shadow_apex)
        if not (isnum(x) and isnum(y)) then fail(where, "analysis.shadow_apex must be {x, y}") end
        return { x = x, y = y, rule = "given" }
    end
    local pts = profile_points(analysis, where)
    if not pts then return nil end
    local d = direction_of(analysis, where)
    local steep = analysis.shadow_steep or M.SHADOW_STEEP_DEG
    if not (isnum(steep) and steep > 0 and steep <= 90) then
        fail(where, "analysis.shadow_steep must be an angle in (0, 90] degrees (got %s)",
            tostring(steep))
    end
    local apex
    local path = travel_order(pts, d)
    for i = 1, #path - 1 do
        local a, b = path[i], path[i + 1]
        local drop = a[2] - b[2] -- > 0: the segment goes down in the direction of travel
        if drop > 0 and math.deg(math.atan(drop, math.abs(b[1] - a[1]))) >= steep then
            apex = { x = b[1], y = b[2],
                rule = string.format("toe of the last downslope segment of %g deg or steeper",
                    steep) }
        end
    end
    return apex
end

--- Energy-line and shadow angles (degrees) of the deposited rocks. A rock is deposited when
--- its stop rule is in opts.deposited (default { rest = true }).
---   energy line: atan2(y_rel - y_end, d (x_end - x_rel)), from the rock's own release point
---                (record.release, else analysis.release) to its end point (both as recorded:
---                the rock's centre);
---   shadow:      atan2(y_apex - y_ground, d (x_end - x_apex)) for rocks beyond the apex
---                (d (x_end - x_apex) > 0), y_ground = profile height at x_end (else
---                end_y - r_eq): the apex is a point of the ground, so is the end point.
--- Returns { per_rock = {{rock, energy_line, shadow}} (record order; NaN when not deposited),
--- apex, deposited, beyond_apex, energy_line = describe, shadow = describe }, with the
--- describe() probabilities opts.percentiles or M.ANGLE_PERCENTILES.
function M.angles(records, analysis, opts)
    local where = "angles"
    opts = opts or {}
    analysis = analysis or {}
    check_records(records, where)
    local level = opts.confidence or analysis.confidence or M.CONFIDENCE
    local probs = opts.percentiles or M.ANGLE_PERCENTILES
    local dep = opts.deposited or { rest = true }
    local d = direction_of(analysis, where)
    local pts = profile_points(analysis, where)
    local apex = M.shadow_apex(analysis)
    local res = { per_rock = {}, apex = apex, deposited = 0, beyond_apex = 0 }
    local el, sh = {}, {}
    for i, r in ipairs(records) do
        local row = { rock = r.rock or i, energy_line = NaN, shadow = NaN }
        if dep[r.stop] then
            res.deposited = res.deposited + 1
            local xr, yr = point_xy(r.release)
            if not (isnum(xr) and isnum(yr)) then xr, yr = point_xy(analysis.release) end
            if not (isnum(xr) and isnum(yr)) then
                fail(where, "record %d (rock %s): no release point (record.release or "
                    .. "analysis.release)", i, tostring(r.rock or i))
            end
            local yend = r.end_y
            if not isnum(yend) then
                fail(where, "record %d (rock %s): end_y must be a number (got %s)", i,
                    tostring(r.rock or i), tostring(yend))
            end
            row.energy_line = math.deg(math.atan(yr - yend, d * (r.end_x - xr)))
            el[#el + 1] = row.energy_line
            if apex and d * (r.end_x - apex.x) > 0 then
                local yg = pts and profile_y(pts, r.end_x) or NaN
                if not isnum(yg) then yg = yend - (isnum(r.r_eq) and r.r_eq or 0) end
                row.shadow = math.deg(math.atan(apex.y - yg, d * (r.end_x - apex.x)))
                sh[#sh + 1] = row.shadow
                res.beyond_apex = res.beyond_apex + 1
            end
        end
        res.per_rock[i] = row
    end
    res.energy_line = M.describe(el, probs, level)
    res.shadow = M.describe(sh, probs, level)
    -- An apex at or below the ground the rocks come to rest on (a cliff straight onto a flat
    -- floor, a ditch at the toe of a slope with no cliff above it) makes the shadow angles
    -- there 0 or negative, which says nothing: say so, with the way out.
    if apex then
        local why
        if pts then
            local path = travel_order(pts, d)
            local lowest, runout = INF, path[#path][2]
            for _, pt in ipairs(pts) do lowest = math.min(lowest, pt[2]) end
            if apex.y <= runout then
                why = string.format("at or below the run-out (the profile ends at y = %.4g)",
                    runout)
            elseif apex.y <= lowest then
                why = "at the bottom of the profile"
            end
        end
        if not why and res.shadow.n > 0 and res.shadow.min <= 0 then
            why = "not above where some rocks stopped"
        end
        if why then
            res.note = string.format("the shadow-angle apex (%.4g, %.4g) is %s: shadow angles "
                .. "there are 0 or negative and say nothing; give shadow_apex = {x, y} (the "
                .. "top of the talus below the cliff the rocks fell from), or rely on the "
                .. "energy-line angle", apex.x, apex.y, why)
        end
    end
    return res
end

-- ------------------------------------------------------------------ CSV output

local function cell(v)
    local t = type(v)
    if t == "number" then
        if v ~= v then return "nan" end
        if v == INF then return "inf" end
        if v == -INF then return "-inf" end
        if math.type(v) == "integer" then return string.format("%d", v) end
        return string.format("%.12g", v)
    elseif t == "nil" then
        return ""
    elseif t == "boolean" then
        return v and "true" or "false"
    end
    local s = tostring(v)
    if s:find('[,"\r\n]') then s = '"' .. s:gsub('"', '""') .. '"' end
    return s
end

local function write_csv(path, header, rows)
    local f, err = io.open(path, "w")
    if not f then
        error("rockfall_stats.write: cannot write " .. path .. ": " .. tostring(err), 3)
    end
    local line = {}
    for i, h in ipairs(header) do line[i] = cell(h) end
    f:write(table.concat(line, ","), "\n")
    for _, row in ipairs(rows) do
        line = {}
        for i = 1, #header do line[i] = cell(row[i]) end
        f:write(table.concat(line, ","), "\n")
    end
    f:close()
end

--- Column names and values of a describe() result, prefixed ("height_mean", ...).
local function describe_header(prefix, probs)
    local h = { prefix .. "n", prefix .. "mean", prefix .. "min", prefix .. "max" }
    for _, p in ipairs(probs) do
        local q = M.qname(p)
        h[#h + 1] = prefix .. q
        h[#h + 1] = prefix .. q .. "_lo"
        h[#h + 1] = prefix .. q .. "_hi"
    end
    return h
end
local function describe_cells(row, d)
    row[#row + 1] = d.n
    row[#row + 1] = d.mean
    row[#row + 1] = d.min
    row[#row + 1] = d.max
    for _, q in ipairs(d.q) do
        row[#row + 1] = q.value
        row[#row + 1] = q.lo
        row[#row + 1] = q.hi
    end
end

local function is_rank0()
    local t = rawget(_G, "talus")
    return ((t and t.rank and t.rank()) or 0) == 0
end

--- Computes everything, writes the CSV files into outdir (created if missing) on MPI rank 0
--- only, and returns the summary table (on every rank). opts: confidence, and
--- trajectories = false to skip trajectories.csv (written when records carry `path`).
--- Files (columns in docs/rockfall-statistics.md): endpoints.csv, endpoint_hist.csv,
--- endpoint_percentiles.csv, stops.csv, reach.csv, envelopes.csv (when analysis.envelope),
--- collectors.csv, barriers.csv, angles.csv, summary.csv, profile.csv (when
--- analysis.profile), trajectories.csv (when paths).
function M.write(records, analysis, outdir, opts)
    analysis = analysis or {}
    opts = opts or {}
    local level = opts.confidence or analysis.confidence or M.CONFIDENCE
    local d = direction_of(analysis, "write")
    local ep = M.endpoints(records, { confidence = level, envelope = analysis.envelope,
        direction = d, bins = opts.bins })
    local env = analysis.envelope and M.envelopes(records, analysis, { confidence = level }) or nil
    local col = M.collectors(records, analysis, { confidence = level })
    local bar = M.barriers(records, analysis, { confidence = level })
    local ang = M.angles(records, analysis, { confidence = level, deposited = opts.deposited })

    local summary = { n = #records, confidence = level, direction = d, stops = ep.stop_count,
        percentiles = ep.percentiles, energy_line = ang.energy_line, shadow = ang.shadow,
        apex = ang.apex, shadow_note = ang.note, deposited = ang.deposited,
        beyond_apex = ang.beyond_apex,
        collectors = col, barriers = bar, outdir = outdir, files = {} }

    -- summary rows: section, name, value, ci_lo, ci_hi
    local srows = { { "rocks", "n", #records } }
    for _, s in ipairs(ep.stops) do srows[#srows + 1] = { "stop", s.rule, s.count } end
    for _, p in ipairs(ep.percentiles) do
        srows[#srows + 1] = { "end_x", p.name, p.x, p.lo, p.hi }
    end
    for _, kind in ipairs({ "energy_line", "shadow" }) do
        local a = ang[kind]
        srows[#srows + 1] = { kind .. "_deg", "n", a.n }
        srows[#srows + 1] = { kind .. "_deg", "min", a.min }
        for _, q in ipairs(a.q) do
            srows[#srows + 1] = { kind .. "_deg", q.name, q.value, q.lo, q.hi }
        end
    end
    for _, c in ipairs(col) do
        srows[#srows + 1] = { "collector:" .. tostring(c.name), "fraction", c.fraction, c.lo, c.hi }
        for _, q in ipairs({ "ke", "height" }) do
            local st = c.stats[q]
            srows[#srows + 1] = { "collector:" .. tostring(c.name), q .. "_q95", st.q95, st.q95_lo,
                st.q95_hi }
            srows[#srows + 1] = { "collector:" .. tostring(c.name), q .. "_max", st.max }
        end
    end
    for _, b in ipairs(bar) do
        srows[#srows + 1] = { "barrier:" .. tostring(b.name), "stopped", b.stopped }
        srows[#srows + 1] = { "barrier:" .. tostring(b.name), "passed", b.passed }
        srows[#srows + 1] = { "barrier:" .. tostring(b.name), "energy_q95", b.stats.energy.q95,
            b.stats.energy.q95_lo, b.stats.energy.q95_hi }
        srows[#srows + 1] = { "barrier:" .. tostring(b.name), "energy_max", b.stats.energy.max }
    end
    summary.rows = srows

    if not is_rank0() then return summary end
    local t = rawget(_G, "talus")
    if t and t.mkdir then
        t.mkdir(outdir)
    else
        os.execute('mkdir -p "' .. tostring(outdir):gsub('"', '\\"') .. '"')
    end
    local function out(name, header, rows)
        local path = outdir .. "/" .. name
        write_csv(path, header, rows)
        summary.files[#summary.files + 1] = path
    end

    local rows = {}
    for i, r in ipairs(records) do
        local rx, ry = point_xy(r.release)
        rows[i] = { r.rock or i, r.seed, r.shape, r.mass, r.stop, rx, ry, r.end_x, r.end_y, r.t_end,
            ep.x_far[i], ang.per_rock[i].energy_line, ang.per_rock[i].shadow }
    end
    out("endpoints.csv", { "rock", "seed", "shape", "mass", "stop", "release_x", "release_y",
        "end_x", "end_y", "t_end", "x_far", "energy_line_deg", "shadow_deg" }, rows)

    rows = {}
    for i, b in ipairs(ep.hist.bins) do
        rows[i] = { b.k, b.x_lo, b.x_hi, b.count, b.fraction, b.cumulative }
    end
    out("endpoint_hist.csv", { "bin", "x_lo", "x_hi", "count", "fraction", "cumulative" }, rows)

    rows = {}
    for i, p in ipairs(ep.percentiles) do rows[i] = { p.p, p.x, p.lo, p.hi, p.coverage } end
    out("endpoint_percentiles.csv", { "p", "end_x", "ci_lo", "ci_hi", "coverage" }, rows)

    rows = {}
    for i, s in ipairs(ep.stops) do rows[i] = { s.rule, s.count, s.fraction } end
    out("stops.csv", { "stop", "count", "fraction" }, rows)

    rows = {}
    for i, r in ipairs(ep.reach) do rows[i] = { r.x, r.count, r.reach, r.lo, r.hi } end
    out("reach.csv", { "x", "count", "reach", "ci_lo", "ci_hi" }, rows)

    if env then
        local header = { "bin", "x_lo", "x_hi", "x_mid", "n", "reach" }
        for _, h in ipairs(describe_header("height_", M.QUANTILES)) do header[#header + 1] = h end
        for _, h in ipairs(describe_header("ke_", M.QUANTILES)) do header[#header + 1] = h end
        rows = {}
        for i, b in ipairs(env.bins) do
            local row = { b.k, b.x_lo, b.x_hi, b.x_mid, b.n, b.reach }
            describe_cells(row, b.height)
            describe_cells(row, b.ke)
            rows[i] = row
        end
        out("envelopes.csv", header, rows)
    end

    local header = { "collector", "x", "crossings", "rocks", "fraction", "fraction_lo",
        "fraction_hi", "quantity" }
    for _, h in ipairs(describe_header("", M.QUANTILES)) do header[#header + 1] = h end
    rows = {}
    for _, c in ipairs(col) do
        for _, q in ipairs(M.COLLECTOR_QUANTITIES) do
            local row = { c.name, c.x, c.crossings, c.rocks, c.fraction, c.lo, c.hi, q }
            describe_cells(row, c.stats[q])
            rows[#rows + 1] = row
        end
    end
    out("collectors.csv", header, rows)

    header = { "barrier", "x", "impacts", "rocks", "stopped", "passed", "not_reached",
        "fraction_stopped", "fraction_passed", "quantity" }
    for _, h in ipairs(describe_header("", M.QUANTILES)) do header[#header + 1] = h end
    rows = {}
    for _, b in ipairs(bar) do
        for _, q in ipairs(M.BARRIER_QUANTITIES) do
            local row = { b.name, b.x, b.impacts, b.rocks, b.stopped, b.passed, b.not_reached,
                b.fraction_stopped, b.fraction_passed, q }
            describe_cells(row, b.stats[q])
            rows[#rows + 1] = row
        end
    end
    out("barriers.csv", header, rows)

    header = { "angle", "apex_x", "apex_y", "deposited" }
    for _, h in ipairs(describe_header("", M.ANGLE_PERCENTILES)) do header[#header + 1] = h end
    rows = {}
    for _, kind in ipairs({ "energy_line", "shadow" }) do
        local row = { kind, kind == "shadow" and ang.apex and ang.apex.x or NaN,
            kind == "shadow" and ang.apex and ang.apex.y or NaN, ang.deposited }
        describe_cells(row, ang[kind])
        rows[#rows + 1] = row
    end
    out("angles.csv", header, rows)

    out("summary.csv", { "section", "name", "value", "ci_lo", "ci_hi" }, srows)

    local pts = profile_points(analysis, "write")
    if pts then
        rows = {}
        for i, p in ipairs(pts) do rows[i] = { p[1], p[2] } end
        out("profile.csv", { "x", "y" }, rows)
    end

    if opts.trajectories ~= false then
        rows = {}
        for i, r in ipairs(records) do
            for _, p in ipairs(r.path or {}) do
                rows[#rows + 1] = { r.rock or i, p.t or p[1], p.x or p[2], p.y or p[3] }
            end
        end
        if #rows > 0 then out("trajectories.csv", { "rock", "t", "x", "y" }, rows) end
    end
    return summary
end

-- ------------------------------------------------------------------ printed summary

local function g(x) return x ~= x and "-" or string.format("%.4g", x) end
local function fmt_ci(v, lo, hi)
    return string.format("%s [%s, %s]", g(v), g(lo), g(hi))
end

--- Prints the summary returned by write() (readable lines; the same numbers as summary.csv).
function M.print_summary(summary, print_fn)
    local p = print_fn or print
    local s = summary
    p(string.format("rockfall statistics: %d rocks, intervals at %g %% confidence", s.n,
        100 * s.confidence))
    local st = {}
    for _, rule in ipairs(M.STOP_RULES) do st[#st + 1] = rule .. " " .. (s.stops[rule] or 0) end
    for rule, c in pairs(s.stops) do
        local known = false
        for _, r in ipairs(M.STOP_RULES) do known = known or r == rule end
        if not known then st[#st + 1] = rule .. " " .. c end
    end
    p("  stopped by: " .. table.concat(st, ", "))
    local pc = {}
    for _, q in ipairs(s.percentiles) do pc[#pc + 1] = q.name .. " " .. fmt_ci(q.x, q.lo, q.hi) end
    p("  end point x: " .. table.concat(pc, "; "))
    for _, kind in ipairs({ "energy_line", "shadow" }) do
        local a = s[kind]
        local parts = { string.format("%d rocks, min %s", a.n, g(a.min)) }
        for _, q in ipairs(a.q) do
            parts[#parts + 1] = q.name .. " " .. fmt_ci(q.value, q.lo, q.hi)
        end
        local extra = ""
        if kind == "shadow" then
            extra = s.apex
                and string.format(" (apex %.4g, %.4g: %s)", s.apex.x, s.apex.y, s.apex.rule)
                or " (no apex: no steep downslope segment and no shadow_apex given)"
        end
        p(string.format("  %s angle [deg]%s: %s", kind == "shadow" and "shadow" or "energy-line",
            extra, table.concat(parts, "; ")))
        if kind == "shadow" and s.shadow_note then p("    note: " .. s.shadow_note) end
    end
    for _, c in ipairs(s.collectors) do
        p(string.format("  collector %s: %d rocks crossed (%s), ke q95 %s J, max %s J; "
            .. "height q95 %s m",
            tostring(c.name), c.rocks, g(c.fraction), fmt_ci(c.stats.ke.q95, c.stats.ke.q95_lo,
                c.stats.ke.q95_hi), g(c.stats.ke.max), fmt_ci(c.stats.height.q95,
                c.stats.height.q95_lo, c.stats.height.q95_hi)))
    end
    for _, b in ipairs(s.barriers) do
        p(string.format("  barrier %s: %d stopped, %d passed, %d not reached; impact energy "
            .. "q95 %s J, max %s J",
            tostring(b.name), b.stopped, b.passed, b.not_reached, fmt_ci(b.stats.energy.q95,
                b.stats.energy.q95_lo, b.stats.energy.q95_hi), g(b.stats.energy.max)))
    end
    if #s.files > 0 then p("  wrote " .. #s.files .. " files in " .. tostring(s.outdir)) end
end

return M
