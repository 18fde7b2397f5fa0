-- SPDX-License-Identifier: MIT
-- rockfall/stats/envelopes.lua: bounce heights and energies along the slope, bin by bin.
local S = require("talus_util.stats")
local M = require("rockfall.stats.defaults")
local R = require("rockfall.stats.records")
local NaN = 0 / 0
local isnum = S.isnum
local fail, check_records, envelope_of = R.fail, R.check_records, R.envelope_of

--- Value of a sparse per-bin table (integer keys; string keys accepted, should a transport
--- turn them into strings).
local function bin_value(t, k)
    if type(t) ~= "table" then return nil end
    local v = t[k]
    if v == nil then v = t[tostring(k)] end
    return v
end

--- Envelopes along x (analysis.envelope = {x0, x1, dx}): per bin k, over the rocks that have
--- an entry env_height[k] or env_ke[k] (the rocks that reached the bin), the count and
--- describe() of the bounce heights and of the total kinetic energies. opts: confidence,
--- quantiles (default M.QUANTILES). Returns { confidence, n = N, bins = {{k, x_lo, x_hi, x_mid,
--- n, reach, height = describe, ke = describe}} }.
function M.envelopes(records, analysis, opts)
    local where = "envelopes"
    opts = opts or {}
    check_records(records, where)
    if not (analysis and analysis.envelope) then
        fail(where, "analysis.envelope = {x0 =, x1 =, dx =} is required")
    end
    local x0, dx, K = envelope_of(analysis.envelope, where)
    local level = opts.confidence or analysis.confidence or M.CONFIDENCE
    local probs = opts.quantiles or M.QUANTILES
    local N = #records
    local res = { confidence = level, n = N, bins = {} }
    for k = 1, K do
        local h, e, n = {}, {}, 0
        for _, r in ipairs(records) do
            local vh, ve = bin_value(r.env_height, k), bin_value(r.env_ke, k)
            if vh ~= nil or ve ~= nil then n = n + 1 end
            if isnum(vh) then h[#h + 1] = vh end
            if isnum(ve) then e[#e + 1] = ve end
        end
        local xl = x0 + (k - 1) * dx
        res.bins[k] = { k = k, x_lo = xl, x_hi = xl + dx, x_mid = xl + dx / 2, n = n,
            reach = N > 0 and n / N or NaN, height = S.describe(h, probs, level),
            ke = S.describe(e, probs, level) }
    end
    return res
end

return M
