-- SPDX-License-Identifier: MIT
-- rockfall/stats/summary.lua: the summary returned by write, printed as readable lines.
local M = require("rockfall.stats.defaults")

local function g(x) return x ~= x and "-" or string.format("%.4g", x) end
local function fmt_ci(v, lo, hi)
    return string.format("%s [%s, %s]", g(v), g(lo), g(hi))
end

--- Prints the summary returned by write() (readable lines; the same numbers as summary.csv).
function M.print_summary(summary, print_fn)
    local p = print_fn or print
    local s = summary
    p(string.format("rockfall statistics: %d rocks, intervals at %g %% confidence", s.n,
        100 * s.confidence))
    local st = {}
    for _, rule in ipairs(M.STOP_RULES) do st[#st + 1] = rule .. " " .. (s.stops[rule] or 0) end
    for rule, c in pairs(s.stops) do
        local known = false
        for _, r in ipairs(M.STOP_RULES) do known = known or r == rule end
        if not known then st[#st + 1] = rule .. " " .. c end
    end
    p("  stopped by: " .. table.concat(st, ", "))
    local pc = {}
    for _, q in ipairs(s.percentiles) do pc[#pc + 1] = q.name .. " " .. fmt_ci(q.x, q.lo, q.hi) end
    p("  end point x: " .. table.concat(pc, "; "))
    for _, kind in ipairs({ "energy_line", "shadow" }) do
        local a = s[kind]
        local parts = { string.format("%d rocks, min %s", a.n, g(a.min)) }
        for _, q in ipairs(a.q) do
            parts[#parts + 1] = q.name .. " " .. fmt_ci(q.value, q.lo, q.hi)
        end
        local extra = ""
        if kind == "shadow" then
            extra = s.apex
                and string.format(" (apex %.4g, %.4g: %s)", s.apex.x, s.apex.y, s.apex.rule)
                or " (no apex: " .. tostring(s.no_apex) .. ")"
        end
        p(string.format("  %s angle [deg]%s: %s", kind == "shadow" and "shadow" or "energy-line",
            extra, table.concat(parts, "; ")))
        if kind == "shadow" and s.shadow_note then p("    note: " .. s.shadow_note) end
        if kind == "shadow" and s.shadow_warning then p("    warning: " .. s.shadow_warning) end
    end
    for _, c in ipairs(s.collectors) do
        p(string.format("  collector %s: %d rocks crossed (%s), ke q95 %s J, max %s J; "
            .. "height q95 %s m",
            tostring(c.name), c.rocks, g(c.fraction), fmt_ci(c.stats.ke.q95, c.stats.ke.q95_lo,
                c.stats.ke.q95_hi), g(c.stats.ke.max), fmt_ci(c.stats.height.q95,
                c.stats.height.q95_lo, c.stats.height.q95_hi)))
    end
    for _, b in ipairs(s.barriers) do
        p(string.format("  barrier %s: %d stopped, %d passed, %d not reached; impact energy "
            .. "q95 %s J, max %s J",
            tostring(b.name), b.stopped, b.passed, b.not_reached, fmt_ci(b.stats.energy.q95,
                b.stats.energy.q95_lo, b.stats.energy.q95_hi), g(b.stats.energy.max)))
    end
    local ret = s.retention
    if ret then
        local parts = {}
        for _, w in ipairs(ret.widths) do
            parts[#parts + 1] = string.format("%g %% within %s m", 100 * w.p, fmt_ci(w.width, w.lo, w.hi))
        end
        p(string.format("  catchment retention from the toe x = %.4g: %s", ret.toe.x,
            table.concat(parts, "; ")))
        for _, c in ipairs(ret.catchments) do
            p(string.format("  catchment %s (x %.4g..%.4g): retained %s of all rocks, %s of the %d "
                .. "that reached it", tostring(c.name), c.x_from, c.x_to, fmt_ci(c.fraction, c.lo, c.hi),
                fmt_ci(c.of_reached, c.of_reached_lo, c.of_reached_hi), c.reached))
        end
    end
    local by_material, order = {}, {}
    for _, grp in ipairs(s.restitution or {}) do
        if not by_material[grp.material] then
            by_material[grp.material] = {}
            order[#order + 1] = grp
        end
        local st = grp.stats
        table.insert(by_material[grp.material], string.format("%s median %s (%d impacts, %.0f %% above 1)",
            grp.shape, fmt_ci(st.median, st.median_lo, st.median_hi), st.n, 100 * grp.above_1))
    end
    for _, grp in ipairs(order) do
        p(string.format("  apparent Rn on %s (a disk's: %s): %s", grp.material, g(grp.nominal),
            table.concat(by_material[grp.material], "; ")))
    end
    if #s.files > 0 then p("  wrote " .. #s.files .. " files in " .. tostring(s.outdir)) end
end

return M
