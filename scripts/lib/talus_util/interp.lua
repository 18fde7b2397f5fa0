-- SPDX-License-Identifier: MIT
-- talus_util/interp.lua: piecewise-linear interpolation in a list of points {x, y} (a ground
-- profile, a measured table), with an explicit rule for x outside the points.
local I = {}

--- y at x on the polyline pts ({{x, y}, ...}, x ascending or descending; equal x allowed: a
--- vertical step). At a point's x its own y; between points linear (segments searched by
--- bisection). `outside` says what x beyond the ends gives: "clamp" the end point's y, "nan"
--- NaN, "error" nil and a message.
function I.linear(pts, x, outside)
    local n = #pts
    if pts[n][1] < pts[1][1] then
        local rev = {}
        for k = n, 1, -1 do rev[#rev + 1] = pts[k] end
        pts = rev
    end
    local x0, x1 = pts[1][1], pts[n][1]
    if x < x0 or x > x1 or x ~= x then
        if outside == "clamp" then return x < x0 and pts[1][2] or pts[n][2] end
        if outside == "nan" then return 0 / 0 end
        return nil, string.format("x = %g is outside the points [%g, %g]", x, x0, x1)
    end
    if x == x0 then return pts[1][2] end
    -- bisection: pts[lo][1] < x <= pts[hi][1]
    local lo, hi = 1, n
    while hi - lo > 1 do
        local mid = (lo + hi) // 2
        if pts[mid][1] < x then lo = mid else hi = mid end
    end
    local a, b = pts[lo], pts[hi]
    if x == b[1] then return b[2] end
    return a[2] + (b[2] - a[2]) * (x - a[1]) / (b[1] - a[1])
end

return I
