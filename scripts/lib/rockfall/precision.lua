-- SPDX-License-Identifier: MIT
-- rockfall/precision.lua: the statistics a Monte Carlo can be asked to know to a stated precision
-- (monte_carlo{precision = ...}): each target checked against the analysis, and its estimate with
-- a confidence interval at a given level, from the records so far.
local Stats = require("rockfall.stats")
local K = require("rockfall.check")
local fail, check_keys, num = K.fail, K.check_keys, K.num

-- stat = {the keys it takes besides stat and within, a label}
local KINDS = {
    run_out = { keys = { "p" } },
    reach = { keys = { "x" } },
    barrier_energy = { keys = { "barrier", "p" } },
    collector_energy = { keys = { "collector", "p" } },
    retention = { keys = { "distance" } },
}
local KIND_NAMES = { "barrier_energy", "collector_energy", "reach", "retention", "run_out" }

local function named(list, name, what, where)
    for _, l in ipairs(list) do if l.name == name then return l end end
    local names = {}
    for _, l in ipairs(list) do names[#names + 1] = l.name end
    fail("%s.%s: no %s '%s' in the analysis (%s)", where, what, what, tostring(name),
        #names > 0 and "known: " .. table.concat(names, ", ") or "it has none")
end

--- The targets of monte_carlo's `precision` option, checked: a list of {stat =, within =, ...}.
--- Returns them with a label ("95 % run-out") and a unit.
local function check(list, an)
    local W = "monte_carlo options.precision"
    if type(list) ~= "table" or #list == 0 then
        fail("%s must be a list of targets, e.g. { { stat = \"run_out\", p = 0.95, within = 2 } }", W)
    end
    local out = {}
    for i, t in ipairs(list) do
        local w = string.format("%s[%d]", W, i)
        if type(t) ~= "table" then fail("%s must be a table", w) end
        local kind = KINDS[t.stat]
        if not kind then
            fail("%s.stat must be one of %s (got %s)%s", w, table.concat(KIND_NAMES, ", "), tostring(t.stat),
                type(t.stat) == "string" and K.hint(t.stat, KIND_NAMES) or "")
        end
        local keys = { "stat", "within" }
        for _, k in ipairs(kind.keys) do keys[#keys + 1] = k end
        check_keys(t, keys, w)
        local c = { stat = t.stat, within = num(t.within, w .. ".within", 0) }
        if t.within <= 0 then fail("%s.within must be > 0 (the half-width wanted)", w) end
        if t.p ~= nil or t.stat == "run_out" or t.stat:find("_energy$") then
            c.p = num(t.p, w .. ".p", 0, 1)
            if c.p <= 0 or c.p >= 1 then fail("%s.p must be in (0, 1) (got %g)", w, c.p) end
        end
        local pct = c.p and string.format("%g %%", 100 * c.p)
        if t.stat == "run_out" then
            c.label, c.unit = pct .. " run-out", "m"
        elseif t.stat == "reach" then
            c.x = num(t.x, w .. ".x")
            c.label, c.unit = string.format("reach probability at x = %g m", c.x), ""
        elseif t.stat == "barrier_energy" then
            c.line = named(an.barriers, t.barrier, "barrier", w).name
            c.label, c.unit = string.format("%s impact energy at %s", pct, c.line), "J"
        elseif t.stat == "collector_energy" then
            c.line = named(an.collectors, t.collector, "collector", w).name
            c.label, c.unit = string.format("%s kinetic energy at %s", pct, c.line), "J"
        else
            c.distance = num(t.distance, w .. ".distance", 0)
            c.label, c.unit = string.format("retention within %g m of the toe", c.distance), ""
        end
        out[i] = c
    end
    return out
end

--- Target t's estimate, lo, hi from the records (at confidence `level`); desc = describe(an).
local function estimate(t, records, desc, level)
    if t.stat == "run_out" then
        local q = Stats.endpoints(records, { percentiles = { t.p }, confidence = level,
            profile = desc.profile }).percentiles[1]
        return q.x, q.lo, q.hi
    elseif t.stat == "reach" then
        local r = Stats.endpoints(records, { reach_x = { t.x }, confidence = level, profile = desc.profile,
            percentiles = {} }).reach[1]
        return r.reach, r.lo, r.hi
    elseif t.stat == "retention" then
        local c = Stats.retention(records, desc, { distances = { t.distance }, widths = {},
            confidence = level }).curve[1]
        return c.fraction, c.lo, c.hi
    end
    local lines = t.stat == "barrier_energy" and Stats.barriers(records, desc, { quantiles = { t.p }, confidence = level })
        or Stats.collectors(records, desc, { quantiles = { t.p }, confidence = level })
    for _, l in ipairs(lines) do
        if l.name == t.line then
            local q = l.stats[t.stat == "barrier_energy" and "energy" or "ke"].q[1]
            return q.value, q.lo, q.hi
        end
    end
    return 0 / 0, 0 / 0, 0 / 0
end

return { check = check, estimate = estimate }
