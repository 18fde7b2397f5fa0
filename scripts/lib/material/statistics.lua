-- SPDX-License-Identifier: MIT
-- material/statistics.lua: elastic constants from a stress-strain history, and the scatter of
-- results over seeds.
local St = {}

--- The least-squares slope of ys on xs (nil for fewer than 2 points or equal xs).
function St.lsq_slope(xs, ys)
    local n = #xs
    if n < 2 then return nil end
    local mx, my = 0, 0
    for i = 1, n do mx = mx + xs[i]; my = my + ys[i] end
    mx, my = mx / n, my / n
    local sxx, sxy = 0, 0
    for i = 1, n do
        sxx = sxx + (xs[i] - mx) ^ 2; sxy = sxy + (xs[i] - mx) * (ys[i] - my)
    end
    if sxx == 0 then return nil end
    return sxy / sxx
end

--- From history rows {ea, sa, el} (axial strain, axial stress, lateral strain) up to the peak:
--- E = tangent modulus at 50% of peak (ISRM; least-squares slope of the pre-peak rows with
--- 40% <= stress <= 60% of peak), E50 = secant modulus at 50% of peak, nu = slope of lateral
--- against axial strain over the same rows.
function St.analyse(rows, ipeak, lo, hi)
    lo, hi = lo or 0.4, hi or 0.6
    local peak = rows[ipeak].sa
    local xs, ys, ls = {}, {}, {}
    for i = 1, ipeak do
        local r = rows[i]
        if r.sa >= lo * peak and r.sa <= hi * peak then
            xs[#xs + 1] = r.ea; ys[#ys + 1] = r.sa; ls[#ls + 1] = r.el
        end
    end
    local E = St.lsq_slope(xs, ys)
    local nu = St.lsq_slope(xs, ls)
    local E50
    for i = 2, ipeak do
        local a, b = rows[i - 1], rows[i]
        if a.sa < 0.5 * peak and b.sa >= 0.5 * peak then
            local f = (0.5 * peak - a.sa) / (b.sa - a.sa)
            E50 = 0.5 * peak / (a.ea + f * (b.ea - a.ea))
            break
        end
    end
    return { E = E, E50 = E50, nu = nu, points = #xs }
end


--- The crack damage threshold (Martin & Chandler 1994): the axial stress where the volumetric
--- strain (compression positive) stops growing and the specimen starts to dilate as its cracks
--- open: the row of the largest volumetric strain up to the peak (row ipeak, the peak itself
--- when it grows until then). Returns { stress, strain_axial, strain_volumetric, cracks, row }
--- or nil without volumetric strains.
function St.crack_damage(rows, ipeak)
    local best
    for i = 1, ipeak do
        local v = rows[i].strain_volumetric
        if v and (not best or v > rows[best].strain_volumetric) then best = i end
    end
    if not best then return nil end
    local r = rows[best]
    return { stress = r.sa, strain_axial = r.ea, strain_volumetric = r.strain_volumetric, cracks = r.cracks,
             row = best }
end

--- Mean and sample standard deviation of field `key` over a list of result tables (the
--- scatter over seeds that the examples report); sd = 0 for a single result. A result with
--- `valid == false` (a Brazilian test that did not split, M.brazilian) or without the value is left
--- out; the third
--- value is the number of results used (mean and sd NaN when none).
function St.mean_sd(results, key)
    local n, s, s2 = 0, 0, 0
    for _, r in ipairs(results) do
        if r.valid ~= false and r[key] ~= nil then n = n + 1; s = s + r[key] end
    end
    local mean = s / n
    for _, r in ipairs(results) do
        if r.valid ~= false and r[key] ~= nil then s2 = s2 + (r[key] - mean) ^ 2 end
    end
    return mean, n > 1 and math.sqrt(s2 / (n - 1)) or (n == 1 and 0 or 0 / 0), n
end

--- The results of a talus.map over `count` seeds without the seeds that failed (talus.map
--- records a failure, nil in its place, and goes on), saying how many were left out.
function St.finished(list, count)
    local ok = {}
    for i = 1, count do
        if list[i] ~= nil then ok[#ok + 1] = list[i] end
    end
    if list.failed then
        print(string.format("%d of %d seeds failed and are left out; the first: %s", #list.failed, count,
            list.failed[1].message))
    end
    return ok
end

return St
