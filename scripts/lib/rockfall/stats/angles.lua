-- SPDX-License-Identifier: MIT
-- rockfall/stats/angles.lua: energy-line and shadow angles of the deposited rocks, and the shadow apex.
local S = require("talus_util.stats")
local M = require("rockfall.stats.defaults")
local R = require("rockfall.stats.records")
local NaN, INF = 0 / 0, math.huge
local isnum = S.isnum
local fail, check_records, direction_of = R.fail, R.check_records, R.direction_of
local profile_points, point_xy, profile_y = R.profile_points, R.point_xy, R.profile_y

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
    res.energy_line = S.describe(el, probs, level)
    res.shadow = S.describe(sh, probs, level)
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
