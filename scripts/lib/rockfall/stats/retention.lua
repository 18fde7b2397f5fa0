-- SPDX-License-Identifier: MIT
-- rockfall/stats/retention.lua: catchment retention, the share of the rocks that stopped within a
-- distance of the toe of the slope (the cumulative curve of Pierson et al.'s (2001) catchment
-- design charts), the width a retention needs, and the retention of named catchments (a ditch).
local S = require("talus_util.stats")
local M = require("rockfall.stats.defaults")
local R = require("rockfall.stats.records")
local NaN, INF = 0 / 0, math.huge
local isnum = S.isnum
local fail, check_records, direction_of = R.fail, R.check_records, R.direction_of
local profile_points, travel_order, inclination = R.profile_points, R.travel_order, R.inclination
local x_far = R.x_far

-- A rock is retained where it stopped for good: at rest, or held by a barrier. One that left the
-- profile or was still moving at the time cap is retained nowhere.
local RETAINED = { rest = true, barrier = true }

--- The toe of the slope, the origin of the catchment distances: analysis.toe when given; else
--- the lower end of the last segment going down at shadow_talus degrees or more (default 10)
--- before the profile first reaches its lowest height (the foot of the slope, below a ditch's
--- near wall when the ditch is the lowest ground). Returns {x, y, rule} or nil.
function M.toe(analysis)
    local where = "toe"
    analysis = analysis or {}
    local pts = profile_points(analysis, where)
    if analysis.toe ~= nil then
        if not isnum(analysis.toe) then fail(where, "analysis.toe must be a number (an x)") end
        return { x = analysis.toe, y = pts and R.profile_y(pts, analysis.toe) or NaN, rule = "given" }
    end
    if not pts then return nil end
    local d = direction_of(analysis, where)
    local talus = analysis.shadow_talus or M.SHADOW_TALUS_DEG
    local path = travel_order(pts, d)
    local low = INF
    for _, p in ipairs(path) do low = math.min(low, p[2]) end
    local toe
    for k = 1, #path - 1 do
        if inclination(path[k], path[k + 1]) >= talus then toe = path[k + 1] end
        if path[k + 1][2] <= low then break end
    end
    toe = toe or path[1]
    return { x = toe[1], y = toe[2], rule = string.format("the foot of the slope (the last "
        .. "segment down at %g deg or more before its lowest point)", talus) }
end

--- Type-7 quantile of a sorted list that may end in +inf (rocks retained nowhere).
local function quantile(sorted, p)
    local n = #sorted
    if n == 0 then return NaN end
    local h = (n - 1) * p + 1
    local j = math.floor(h)
    if j >= n or h == j then return sorted[math.min(j, n)] end
    local a, b = sorted[j], sorted[j + 1]
    if b == INF then return INF end
    return a + (h - j) * (b - a)
end

--- Catchment retention. opts: confidence, distances (the grid; default 0, dx, ... up to the
--- profile's end, dx the envelope's or 1 m), widths (retentions whose width is reported,
--- default M.RETENTION_WIDTHS). Returns { toe, n, above_toe, nowhere, curve = {{distance, x,
--- retained, fraction, lo, hi}}, widths = {{p, name, width, lo, hi}}, catchments = {{name,
--- x_from, x_to, reached, retained, fraction, lo, hi, of_reached, of_reached_lo,
--- of_reached_hi}} } or nil when there is no toe (no profile and no analysis.toe).
function M.retention(records, analysis, opts)
    local where = "retention"
    opts, analysis = opts or {}, analysis or {}
    check_records(records, where)
    local toe = M.toe(analysis)
    if not toe then return nil end
    local level = opts.confidence or analysis.confidence or M.CONFIDENCE
    local d = direction_of(analysis, where)
    local n = #records
    -- Each rock's distance from the toe where it was retained (+inf: nowhere).
    local dist, res = {}, { toe = toe, n = n, above_toe = 0, nowhere = 0 }
    for i, r in ipairs(records) do
        if RETAINED[r.stop] then
            dist[i] = d * (r.end_x - toe.x)
            if dist[i] <= 0 then res.above_toe = res.above_toe + 1 end
        else
            dist[i] = INF
            res.nowhere = res.nowhere + 1
        end
    end
    local grid = opts.distances
    if not grid then
        grid = {}
        local pts = profile_points(analysis, where)
        local far = 0
        for _, p in ipairs(pts or {}) do far = math.max(far, d * (p[1] - toe.x)) end
        local env = analysis.envelope
        local dx = type(env) == "table" and (env.dx or env[3]) or 1
        for k = 0, math.ceil(far / dx - 1e-9) do grid[#grid + 1] = math.min(k * dx, far) end
    end
    res.curve = {}
    for i, w in ipairs(grid) do
        local k = 0
        for _, s in ipairs(dist) do if s <= w then k = k + 1 end end
        local lo, hi = S.wilson(k, n, level)
        res.curve[i] = { distance = w, x = toe.x + d * w, retained = k,
            fraction = n > 0 and k / n or NaN, lo = lo, hi = hi }
    end
    -- The width that retains a share p: the p-quantile of the distances (0 for rocks that
    -- stopped above the toe), with its order-statistic interval; inf where more than 1 - p of
    -- the rocks are retained nowhere.
    local sorted = {}
    for i, s in ipairs(dist) do sorted[i] = math.max(s, 0) end
    table.sort(sorted)
    res.widths = {}
    for i, p in ipairs(opts.widths or M.RETENTION_WIDTHS) do
        local lo, hi = S.quantile_ci(sorted, p, level)
        res.widths[i] = { p = p, name = S.qname(p), width = quantile(sorted, p), lo = lo, hi = hi }
    end
    -- Named catchments: the rocks retained between x_from and x_to, of all and of those that
    -- reached x_from.
    res.catchments = {}
    for i, c in ipairs(analysis.catchments or {}) do
        local a, b = c.x_from, c.x_to
        if not (isnum(a) and isnum(b) and d * (b - a) > 0) then
            fail(where, "analysis.catchments[%d] must be {name =, x_from =, x_to =} with x_to "
                .. "beyond x_from in the direction of travel", i)
        end
        local reached, kept = 0, 0
        for _, r in ipairs(records) do
            if d * x_far(r, d) >= d * a then reached = reached + 1 end
            if RETAINED[r.stop] and d * r.end_x >= d * a and d * r.end_x <= d * b then
                kept = kept + 1
            end
        end
        local lo, hi = S.wilson(kept, n, level)
        local rlo, rhi = S.wilson(kept, reached, level)
        res.catchments[i] = { name = c.name or ("catchment" .. i), x_from = a, x_to = b,
            reached = reached, retained = kept, fraction = n > 0 and kept / n or NaN, lo = lo,
            hi = hi, of_reached = reached > 0 and kept / reached or NaN, of_reached_lo = rlo,
            of_reached_hi = rhi }
    end
    return res
end

return M
