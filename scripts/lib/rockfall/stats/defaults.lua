-- SPDX-License-Identifier: MIT
-- rockfall/stats/defaults.lua: the statistics' defaults (docs/rockfall-statistics.md); a script may change them
-- (rockfall.stats.CONFIDENCE = 0.9) before calling write.

local M = {}


--- Defaults (documented in docs/rockfall-statistics.md).
M.CONFIDENCE = 0.95
M.PERCENTILES = { 0.5, 0.9, 0.95, 0.98, 0.99 } -- of the end point
M.QUANTILES = { 0.5, 0.9, 0.95, 0.98 } -- of envelopes, collectors and barriers (RAMMS + 98 %)
M.ANGLE_PERCENTILES = { 0.01, 0.02, 0.05, 0.1, 0.5 } -- low angles are the far-reaching rocks
M.STOP_RULES = { "rest", "left", "time", "barrier" }
M.SHADOW_STEEP_DEG = 45 -- a profile segment at least this steep is "cliff" for the apex rule
M.SHADOW_TALUS_DEG = 10 -- one less steep but at least this steep is "talus"
M.SHADOW_MIN_DEG = 27.5 -- Evans & Hungr's (1993) lowest shadow angle: a warning below it
M.RETENTION_WIDTHS = { 0.9, 0.95, 0.99 } -- catchment widths reported for these retentions
M.RESTITUTION_PERCENTILES = { 0.1, 0.5, 0.9 } -- of the apparent Rn per material and shape
M.COLLECTOR_QUANTITIES = { "height", "ke_trans", "ke_rot", "ke", "v", "spin" }
M.BARRIER_QUANTITIES = { "energy", "height", "angle" }

return M
