-- SPDX-License-Identifier: MIT
-- material/brazilian.lua: the Brazilian (diametral compression) test on a disk: the disk cut
-- from a packing, the test, and where the bonds broke.
local U = require("material.util")
local Wl = require("material.walls")
local L = require("material.loading")
local Cr = require("material.cracks")
local St = require("material.statistics")
local raise = require("talus_util.errors").raise

local Br = {}

--- Indices of the packing's balls inside a disk of diameter d (default: 0.98 of the smaller
--- box side) at the box centre; the disk is cut from the packing (P&C cut their specimens
--- from a larger packing too). The list also carries `center` = {x, y} and `cut` = d, so
--- M.specimen knows it is a disk and gives it the Brazilian jaws.
function Br.disk(pk, d)
    -- a disk made in a circular vessel (M.genesis_disk) is all of the packing
    if pk.vessel and d == nil then
        local idx = { center = pk.vessel.center, cut = pk.vessel.diameter }
        for i = 1, #pk.balls do idx[i] = i end
        return idx
    end
    local b = pk.box
    local cx, cy = 0.5 * (b[1] + b[3]), 0.5 * (b[2] + b[4])
    d = d or 0.98 * math.min(b[3] - b[1], b[4] - b[2])
    local idx = { center = { cx, cy }, cut = d }
    for i, p in ipairs(pk.balls) do
        local dist = math.sqrt((p[1] - cx) ^ 2 + (p[2] - cy) ^ 2)
        if dist + p[3] <= 0.5 * d then idx[#idx + 1] = i end
    end
    return idx
end

--- Where the bonds of a Brazilian disk broke, against the loaded diameter (the vertical line
--- x = cx). breaks = {{x, y, t}, ...}; D the disk's diameter; t_peak the time of the peak.
--- Returns:
---   n, band: the number of breaks and the fraction within |x - cx| <= 0.1 D (a band of 0.2 D
---     about the loaded diameter; breaks spread evenly over the disk would give 0.25 of them);
---   cover: the fraction of the loaded diameter's 20 bins (of 0.05 D along y) holding a break
---     of the band: how far the crack runs along the diameter;
---   angle: the orientation of the breaks' principal axis (second moments of their positions),
---     degrees from the loaded diameter (0: along it);
---   pre_peak: the number of breaks up to the peak; jaw_first: how many of the first
---     max(pre_peak, 1) breaks (those up to the peak, or the one that ended it) lie at a jaw:
---     within 0.1 D of the disk's surface (distance from the centre >= 0.4 D) and within 35
---     degrees of the loaded diameter (the curved jaws span +-31 degrees of the disk; a jaw's
---     first contact may be 20 degrees off the diameter);
---   split: band >= 0.5 and cover >= 0.5 (most breaks on the loaded diameter, and the crack
---     spans at least half of it); crush: not split, and at least half of those first breaks
---     at a jaw (the failure of the flat platens: bonds under the point load).
--- The thresholds are set a priori (not fitted to runs): the band is the central fifth of the
--- disk, a split at a 50% post-peak stop is expected to reach well past the centre.
function Br.fracture(breaks, center, D, t_peak)
    local cx, cy = center[1], center[2]
    local n, nb = #breaks, 0
    local bins = {}
    local sx, sy = 0, 0
    for _, b in ipairs(breaks) do sx = sx + b[1]; sy = sy + b[2] end
    local mx, my = sx / math.max(n, 1), sy / math.max(n, 1)
    local cxx, cyy, cxy = 0, 0, 0
    local pre = 0
    for _, b in ipairs(breaks) do
        if t_peak and b[3] <= t_peak then pre = pre + 1 end
    end
    local first = math.min(n, math.max(pre, 1))
    local near = 0
    for k = 1, first do
        local dx, dy = breaks[k][1] - cx, breaks[k][2] - cy
        local rr = math.sqrt(dx * dx + dy * dy)
        if rr >= 0.4 * D and math.deg(math.atan(math.abs(dx), math.abs(dy))) <= 35 then near = near + 1 end
    end
    for _, b in ipairs(breaks) do
        local dx, dy = b[1] - cx, b[2] - cy
        if math.abs(dx) <= 0.1 * D then
            nb = nb + 1
            local k = math.floor((dy / D + 0.5) * 20)
            if k >= 0 and k < 20 then bins[k] = true end
        end
        cxx = cxx + (b[1] - mx) ^ 2; cyy = cyy + (b[2] - my) ^ 2; cxy = cxy + (b[1] - mx) * (b[2] - my)
    end
    local nbins = 0
    for _ in pairs(bins) do nbins = nbins + 1 end
    -- principal axis of the 2x2 second-moment tensor: 0.5 atan2(2 cxy, cxx - cyy) from x;
    -- from the vertical (the loaded diameter) that is 90 degrees less, folded into [0, 90]
    local theta = 0.5 * math.atan(2 * cxy, cxx - cyy)
    local angle = math.abs(90 - math.abs(math.deg(theta)))
    local band = n > 0 and nb / n or 0
    local cover = nbins / 20
    local split = n > 0 and band >= 0.5 and cover >= 0.5
    return { n = n, band = band, cover = cover, angle = n > 1 and angle or nil, pre_peak = pre,
             jaw_first = near, split = split, crush = (not split) and n > 0 and near >= 0.5 * first }
end

--- The secant stiffness at the peak over the elastic stiffness: the least-squares slope of the
--- load against the strain over the rows before the first break with at least a fifth of the
--- load there, and the secant from that line's zero-load strain to the peak. About 1 when the
--- disk split from an elastic state (0.66-1.05 on the flat-jointed granite's disks that split);
--- far below it when the disk cracked through, its load stopped rising, and the pieces then
--- loaded up again as they compacted between the jaws (0.14-0.34 on those disks). nil when
--- fewer than 3 such rows (rows without strain or break counts: no judgement).
function Br.peak_stiffness(rows, ipeak)
    local last = 0
    for i = 1, ipeak do
        local r = rows[i]
        if not (r.ea and r.sa and r.breaks_tension and r.breaks_shear) then return nil end
        if r.breaks_tension + r.breaks_shear > 0 then break end
        last = math.max(last, r.sa)
    end
    local xs, ys, sx, sy = {}, {}, 0, 0
    for i = 1, ipeak do
        local r = rows[i]
        if r.breaks_tension + r.breaks_shear > 0 then break end
        if r.sa >= 0.2 * last and last > 0 then
            xs[#xs + 1], ys[#ys + 1] = r.ea, r.sa
            sx, sy = sx + r.ea, sy + r.sa
        end
    end
    if #xs < 3 then return nil end
    local k = St.lsq_slope(xs, ys)
    if not (k and k > 0) then return nil end
    local e0 = (sx - sy / k) / #xs
    local p = rows[ipeak]
    if not (p.ea > e0) then return nil end
    return p.sa / (p.ea - e0) / k
end

--- A peak reached at less than this secant over elastic stiffness (Br.peak_stiffness) is not a
--- splitting strength.
Br.min_peak_stiffness = 0.5

--- Whether a Brazilian test measured a tensile strength: the disk split along the loaded
--- diameter, and its peak came from that fracture. Not valid (with the reason) when the test
--- stopped before the disk failed (max_steps, max_strain); when the load fell after its peak
--- with no bond breaking (the disk slipped or rolled at a jaw: the peak is a friction limit, not
--- a strength); when the first breaks were under a jaw and the disk did not split (a crushed
--- contact: fracture.crush); when it did not split (fracture.split); or when the peak came
--- after the disk had cracked through and its load had risen again (Br.peak_stiffness below
--- Br.min_peak_stiffness: the elastic solution behind 2F / (pi D t) no longer held). res:
--- M.brazilian's result (stop, rows, ipeak, cracks, fracture). Returns valid, reason.
function Br.validity(res)
    if res.stop ~= "post_peak" then
        return false, string.format("the disk did not fail (the test stopped at %s)", res.stop)
    end
    local t_peak, after = res.rows[res.ipeak].time, 0
    for _, c in ipairs(res.cracks) do
        if c.time > t_peak then after = after + 1 end
    end
    if after == 0 then
        return false, "the load fell after its peak with no bond breaking: a slip (at a jaw, or on contacts " ..
            "already broken), not a fracture"
    end
    local f = res.fracture
    if f.crush then
        return false, string.format("crushed at a jaw (%d of the first %d breaks there), no split", f.jaw_first,
            math.max(f.pre_peak, 1))
    end
    if not f.split then
        return false, string.format("no split along the loaded diameter (%.0f%% of the breaks within 0.1 D of it, "
            .. "crack along %.0f%% of it)", 100 * f.band, 100 * f.cover)
    end
    local k = Br.peak_stiffness(res.rows, res.ipeak)
    if k and k < Br.min_peak_stiffness then
        return false, string.format("the peak came after the disk had cracked (its secant stiffness there %.2f of the "
            .. "elastic one): the cracked disk compacting between the jaws, not a splitting strength", k)
    end
    return true, nil
end

--- A copy of material `mat` whose platens (the jaws) have friction `fric`: between smooth
--- jaws a disk slid or rolled out sideways (docs/results/material.md).
function Br.with_jaw_friction(mat, fric)
    return U.merged(mat, { platen = U.merged(mat.platen, { fric = fric }) })
end

--- Brazilian test on a disk specimen (M.specimen(pk, mat, { balls = M.disk(pk) })), between
--- the curved jaws of the ISRM suggested method (the default, M.make_jaws) or flat platens
--- (M.specimen's opts.jaws = "flat"); sigma_t = 2 F / (pi D t), F the mean of the two jaws'
--- forces at the peak, D the disk's diameter (ball extent), t = 1 m. Options as for
--- M.compress, plus `jaws` (optional: it must match the specimen's, a check that the
--- specimen was made for what the caller means to run). The result also has `fracture`
--- (M.fracture of the bond breaks), `jaws`, `cracks` (the crack list, cracks.lua; written as
--- CSV as M.compress's), `breaks_at` (the breaks {x, y, time}), and `valid`, `reason`
--- (Br.validity): `tensile` is a tensile strength only when `valid`; M.mean_sd leaves the others
--- out.
function Br.brazilian(sp, opts)
    opts = opts or {}
    if opts.jaws ~= nil and opts.jaws ~= (sp.jaws or "flat") then
        raise(string.format("material.brazilian: jaws = '%s' but the specimen has %s (give jaws to " ..
            "M.specimen: M.specimen(pk, mat, { balls = M.disk(pk), jaws = '%s' })",
            tostring(opts.jaws), sp.jaws and ("'" .. sp.jaws .. "'") or "flat platens", tostring(opts.jaws)))
    end
    -- a copy, the caller's table untouched
    local o = U.merged(opts)
    o.jaws = nil
    -- see load_platens: a load that comes back after a break under a platen is not cut
    if o.confirm == nil then o.confirm = 0.5 end
    local e = sp.extent
    local D = 0.5 * ((e[3] - e[1]) + (e[4] - e[2]))
    local res = L.load_platens(sp, o, function(h0, h)
        local F = 0.5 * (Wl.push(sp.top) + Wl.push(sp.bottom))
        return { ea = (h0 - h) / h0, sa = 2 * F / (math.pi * D), el = 0, force = F }
    end)
    if opts.csv then U.write_csv(opts.csv, res.rows, L.columns) end
    local crack_csv = Cr.csv_name(opts)
    if crack_csv then Cr.write_csv(crack_csv, res.cracks) end
    local at = {}
    for i, c in ipairs(res.cracks) do at[i] = { c.x, c.y, c.time } end
    res.tensile = res.peak
    res.force = res.rows[res.ipeak].force
    res.diameter = D
    res.balls = sp.balls and #sp.balls or sp.model:ball_count()
    res.jaws = sp.jaws or "flat"
    res.breaks_at = at
    local c = sp.disk and sp.disk.center or { 0.5 * (e[1] + e[3]), 0.5 * (e[2] + e[4]) }
    res.fracture = Br.fracture(at, c, D, res.rows[res.ipeak].time)
    res.valid, res.reason = Br.validity(res)
    return res
end

return Br
