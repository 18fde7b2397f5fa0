-- SPDX-License-Identifier: MIT
-- material/jaws.lua: the loading walls of the Brazilian test: the curved jaws of the ISRM
-- suggested method (ISRM 1978), and where the loading walls first touch a disk.
local raise = require("talus_util.errors").raise
local J = {}

--- Where the loading walls first touch a disk: the angles [degrees] from the loaded diameter,
--- seen from the disk's centre (cx, cy), of the balls it and ib of `list` (top and bottom).
--- A cut disk's surface is as rough as a ball radius, so the first contact may lie well off
--- the diameter (docs/material.md "Brazilian test").
function J.contact_angles(list, cx, cy, it, ib)
    local function ang(p, side) return math.deg(math.atan(p[1] - cx, side * (p[2] - cy))) end
    return { ang(list[it], 1), ang(list[ib], -1) }
end

--- Vertices of a curved jaw: n + 1 points on the circle of radius Rj about (cx, yc), from
--- -phi to +phi about the vertical; side = 1 for the top jaw (the arc is the circle's top,
--- concave downward onto the disk), -1 for the bottom jaw. Every vertex lies on the circle,
--- so each segment is a chord; its midpoint lies Rj (1 - cos(phi / n)) inside the circle
--- (the sagitta, L^2 / (8 Rj) for a chord of length L).
function J.jaw_points(cx, yc, Rj, phi, n, side)
    local pts = {}
    for k = 0, n do
        local a = -phi + 2 * phi * k / n
        pts[#pts + 1] = { cx + Rj * math.sin(a), yc + side * Rj * math.cos(a) }
    end
    return pts
end

--- The curved jaws of the ISRM suggested method for the Brazilian test (ISRM 1978): each jaw
--- is an arc of radius Rj = 1.5 R (R = D / 2, D the disk's ball extent as M.brazilian measures
--- it), so the load spreads over a contact arc (about 10 degrees at failure in the rock test)
--- instead of the point load of a flat platen, which in a bonded-ball disk is one ball: that
--- ball's bonds crush first and the disk may never split (docs/material.md "Brazilian test").
--- A jaw is one wall, a chain of `segments` chords of the arc (default: chords no longer than
--- half the smallest ball radius, so a ball meets a concave polygon whose flats are shorter
--- than itself and whose sagitta is below 1e-3 of a ball radius at LdB sizes), spanning
--- +-`angle` about the jaw's centre (default 20 degrees: +-0.51 R across, about +-31 degrees
--- of the disk; the jaw clears the disk's surface by 0.05 R at its ends, far more than the
--- jaw travel at failure). Each jaw is placed where it just touches the outermost ball it can
--- reach: the top jaw's centre at yc = max_i (y_i - sqrt((Rj - r_i)^2 - (x_i - cx)^2)) over
--- the balls within its span, the lowest centre for which they all lie inside the jaw's
--- circle; the bottom one mirrored.
--- Sets sp.top, sp.bottom (wall records, apex positions), sp.disk = {center, D, Rj, angle,
--- segments, top_center, bottom_center, first_contact}.
--- Measured limit (docs/results/material.md): on a disk cut from a box packing (M.disk) the surface is
--- as rough as a ball radius, far rougher than the jaw's departure from the disk's circle
--- (R theta^2 / 6), so the jaw first touches one ball up to ~20 degrees off the diameter and
--- the LdB disks split no more often than between flat platens.
function J.make_jaws(sp, list, center, angle_deg, segments)
    local m = sp.model
    local cx, cy = center[1], center[2]
    local xmin, xmax, ymin, ymax, rmin = math.huge, -math.huge, math.huge, -math.huge, math.huge
    for _, p in ipairs(list) do
        xmin = math.min(xmin, p[1] - p[3]); xmax = math.max(xmax, p[1] + p[3])
        ymin = math.min(ymin, p[2] - p[3]); ymax = math.max(ymax, p[2] + p[3])
        rmin = math.min(rmin, p[3])
    end
    local D = 0.5 * ((xmax - xmin) + (ymax - ymin))
    local Rj = 1.5 * 0.5 * D
    angle_deg = angle_deg or 20
    if type(angle_deg) ~= "number" or angle_deg <= 0 or angle_deg > 60 then
        raise(string.format("material.specimen: jaw_angle = %s degrees (0 < angle <= 60)", tostring(angle_deg)))
    end
    local phi = math.rad(angle_deg)
    -- an even count puts a vertex at the apex (the jaw symmetric about the loaded diameter)
    local n = segments or 2 * math.max(4, math.ceil(phi * Rj / (0.5 * rmin)))
    if type(n) ~= "number" or n < 1 or n ~= math.floor(n) then
        raise(string.format("material.specimen: jaw_segments = %s (a positive integer)", tostring(segments)))
    end
    -- Only the balls the arc can touch count: those seen from the jaw's centre within the
    -- jaw's span widened by the ball's own angular half-width r / (Rj - r) (a ball further out
    -- passes beside the jaw's end; counting it would leave a narrow jaw short of the disk).
    -- The jaw's centre is at about cy -+ (Rj - R) below/above the disk's centre (R = D/2) for
    -- this angular test; the height then follows from the selected balls exactly.
    local yt, yb = -math.huge, math.huge
    local it, ib -- the balls the jaws touch first
    local R = 0.5 * D
    for i, p in ipairs(list) do
        local dx = p[1] - cx
        local h = math.sqrt((Rj - p[3]) ^ 2 - dx * dx) -- Rj > R >= |dx| + r: real
        local w = phi + p[3] / (Rj - p[3])
        if math.abs(math.atan(dx, p[2] - (cy - (Rj - R)))) <= w and p[2] - h > yt then yt, it = p[2] - h, i end
        if math.abs(math.atan(dx, (cy + (Rj - R)) - p[2])) <= w and p[2] + h < yb then yb, ib = p[2] + h, i end
    end
    local function jaw(yc, side)
        local pts = J.jaw_points(cx, yc, Rj, phi, n, side)
        local w = m:wall{ points = pts, group = "platen" }
        -- inward normal -side (the top jaw presses down); apex offset from the first vertex
        return { wall = w, n = { 0, -side }, apex = -Rj * (1 - math.cos(phi)) }
    end
    sp.top = jaw(yt, 1)
    sp.bottom = jaw(yb, -1)
    sp.disk = { center = { cx, cy }, D = D, Rj = Rj, angle = angle_deg, segments = n,
                top_center = { cx, yt }, bottom_center = { cx, yb },
                first_contact = J.contact_angles(list, cx, cy, it, ib) }
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

return J
