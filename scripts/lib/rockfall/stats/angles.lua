-- SPDX-License-Identifier: MIT
-- rockfall/stats/angles.lua: energy-line and shadow angles of the deposited rocks, and the shadow apex.
local S = require("talus_util.stats")
local M = require("rockfall.stats.defaults")
local R = require("rockfall.stats.records")
local NaN, INF = 0 / 0, math.huge
local isnum = S.isnum
local fail, check_records, direction_of = R.fail, R.check_records, R.direction_of
local profile_points, point_xy, profile_y = R.profile_points, R.point_xy, R.profile_y
local travel_order, inclination = R.travel_order, R.inclination

-- Segments of the profile by their inclination in the direction of travel (degrees, positive
-- down): a cliff goes down at shadow_steep or more, a talus at shadow_talus or more (and less
-- than a cliff); anything flatter, level or rising (a bench, a ditch floor, a ditch's far wall)
-- is neither.
local function segment_kind(a, b, steep, talus)
    local deg = inclination(a, b)
    if deg >= steep then return "cliff", deg end
    if deg >= talus then return "talus", deg end
    return "other", deg
end

--- The x where the rocks start: analysis.release, else the mean of the records' releases.
local function release_x(analysis, records)
    local x = point_xy(analysis.release)
    if isnum(x) then return x end
    local sum, n = 0, 0
    for _, r in ipairs(records or {}) do
        local rx = point_xy(r.release)
        if isnum(rx) then sum, n = sum + rx, n + 1 end
    end
    return n > 0 and sum / n or nil
end

local function angle_option(analysis, key, default, where)
    local v = analysis[key]
    if v == nil then return default end
    if not (isnum(v) and v > 0 and v <= 90) then
        fail(where, "analysis.%s must be an angle in (0, 90] degrees (got %s)", key, tostring(v))
    end
    return v
end

--- The shadow-angle apex (Evans & Hungr 1993): the top of the talus below the cliff the rocks
--- fall from. analysis.shadow_apex ({x, y} or {x =, y =}) when given. Otherwise, walking the
--- profile in the direction of travel from the release (analysis.release, else the records'):
--- the source cliff is the run of cliff segments (downslope at analysis.shadow_steep degrees or
--- more, default 45) the rocks start on, or the first one they reach over level or gentle ground
--- (a crest); when they start on a talus, the cliff right above it. The apex is the cliff's toe
--- when a talus (downslope at analysis.shadow_talus or more, default 10) follows it. A ditch, a
--- step or a bench below never makes an apex. Returns apex {x, y, rule}, or nil and the reason.
function M.shadow_apex(analysis, records)
    local where = "shadow_apex"
    analysis = analysis or {}
    if analysis.shadow_apex ~= nil then
        local x, y = point_xy(analysis.shadow_apex)
        if not (isnum(x) and isnum(y)) then fail(where, "analysis.shadow_apex must be {x, y}") end
        return { x = x, y = y, rule = "given" }
    end
    local pts = profile_points(analysis, where)
    if not pts then return nil, "no profile and no shadow_apex" end
    local d = direction_of(analysis, where)
    local steep = angle_option(analysis, "shadow_steep", M.SHADOW_STEEP_DEG, where)
    local talus = angle_option(analysis, "shadow_talus", M.SHADOW_TALUS_DEG, where)
    if talus >= steep then
        fail(where, "analysis.shadow_talus (%g) must be less than shadow_steep (%g)", talus, steep)
    end
    local path = travel_order(pts, d)
    local kind, deg = {}, {}
    for k = 1, #path - 1 do kind[k], deg[k] = segment_kind(path[k], path[k + 1], steep, talus) end
    local xr = release_x(analysis, records) or path[1][1]
    local k = 1
    while k < #path - 1 and d * path[k + 1][1] < d * xr do k = k + 1 end
    local function at(p) return string.format("(%.4g, %.4g)", p[1], p[2]) end
    local function apex_at(j, how)
        return { x = path[j][1], y = path[j][2], rule = how }
    end
    if kind[k] == "talus" then
        local j = k
        while j > 1 and kind[j - 1] == "talus" do j = j - 1 end
        if j > 1 and kind[j - 1] == "cliff" then
            return apex_at(j, "top of the talus the rocks start on, below a cliff")
        end
        return nil, string.format("the rocks start on a %.3g deg slope, less steep than a cliff "
            .. "(shadow_steep = %g deg), with no cliff above it: no talus apex", deg[k], steep)
    end
    while kind[k] == "other" and k < #path - 1 do k = k + 1 end
    if kind[k] ~= "cliff" then
        return nil, kind[k] == "talus"
            and string.format("the rocks reach a %.3g deg slope, less steep than a cliff "
                .. "(shadow_steep = %g deg), before any cliff: no talus apex", deg[k], steep)
            or "no cliff (a segment of shadow_steep = " .. steep .. " deg or steeper) below the release"
    end
    local j = k
    while j < #path - 1 and kind[j + 1] == "cliff" do j = j + 1 end
    if j < #path - 1 and kind[j + 1] == "talus" then
        return apex_at(j + 1, string.format("top of the talus below the cliff %s-%s", at(path[k]),
            at(path[j + 1])))
    end
    return nil, string.format("the cliff %s-%s ends on ground that does not go down at "
        .. "shadow_talus = %g deg or more (a bench, a ditch, a flat): no talus apex",
        at(path[k]), at(path[j + 1]), talus)
end

--- The warning for shadow angles below Evans & Hungr's (1993) lowest, 27.5 deg (nil if none).
function M.shadow_warning(shadow)
    local low, min = 0, INF
    for _, a in ipairs(shadow) do
        if a < M.SHADOW_MIN_DEG then low = low + 1 end
        min = math.min(min, a)
    end
    if low == 0 then return nil end
    return string.format("%d of %d rocks beyond the apex stopped at shadow angles below %g deg "
        .. "(the lowest %.3g deg), the lowest Evans & Hungr (1993) found in the field: check the "
        .. "materials' restitution and rolling resistance, and the apex", low, #shadow,
        M.SHADOW_MIN_DEG, min)
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
    local apex, no_apex = M.shadow_apex(analysis, records)
    local res = { per_rock = {}, apex = apex, no_apex = no_apex, deposited = 0, beyond_apex = 0 }
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
    res.energy_line = S.describe(el, probs, level)
    res.shadow = S.describe(sh, probs, level)
    res.warning = M.shadow_warning(sh)
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

return M
