-- SPDX-License-Identifier: MIT
-- talus_util/stats.lua: sample statistics with distribution-free confidence intervals
-- (docs/rockfall-statistics.md gives every definition):
--   * quantiles: Hyndman & Fan (1996) type 7 (linear interpolation between order statistics,
--     the default of R and numpy);
--   * confidence interval of a quantile: the interval [x_(l), x_(u)] between two order
--     statistics, the ranks from the binomial distribution of the number of observations below
--     the quantile, each tail at most (1 - level)/2 (Hahn & Meeker 1991, section 5.2; Conover
--     1999, section 3.2); a side the sample is too small for is NaN;
--   * confidence interval of a probability: Wilson's score interval (Wilson 1927; recommended
--     by Brown, Cai & DasGupta 2001).
-- NaN marks "not defined" (an empty sample, an interval side out of reach).
local M = {}

local NaN = 0 / 0
local INF = math.huge

M.CONFIDENCE = 0.95

function M.isnum(v) return type(v) == "number" and v == v end
local isnum = M.isnum

--- The numbers of a list, NaN and non-numbers dropped, sorted ascending (a new table).
function M.sorted_numbers(list)
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
    probs = probs or { 0.5, 0.9, 0.95, 0.98 }
    local s = M.sorted_numbers(values)
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

return M
