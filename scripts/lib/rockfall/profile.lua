-- SPDX-License-Identifier: MIT
-- rockfall/profile.lua: slope profiles: read from CSV, checked, split into material zones, roughened;
-- the ground height under a point and the distance to the slope.
local Interp = require("talus_util.interp")
local Rand = require("rockfall.random")
local K = require("rockfall.check")
local fail, point, hint, sorted_keys, check_keys, num = K.fail, K.point, K.hint, K.sorted_keys, K.check_keys, K.num
local rng = Rand.rng

--- Reads x,y points from a CSV file (a header line is allowed; '#' lines are comments).
local function read_csv(file)
    local f, err = io.open(file, "r")
    if not f then fail("cannot read profile '%s' (%s)", file, tostring(err)) end
    local pts, n = {}, 0
    for line in f:lines() do
        n = n + 1
        local s = line:gsub("#.*$", ""):gsub("^%s+", ""):gsub("%s+$", "")
        if s ~= "" then
            local a, b = s:match("^([^,;%s]+)[,;%s]+([^,;%s]+)")
            local x, y = tonumber(a), tonumber(b)
            if x and y then
                pts[#pts + 1] = { x, y }
            elseif #pts > 0 or not (a and b) then
                f:close()
                fail("profile '%s' line %d: expected two numbers x,y (got %q)", file, n, line)
            end -- else: the header
        end
    end
    f:close()
    return pts
end

local function check_points(pts, where)
    if type(pts) ~= "table" or #pts < 2 then
        fail("%s needs at least 2 points {x, y} (got %s)", where, type(pts) == "table" and #pts or tostring(pts))
    end
    local out = {}
    for k, p in ipairs(pts) do
        out[k] = point(p, string.format("%s point %d", where, k))
        if k > 1 then
            local q = out[k - 1]
            -- Toward +x, vertical steps allowed, no overhangs: ground(x) must be a function.
            if out[k][1] < q[1] then
                fail("%s: x must not decrease (point %d at x = %g follows x = %g); profiles run "
                    .. "toward +x without overhangs", where, k, out[k][1], q[1])
            end
            if out[k][1] == q[1] and out[k][2] == q[2] then
                fail("%s: points %d and %d coincide at (%g, %g)", where, k - 1, k, q[1], q[2])
            end
        end
    end
    return out
end

--- Height of polyline pts under x; beyond the ends, the end's height.
local function ground_at(pts, x)
    return (Interp.linear(pts, x, "clamp"))
end

--- Distance from p to the polyline.
local function polyline_distance(pts, px, py)
    local best = math.huge
    for k = 1, #pts - 1 do
        local a, b = pts[k], pts[k + 1]
        local ex, ey = b[1] - a[1], b[2] - a[2]
        local s = ((px - a[1]) * ex + (py - a[2]) * ey) / (ex * ex + ey * ey)
        s = math.max(0, math.min(1, s))
        local dx, dy = px - a[1] - s * ex, py - a[2] - s * ey
        best = math.min(best, math.sqrt(dx * dx + dy * dy))
    end
    return best
end

--- Subdivides every segment into pieces no longer than `spacing` (for roughness).
local function refine(pts, spacing)
    local out = { { pts[1][1], pts[1][2] } }
    for k = 1, #pts - 1 do
        local a, b = pts[k], pts[k + 1]
        local len = math.sqrt((b[1] - a[1]) ^ 2 + (b[2] - a[2]) ^ 2)
        local m = math.max(1, math.ceil(len / spacing - 1e-9))
        for j = 1, m do
            out[#out + 1] = { a[1] + (b[1] - a[1]) * j / m, a[2] + (b[2] - a[2]) * j / m }
        end
    end
    return out
end

--- RocFall-style roughness: every interior vertex moves along the bisector of its two segments'
--- normals (perpendicular to the slope there) by amplitude x u, u uniform in [-1, 1], so no
--- vertex moves farther than the amplitude. End points stay. Same seed, same profile.
local function roughen(pts, amplitude, seed)
    local r = rng(seed)
    local out = { { pts[1][1], pts[1][2] } }
    for k = 2, #pts - 1 do
        local a, p, b = pts[k - 1], pts[k], pts[k + 1]
        local function unit_normal(u, v)
            local tx, ty = v[1] - u[1], v[2] - u[2]
            local l = math.sqrt(tx * tx + ty * ty)
            return -ty / l, tx / l -- the left normal: upward for a profile toward +x
        end
        local n1x, n1y = unit_normal(a, p)
        local n2x, n2y = unit_normal(p, b)
        local nx, ny = n1x + n2x, n1y + n2y
        local l = math.sqrt(nx * nx + ny * ny)
        if l < 1e-12 then nx, ny = n1x, n1y else nx, ny = nx / l, ny / l end
        local off = amplitude * (2 * r:uniform() - 1)
        out[k] = { p[1] + off * nx, p[2] + off * ny }
    end
    out[#pts] = { pts[#pts][1], pts[#pts][2] }
    for k = 2, #out do
        if out[k][1] < out[k - 1][1] then
            fail("roughness amplitude %g m folds the profile near x = %g (vertices %d and %d cross); "
                .. "lower the amplitude or refine more coarsely", amplitude, out[k][1], k - 1, k)
        end
    end
    return out
end

--- Splits the profile into runs of segments of one material; inserts a vertex where a zone
--- boundary cuts a segment. Returns points and one material name per segment.
local function zone_profile(pts, zones, materials, default, where)
    local seg = {}
    if zones == nil then
        if not default then
            if #sorted_keys(materials) ~= 1 then
                fail("%s: give zones (or material = name) to say where each material is", where)
            end
            default = sorted_keys(materials)[1]
        end
        for k = 1, #pts - 1 do seg[k] = default end
        return pts, seg
    end
    if type(zones) ~= "table" or #zones == 0 then fail("%s.zones must be a non-empty list", where) end
    if type(zones[1]) == "string" then
        -- One material name per segment.
        if #zones ~= #pts - 1 then
            fail("%s.zones: %d names for %d segments (one per segment)", where, #zones, #pts - 1)
        end
        for k, z in ipairs(zones) do
            if type(z) ~= "string" or not materials[z] then
                fail("%s.zones[%d]: unknown material '%s'%s (materials: %s)", where, k, tostring(z),
                    hint(z, sorted_keys(materials)), table.concat(sorted_keys(materials), ", "))
            end
            seg[k] = z
        end
        return pts, seg
    end
    local x0, x1 = pts[1][1], pts[#pts][1]
    local list = {}
    for k, z in ipairs(zones) do
        local w = string.format("%s.zones[%d]", where, k)
        check_keys(z, { "material", "name", "x_from", "x_to" }, w)
        local mat = z.material or z.name
        if type(mat) ~= "string" or not materials[mat] then
            fail("%s: unknown material '%s'%s (materials: %s)", w, tostring(mat), hint(mat, sorted_keys(materials)),
                table.concat(sorted_keys(materials), ", "))
        end
        num(z.x_from, w .. ".x_from")
        num(z.x_to, w .. ".x_to")
        if z.x_to <= z.x_from then fail("%s: x_to (%g) must exceed x_from (%g)", w, z.x_to, z.x_from) end
        if z.x_from < x0 - 1e-9 or z.x_to > x1 + 1e-9 then
            fail("%s (material '%s', x %g..%g) lies outside the profile (x %g..%g)", w, mat, z.x_from,
                z.x_to, x0, x1)
        end
        list[#list + 1] = { mat = mat, a = z.x_from, b = z.x_to, k = k }
    end
    table.sort(list, function(u, v) return u.a < v.a end)
    for k = 2, #list do
        if list[k].a < list[k - 1].b - 1e-9 then
            fail("%s.zones[%d] and zones[%d] overlap (x %g..%g and %g..%g)", where, list[k - 1].k, list[k].k,
                list[k - 1].a, list[k - 1].b, list[k].a, list[k].b)
        end
    end
    -- Insert vertices at zone boundaries that cut a segment.
    local cuts = {}
    for _, z in ipairs(list) do cuts[#cuts + 1] = z.a; cuts[#cuts + 1] = z.b end
    local out = { pts[1] }
    for k = 1, #pts - 1 do
        local a, b = pts[k], pts[k + 1]
        local inner = {}
        for _, c in ipairs(cuts) do
            if c > a[1] + 1e-9 and c < b[1] - 1e-9 then inner[#inner + 1] = c end
        end
        table.sort(inner)
        local last = nil
        for _, c in ipairs(inner) do
            if c ~= last then
                out[#out + 1] = { c, a[2] + (b[2] - a[2]) * (c - a[1]) / (b[1] - a[1]) }
                last = c
            end
        end
        out[#out + 1] = b
    end
    for k = 1, #out - 1 do
        local a, b = out[k], out[k + 1]
        local xm = 0.5 * (a[1] + b[1])
        for _, z in ipairs(list) do
            if xm >= z.a - 1e-9 and (xm < z.b - 1e-9 or (z.b >= x1 - 1e-9 and xm <= z.b + 1e-9)) then
                seg[k] = z.mat
                break
            end
        end
        if not seg[k] then
            fail("%s: profile segment %d (x %g..%g) is in no zone", where, k, a[1], b[1])
        end
    end
    return out, seg
end

return { read_csv = read_csv, check_points = check_points, ground_at = ground_at, polyline_distance = polyline_distance, refine = refine, roughen = roughen, zone_profile = zone_profile }
