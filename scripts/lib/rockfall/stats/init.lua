-- SPDX-License-Identifier: MIT
--
-- rockfall.stats (also require("rockfall_stats")): Monte Carlo statistics of a rockfall
-- analysis, over the per-rock records of the rockfall library (one plain table per rock: end point, stop rule,
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
--
-- The parts, one file each in this folder: defaults.lua (the module table and its defaults),
-- records.lua (checks, profile, direction), endpoints.lua, envelopes.lua, lines.lua (collectors
-- and barriers), angles.lua, retention.lua (catchment retention), write.lua (CSV files),
-- summary.lua (printed); the general statistics are talus_util/stats.lua's.

local S = require("talus_util.stats")
local M = require("rockfall.stats.defaults")
require("rockfall.stats.write")
require("rockfall.stats.summary")

-- The general statistics, with this module's defaults.
M.qname, M.quantile, M.normal_quantile = S.qname, S.quantile, S.normal_quantile
function M.quantile_ci_ranks(n, p, level) return S.quantile_ci_ranks(n, p, level or M.CONFIDENCE) end
function M.quantile_ci(sorted, p, level) return S.quantile_ci(sorted, p, level or M.CONFIDENCE) end
function M.wilson(k, n, level) return S.wilson(k, n, level or M.CONFIDENCE) end
function M.describe(values, probs, level)
    return S.describe(values, probs or M.QUANTILES, level or M.CONFIDENCE)
end

return M
