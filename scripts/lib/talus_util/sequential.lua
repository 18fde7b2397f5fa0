-- SPDX-License-Identifier: MIT
-- talus_util/sequential.lua: a Monte Carlo that runs until named statistics are known to a stated
-- precision, looking at its sample at a few sizes fixed in advance.
--
-- Stopping the first time an interval is narrow enough is a sequential test: a fixed-n
-- interval with coverage 1 - a covers less often at a data-dependent stopping time, because an
-- interval that happens to be short is more often one that misses (Chow & Robbins 1965 for the
-- mean; the same holds for order-statistic intervals of a quantile). With looks at n_1 < ... < n_L
-- fixed in advance and every interval at level 1 - a / L, the chance that the interval at the
-- stopping look misses is at most the chance that one of the L intervals misses, at most
-- L (a / L) = a (Bonferroni's inequality; Jennison & Turnbull 2000 on repeated confidence
-- intervals): the reported interval covers with probability at least 1 - a whenever the run
-- stops. The price is wider intervals: z = 2.80 instead of 1.96 for 9 looks at 95 %.
local M = {}

--- The look sizes: first, first g, first g^2, ... (rounded up, each at least one more than the
--- one before), and max_n last.
function M.schedule(first, max_n, growth)
    growth = growth or 2
    if not (math.type(first) == "integer" and first >= 1 and math.type(max_n) == "integer"
            and max_n >= first and type(growth) == "number" and growth > 1) then
        require("talus_util.errors").raise("sequential.schedule: need integers 1 <= first <= max_n and "
            .. "growth > 1 (got %s, %s, %s)", tostring(first), tostring(max_n), tostring(growth))
    end
    local looks, n = { first }, first
    while n < max_n do
        n = math.min(max_n, math.max(n + 1, math.ceil(first * growth ^ #looks - 1e-9)))
        looks[#looks + 1] = n
    end
    return looks
end

--- The confidence level of each look's intervals: 1 - (1 - level) / looks.
function M.look_level(level, looks) return 1 - (1 - level) / looks end

--- Runs looks until every target is met. spec:
---   schedule  the look sizes (M.schedule)
---   level     the overall confidence level (default 0.95)
---   more(from, to)  grows the sample to `to` items (items from..to are new)
---   targets   list of { within = half-width, estimate = function(level) -> value, lo, hi }
--- A target is met when both bounds are finite numbers and (hi - lo) / 2 <= within.
--- Returns { n =, looks = (looks taken), met = (all met), level = (each look's), history =
--- {{look =, n =, estimates = {{value, lo, hi, half, met}}}} }.
function M.run(spec)
    local level = M.look_level(spec.level or 0.95, #spec.schedule)
    local out = { level = level, history = {}, met = false, n = 0, looks = 0 }
    local have = 0
    for k, n in ipairs(spec.schedule) do
        spec.more(have + 1, n)
        have = n
        local look, all = { look = k, n = n, estimates = {} }, true
        for i, t in ipairs(spec.targets) do
            local v, lo, hi = t.estimate(level)
            local half = (hi - lo) / 2
            local ok = lo == lo and hi == hi and math.abs(lo) < math.huge and math.abs(hi) < math.huge
                and half <= t.within
            look.estimates[i] = { value = v, lo = lo, hi = hi, half = half, met = ok }
            all = all and ok
        end
        out.history[k] = look
        out.n, out.looks = n, k
        if all then
            out.met = true
            break
        end
    end
    return out
end

return M
