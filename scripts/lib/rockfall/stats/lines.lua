-- SPDX-License-Identifier: MIT
-- rockfall/stats/lines.lua: what crossed each collector and what hit each barrier.
local S = require("talus_util.stats")
local M = require("rockfall.stats.defaults")
local R = require("rockfall.stats.records")
local NaN = 0 / 0
local isnum = S.isnum
local check_records = R.check_records

--- Names in the analysis order, then names seen only in the records (order of appearance).
local function names_of(list, records, field, key)
    local names, xs, seen = {}, {}, {}
    for _, c in ipairs(list or {}) do
        if c.name ~= nil and not seen[c.name] then
            names[#names + 1] = c.name
            xs[c.name] = c.x
            seen[c.name] = true
        end
    end
    for _, r in ipairs(records) do
        for _, e in ipairs(r[field] or {}) do
            local name = e[key]
            if name ~= nil and not seen[name] then
                names[#names + 1] = name
                seen[name] = true
            end
        end
    end
    return names, xs
end

--- The first event (smallest t, else first listed) of each rock with e[key] == name.
local function first_events(records, field, key, name)
    local events, firsts = 0, {}
    for _, r in ipairs(records) do
        local first
        for _, e in ipairs(r[field] or {}) do
            if e[key] == name then
                events = events + 1
                if not first or (isnum(e.t) and isnum(first.t) and e.t < first.t) then first = e end
            end
        end
        if first then firsts[#firsts + 1] = { rec = r, e = first } end
    end
    return events, firsts
end

--- Per collector (analysis.collectors, plus lines met only in the records): crossings (all
--- events), rocks (distinct rocks), fraction = rocks / N, and describe() of height, ke_trans,
--- ke_rot, ke, v and spin (|spin|, rad/s) over each rock's FIRST crossing of the line.
function M.collectors(records, analysis, opts)
    local where = "collectors"
    opts = opts or {}
    check_records(records, where)
    local level = opts.confidence or (analysis and analysis.confidence) or M.CONFIDENCE
    local probs = opts.quantiles or M.QUANTILES
    local N = #records
    local names, xs = names_of(analysis and analysis.collectors, records, "crossings", "line")
    local res = {}
    for i, name in ipairs(names) do
        local events, firsts = first_events(records, "crossings", "line", name)
        local c = { name = name, x = xs[name] or NaN, crossings = events, rocks = #firsts,
            fraction = N > 0 and #firsts / N or NaN, stats = {} }
        c.lo, c.hi = S.wilson(#firsts, N, level)
        for _, q in ipairs(M.COLLECTOR_QUANTITIES) do
            local vals = {}
            for _, f in ipairs(firsts) do
                local v = f.e[q]
                if q == "spin" and isnum(v) then v = math.abs(v) end
                vals[#vals + 1] = v
            end
            c.stats[q] = S.describe(vals, probs, level)
        end
        res[i] = c
    end
    return res
end

--- Per barrier (analysis.barriers, plus names met only in the records): rocks = distinct rocks
--- with an impact, stopped = rocks with an impact flagged stopped, passed = rocks - stopped,
--- not_reached = N - rocks, impacts = all events, and describe() of energy, height and angle
--- over each rock's FIRST impact on the barrier.
function M.barriers(records, analysis, opts)
    local where = "barriers"
    opts = opts or {}
    check_records(records, where)
    local level = opts.confidence or (analysis and analysis.confidence) or M.CONFIDENCE
    local probs = opts.quantiles or M.QUANTILES
    local N = #records
    local names, xs = names_of(analysis and analysis.barriers, records, "barrier", "name")
    local res = {}
    for i, name in ipairs(names) do
        local events, firsts = first_events(records, "barrier", "name", name)
        local stopped = 0
        for _, f in ipairs(firsts) do
            for _, e in ipairs(f.rec.barrier) do
                if e.name == name and e.stopped then
                    stopped = stopped + 1
                    break
                end
            end
        end
        local b = { name = name, x = xs[name] or NaN, impacts = events, rocks = #firsts,
            stopped = stopped, passed = #firsts - stopped, not_reached = N - #firsts,
            fraction_stopped = N > 0 and stopped / N or NaN,
            fraction_passed = N > 0 and (#firsts - stopped) / N or NaN, stats = {} }
        for _, q in ipairs(M.BARRIER_QUANTITIES) do
            local vals = {}
            for _, f in ipairs(firsts) do vals[#vals + 1] = f.e[q] end
            b.stats[q] = S.describe(vals, probs, level)
        end
        res[i] = b
    end
    return res
end

return M
