-- SPDX-License-Identifier: MIT
-- rockfall/stats/records.lua: the records and the analysis as the statistics read them: checks, the profile,
-- the downslope direction, the envelope bins.
local Err = require("talus_util.errors")
local Interp = require("talus_util.interp")
local S = require("talus_util.stats")

local R = {}
local NaN = 0 / 0
local isnum = S.isnum
R.NaN, R.isnum = NaN, isnum

--- Raises "rockfall_stats.<where>: <message>" at the user's script line.
local function fail(where, fmt, ...)
    Err.raise("rockfall_stats." .. where .. ": " .. string.format(fmt, ...))
end

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

--- The profile's points in the order a rock travelling along d meets them.
local function travel_order(pts, d)
    if d * (pts[#pts][1] - pts[1][1]) >= 0 then return pts end
    local r = {}
    for i = #pts, 1, -1 do r[#r + 1] = pts[i] end
    return r
end

--- Inclination (degrees) of the segment a-b in the direction of travel, positive going down.
local function inclination(a, b)
    return math.deg(math.atan(a[2] - b[2], math.abs(b[1] - a[1])))
end

--- Surface height of the profile at x (linear between points; NaN outside the profile).
local function profile_y(pts, x)
    return (Interp.linear(pts, x, "nan"))
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

R.fail, R.point_xy, R.profile_points, R.direction_of, R.profile_y = fail, point_xy, profile_points,
    direction_of, profile_y
R.check_records, R.envelope_of, R.x_far, R.nice_width = check_records, envelope_of, x_far, nice_width
R.travel_order, R.inclination = travel_order, inclination

return R
