-- SPDX-License-Identifier: MIT
-- calibrate/targets.lua: the restitution wanted against impact velocity: RocFall's velocity-scaled
-- Rn, or a measured table.
local Interp = require("talus_util.interp")
local raise = require("talus_util.errors").raise

local C = {}

--- RocFall's normal restitution scaled by the impact velocity (Pfeiffer & Bowen
--- 1989): Rn(v) = rn / (1 + (v / vref)^2), rn = 0.53 (clean hard sandstone), vref = 9.144 m/s.
function C.rocfall(rn, vref)
    rn, vref = rn or 0.53, vref or 9.144
    return function(v) return rn / (1 + (v / vref) ^ 2) end
end

--- A target e(v) from a function, or from a table {{v, e}, ...} (sorted by v here; linear
--- interpolation between points; outside the table an error, since extrapolating a measured
--- restitution is a guess the caller should make explicitly).
function C.target(t)
    if type(t) == "function" then return t end
    if type(t) ~= "table" or #t < 1 then
        raise("calibrate.target: give a function e(v) or a table {{v, e}, ...}")
    end
    local pts = {}
    for i, p in ipairs(t) do
        local v, e = p[1] or p.v, p[2] or p.e
        if type(v) ~= "number" or type(e) ~= "number" then
            raise("calibrate.target: entry %d must be {v, e} numbers", i)
        end
        pts[#pts + 1] = { v, e }
    end
    table.sort(pts, function(p, q) return p[1] < q[1] end)
    return function(v)
        local e = Interp.linear(pts, v, "error")
        if not e then
            raise("calibrate.target: v = %g is outside the table [%g, %g]", v, pts[1][1], pts[#pts][1])
        end
        return e
    end
end

--- The velocities of a table target, or the given list.
function C.velocities_of(spec)
    if spec.velocities then return spec.velocities end
    if type(spec.target) == "table" then
        local vs = {}
        for _, p in ipairs(spec.target) do vs[#vs + 1] = p[1] or p.v end
        table.sort(vs)
        return vs
    end
    raise("calibrate: give 'velocities' (the target is a function)")
end

return C
