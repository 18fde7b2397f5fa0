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

--- The statistics of each line of one kind (the analysis' spec.list, plus names met only in
--- the records): spec.entry(name, x, events, firsts, N, level) gives its counts, and
--- describe() of each of spec.quantities over each rock's FIRST event on the line (the records
--- keep the events in spec.field, the line's name in spec.key; spec.value(q, v) maps a value).
local function per_line(records, analysis, opts, spec)
    opts = opts or {}
    check_records(records, spec.where)
    local level = opts.confidence or (analysis and analysis.confidence) or M.CONFIDENCE
    local probs = opts.quantiles or M.QUANTILES
    local N = #records
    local names, xs = names_of(analysis and analysis[spec.list], records, spec.field, spec.key)
    local res = {}
    for i, name in ipairs(names) do
        local events, firsts = first_events(records, spec.field, spec.key, name)
        local c = spec.entry(name, xs[name] or NaN, events, firsts, N, level)
        c.stats = {}
        for _, q in ipairs(spec.quantities) do
            local vals = {}
            for _, f in ipairs(firsts) do vals[#vals + 1] = spec.value(q, f.e[q]) end
            c.stats[q] = S.describe(vals, probs, level)
        end
        res[i] = c
    end
    return res
end

--- Per collector (analysis.collectors, plus lines met only in the records): crossings (all
--- events), rocks (distinct rocks), fraction = rocks / N, and describe() of height, ke_trans,
--- ke_rot, ke, v and spin (|spin|, rad/s) over each rock's FIRST crossing of the line.
function M.collectors(records, analysis, opts)
    return per_line(records, analysis, opts, {
        where = "collectors", list = "collectors", field = "crossings", key = "line",
        quantities = M.COLLECTOR_QUANTITIES,
        value = function(q, v)
            if q == "spin" and isnum(v) then return math.abs(v) end
            return v
        end,
        entry = function(name, x, events, firsts, N, level)
            local c = { name = name, x = x, crossings = events, rocks = #firsts,
                fraction = N > 0 and #firsts / N or NaN }
            c.lo, c.hi = S.wilson(#firsts, N, level)
            return c
        end,
    })
end

--- Rocks of `firsts` whose impacts on barrier `name` include one flagged stopped.
local function stopped_at(firsts, name)
    local stopped = 0
    for _, f in ipairs(firsts) do
        for _, e in ipairs(f.rec.barrier) do
            if e.name == name and e.stopped then
                stopped = stopped + 1
                break
            end
        end
    end
    return stopped
end

--- Per barrier (analysis.barriers, plus names met only in the records): rocks = distinct rocks
--- with an impact, stopped = rocks with an impact flagged stopped, passed = rocks - stopped,
--- not_reached = N - rocks, impacts = all events, and describe() of energy, height and angle
--- over each rock's FIRST impact on the barrier.
function M.barriers(records, analysis, opts)
    return per_line(records, analysis, opts, {
        where = "barriers", list = "barriers", field = "barrier", key = "name",
        quantities = M.BARRIER_QUANTITIES,
        value = function(_, v) return v end,
        entry = function(name, x, events, firsts, N)
            local stopped = stopped_at(firsts, name)
            return { name = name, x = x, impacts = events, rocks = #firsts,
                stopped = stopped, passed = #firsts - stopped, not_reached = N - #firsts,
                fraction_stopped = N > 0 and stopped / N or NaN,
                fraction_passed = N > 0 and (#firsts - stopped) / N or NaN }
        end,
    })
end

return M
