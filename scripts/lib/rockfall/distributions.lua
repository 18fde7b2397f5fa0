-- SPDX-License-Identifier: MIT
-- rockfall/distributions.lua: quantities given as a number or a distribution (uniform, normal, lognormal),
-- checked, and drawn truncated.
local K = require("rockfall.check")
local fail, check_keys, num = K.fail, K.check_keys, K.num

local DIST_KEYS = {
    uniform = { "dist", "min", "max" },
    normal = { "dist", "mean", "sd", "min", "max" },
    lognormal = { "dist", "mean", "sd", "mu", "sigma", "min", "max" },
}

--- The range a distribution is truncated to. Normal: mean -/+ 3 sd unless min/max are given
--- (0.27% of an untruncated normal lies outside; a rock with a negative mass is never drawn).
--- Lognormal: (0, inf) unless given.
local function bounds(spec)
    if type(spec) == "number" then return spec, spec end
    if spec.dist == "uniform" then return spec.min, spec.max end
    if spec.dist == "normal" then
        return spec.min or (spec.mean - 3 * spec.sd), spec.max or (spec.mean + 3 * spec.sd)
    end
    return spec.min or 0, spec.max or math.huge
end

--- Checks a quantity spec: a number (fixed) or {dist = "uniform"|"normal"|"lognormal", ...}.
local function check_dist(spec, where, lo)
    if type(spec) == "number" then return num(spec, where, lo) end
    if type(spec) ~= "table" then
        fail("%s must be a number or a distribution {dist = ...} (got %s)", where, tostring(spec))
    end
    local keys = DIST_KEYS[spec.dist]
    if not keys then
        fail("%s: dist must be \"uniform\", \"normal\" or \"lognormal\" (got %s)", where, tostring(spec.dist))
    end
    check_keys(spec, keys, where)
    if spec.dist == "uniform" then
        num(spec.min, where .. ".min")
        num(spec.max, where .. ".max")
        if spec.max < spec.min then fail("%s: max < min", where) end
        if lo and spec.min < lo then fail("%s: min must be >= %g (got %g)", where, lo, spec.min) end
    elseif spec.dist == "normal" then
        num(spec.mean, where .. ".mean")
        num(spec.sd, where .. ".sd", 0)
    else
        if spec.mu ~= nil or spec.sigma ~= nil then
            if spec.mean ~= nil or spec.sd ~= nil then
                fail("%s: give mean and sd, or mu and sigma (of log), not both", where)
            end
            num(spec.mu, where .. ".mu")
            num(spec.sigma, where .. ".sigma", 0)
        else
            num(spec.mean, where .. ".mean", 1e-300)
            num(spec.sd, where .. ".sd", 0)
        end
    end
    if spec.dist ~= "uniform" then
        if spec.min ~= nil then num(spec.min, where .. ".min") end
        if spec.max ~= nil then num(spec.max, where .. ".max") end
        local a, b = bounds(spec)
        if b < a then fail("%s: max < min", where) end
        if lo and a < lo then
            if spec.min ~= nil or spec.dist == "normal" then
                fail("%s: the distribution reaches %g, below the allowed %g (set min)", where, a, lo)
            end
        end
    end
    return spec
end

local function lognormal_params(spec)
    if spec.mu then return spec.mu, spec.sigma end
    -- Moments of the variable itself: sigma^2 = ln(1 + (sd/mean)^2), mu = ln(mean) - sigma^2/2.
    local s2 = math.log(1 + (spec.sd / spec.mean) ^ 2)
    return math.log(spec.mean) - s2 / 2, math.sqrt(s2)
end

--- One draw of a quantity spec from generator r. Truncation by rejection (at most 10000
--- tries, then an error: a window that far in the tail is an input mistake).
local function draw(spec, r)
    if type(spec) == "number" then return spec end
    if spec.dist == "uniform" then return r:range(spec.min, spec.max) end
    local a, b = bounds(spec)
    for _ = 1, 10000 do
        local v
        if spec.dist == "normal" then
            v = spec.mean + spec.sd * r:normal()
        else
            local mu, sigma = lognormal_params(spec)
            v = math.exp(mu + sigma * r:normal())
        end
        if v >= a and v <= b then return v end
    end
    fail("distribution %s: no draw fell in [%g, %g] in 10000 tries", spec.dist, a, b)
end

return { check_dist = check_dist, bounds = bounds, draw = draw }
