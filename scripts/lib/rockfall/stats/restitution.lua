-- SPDX-License-Identifier: MIT
-- rockfall/stats/restitution.lua: the apparent normal restitution of the impacts, per slope material
-- and rock shape. A rock that is not a disk hits on a corner away from its centroid, and the
-- impulse there turns translation into rotation and back, so its apparent Rn (the centroid's
-- normal velocity after / before) is not the material's Rn (docs/rockfall.md, "Rn of rocks that
-- are not disks").
local S = require("talus_util.stats")
local M = require("rockfall.stats.defaults")
local R = require("rockfall.stats.records")
local NaN = 0 / 0
local isnum = S.isnum
local check_records = R.check_records

--- Apparent Rn (impact.rn = |vn_out / vn_in|) per material and shape, over the impacts that
--- ended (an impact open when the rock ended has no rebound). opts: confidence, percentiles
--- (default M.RESTITUTION_PERCENTILES). analysis.materials = {name = {rn =}} gives the
--- nominal Rn of a material (a disk's, head on) for the table. Returns a list, sorted by
--- material then shape, of { material, shape, nominal, stats = describe(rn), above_1 (the
--- share above 1: rotation turned into normal velocity) }.
function M.restitution(records, analysis, opts)
    opts, analysis = opts or {}, analysis or {}
    check_records(records, "restitution")
    local level = opts.confidence or analysis.confidence or M.CONFIDENCE
    local groups, keys = {}, {}
    for _, r in ipairs(records) do
        local shape = tostring(r.shape or "rock")
        for _, im in ipairs(r.impacts or {}) do
            if isnum(im.rn) and im.ended ~= false then
                local key = tostring(im.material) .. "\0" .. shape
                local g = groups[key]
                if not g then
                    g = { material = tostring(im.material), shape = shape, rn = {} }
                    groups[key], keys[#keys + 1] = g, key
                end
                g.rn[#g.rn + 1] = im.rn
            end
        end
    end
    table.sort(keys)
    local out = {}
    for i, key in ipairs(keys) do
        local g = groups[key]
        local above = 0
        for _, v in ipairs(g.rn) do if v > 1 then above = above + 1 end end
        local mat = type(analysis.materials) == "table" and analysis.materials[g.material]
        out[i] = { material = g.material, shape = g.shape,
            nominal = type(mat) == "table" and isnum(mat.rn) and mat.rn or NaN,
            stats = S.describe(g.rn, opts.percentiles or M.RESTITUTION_PERCENTILES, level),
            above_1 = above / #g.rn }
    end
    return out
end

return M
