-- SPDX-License-Identifier: MIT
-- rockfall/stats/write.lua: every statistic computed and written as CSV files (rank 0), and the summary.
local S = require("talus_util.stats")
local M = require("rockfall.stats.defaults")
local R = require("rockfall.stats.records")
local Csv = require("talus_util.csv")
local Err = require("talus_util.errors")
-- the parts write uses, each adding its functions to M
require("rockfall.stats.endpoints")
require("rockfall.stats.envelopes")
require("rockfall.stats.lines")
require("rockfall.stats.angles")
require("rockfall.stats.retention")
require("rockfall.stats.restitution")
local NaN = 0 / 0
local direction_of, profile_points, point_xy = R.direction_of, R.profile_points, R.point_xy

-- The statistics files keep 12 significant digits (talus_util.csv's format otherwise).
local DIGITS = 12

local function write_csv(path, header, rows)
    local ok, why = Csv.write(path, header, rows, { digits = DIGITS })
    if not ok then Err.raise("rockfall_stats.write: " .. why) end
end

--- Column names and values of a describe() result, prefixed ("height_mean", ...).
local function describe_header(prefix, probs)
    local h = { prefix .. "n", prefix .. "mean", prefix .. "min", prefix .. "max" }
    for _, p in ipairs(probs) do
        local q = S.qname(p)
        h[#h + 1] = prefix .. q
        h[#h + 1] = prefix .. q .. "_lo"
        h[#h + 1] = prefix .. q .. "_hi"
    end
    return h
end
local function describe_cells(row, d)
    row[#row + 1] = d.n
    row[#row + 1] = d.mean
    row[#row + 1] = d.min
    row[#row + 1] = d.max
    for _, q in ipairs(d.q) do
        row[#row + 1] = q.value
        row[#row + 1] = q.lo
        row[#row + 1] = q.hi
    end
end

local function is_rank0()
    local t = rawget(_G, "talus")
    return ((t and t.rank and t.rank()) or 0) == 0
end

--- The summary rows of catchment retention: the toe, the widths, the named catchments.
local function retention_rows(srows, ret)
    if not ret then return end
    srows[#srows + 1] = { "retention", "toe_x", ret.toe.x }
    for _, w in ipairs(ret.widths) do
        srows[#srows + 1] = { "retention", "width_" .. w.name, w.width, w.lo, w.hi }
    end
    for _, c in ipairs(ret.catchments) do
        local sec = "catchment:" .. tostring(c.name)
        srows[#srows + 1] = { sec, "retained", c.fraction, c.lo, c.hi }
        srows[#srows + 1] = { sec, "retained_of_reached", c.of_reached, c.of_reached_lo, c.of_reached_hi }
    end
end

--- The summary rows of the apparent restitution: the median per material and shape.
local function restitution_rows(srows, rest)
    for _, g in ipairs(rest) do
        local st = g.stats
        srows[#srows + 1] = { "restitution:" .. g.material .. ":" .. g.shape, "rn_median", st.median,
            st.median_lo, st.median_hi }
    end
end

--- The summary rows (summary.csv): section, name, value, ci_lo, ci_hi.
local function summary_rows(records, ep, ang, col, bar, ret, rest)
    local srows = { { "rocks", "n", #records } }
    for _, s in ipairs(ep.stops) do srows[#srows + 1] = { "stop", s.rule, s.count } end
    for _, p in ipairs(ep.percentiles) do
        srows[#srows + 1] = { "end_x", p.name, p.x, p.lo, p.hi }
    end
    for _, kind in ipairs({ "energy_line", "shadow" }) do
        local a = ang[kind]
        srows[#srows + 1] = { kind .. "_deg", "n", a.n }
        srows[#srows + 1] = { kind .. "_deg", "min", a.min }
        for _, q in ipairs(a.q) do
            srows[#srows + 1] = { kind .. "_deg", q.name, q.value, q.lo, q.hi }
        end
    end
    for _, c in ipairs(col) do
        srows[#srows + 1] = { "collector:" .. tostring(c.name), "fraction", c.fraction, c.lo, c.hi }
        for _, q in ipairs({ "ke", "height" }) do
            local st = c.stats[q]
            srows[#srows + 1] = { "collector:" .. tostring(c.name), q .. "_q95", st.q95, st.q95_lo,
                st.q95_hi }
            srows[#srows + 1] = { "collector:" .. tostring(c.name), q .. "_max", st.max }
        end
    end
    for _, b in ipairs(bar) do
        srows[#srows + 1] = { "barrier:" .. tostring(b.name), "stopped", b.stopped }
        srows[#srows + 1] = { "barrier:" .. tostring(b.name), "passed", b.passed }
        srows[#srows + 1] = { "barrier:" .. tostring(b.name), "energy_q95", b.stats.energy.q95,
            b.stats.energy.q95_lo, b.stats.energy.q95_hi }
        srows[#srows + 1] = { "barrier:" .. tostring(b.name), "energy_max", b.stats.energy.max }
    end
    retention_rows(srows, ret)
    restitution_rows(srows, rest)
    return srows
end

--- The files of the end points: endpoints, endpoint_hist, endpoint_percentiles, stops, reach.
local function write_point_files(out, records, ep, ang)
    local rows = {}
    for i, r in ipairs(records) do
        local rx, ry = point_xy(r.release)
        rows[i] = { r.rock or i, r.seed, r.shape, r.mass, r.stop, rx, ry, r.end_x, r.end_y, r.t_end,
            ep.x_far[i], ang.per_rock[i].energy_line, ang.per_rock[i].shadow }
    end
    out("endpoints.csv", { "rock", "seed", "shape", "mass", "stop", "release_x", "release_y",
        "end_x", "end_y", "t_end", "x_far", "energy_line_deg", "shadow_deg" }, rows)

    rows = {}
    for i, b in ipairs(ep.hist.bins) do
        rows[i] = { b.k, b.x_lo, b.x_hi, b.count, b.fraction, b.cumulative }
    end
    out("endpoint_hist.csv", { "bin", "x_lo", "x_hi", "count", "fraction", "cumulative" }, rows)

    rows = {}
    for i, p in ipairs(ep.percentiles) do rows[i] = { p.p, p.x, p.lo, p.hi, p.coverage } end
    out("endpoint_percentiles.csv", { "p", "end_x", "ci_lo", "ci_hi", "coverage" }, rows)

    rows = {}
    for i, s in ipairs(ep.stops) do rows[i] = { s.rule, s.count, s.fraction } end
    out("stops.csv", { "stop", "count", "fraction" }, rows)

    rows = {}
    for i, r in ipairs(ep.reach) do rows[i] = { r.x, r.count, r.reach, r.lo, r.hi } end
    out("reach.csv", { "x", "count", "reach", "ci_lo", "ci_hi" }, rows)
end

--- The catchment files: retention.csv (the curve from the toe) and catchments.csv (named ones).
local function write_retention_files(out, ret)
    if not ret then return end
    local rows = {}
    for i, c in ipairs(ret.curve) do
        rows[i] = { c.distance, c.x, c.retained, c.fraction, c.lo, c.hi }
    end
    out("retention.csv", { "distance", "x", "retained", "fraction", "ci_lo", "ci_hi" }, rows)
    if #ret.catchments == 0 then return end
    rows = {}
    for i, c in ipairs(ret.catchments) do
        rows[i] = { c.name, c.x_from, c.x_to, ret.n, c.reached, c.retained, c.fraction, c.lo, c.hi,
            c.of_reached, c.of_reached_lo, c.of_reached_hi }
    end
    out("catchments.csv", { "catchment", "x_from", "x_to", "rocks", "reached", "retained", "fraction",
        "fraction_lo", "fraction_hi", "of_reached", "of_reached_lo", "of_reached_hi" }, rows)
end

--- restitution.csv: the apparent Rn per material and shape (when there were impacts).
local function write_restitution_file(out, rest)
    if #rest == 0 then return end
    local header = { "material", "shape", "nominal_rn" }
    for _, h in ipairs(describe_header("", M.RESTITUTION_PERCENTILES)) do header[#header + 1] = h end
    header[#header + 1] = "above_1"
    local rows = {}
    for i, g in ipairs(rest) do
        local row = { g.material, g.shape, g.nominal }
        describe_cells(row, g.stats)
        row[#row + 1] = g.above_1
        rows[i] = row
    end
    out("restitution.csv", header, rows)
end

--- The files along the slope and of the lines: envelopes (with an envelope), collectors,
--- barriers, angles.
local function write_line_files(out, env, col, bar, ang)
    local rows
    if env then
        local header = { "bin", "x_lo", "x_hi", "x_mid", "n", "reach" }
        for _, h in ipairs(describe_header("height_", M.QUANTILES)) do header[#header + 1] = h end
        for _, h in ipairs(describe_header("ke_", M.QUANTILES)) do header[#header + 1] = h end
        rows = {}
        for i, b in ipairs(env.bins) do
            local row = { b.k, b.x_lo, b.x_hi, b.x_mid, b.n, b.reach }
            describe_cells(row, b.height)
            describe_cells(row, b.ke)
            rows[i] = row
        end
        out("envelopes.csv", header, rows)
    end

    local header = { "collector", "x", "crossings", "rocks", "fraction", "fraction_lo",
        "fraction_hi", "quantity" }
    for _, h in ipairs(describe_header("", M.QUANTILES)) do header[#header + 1] = h end
    rows = {}
    for _, c in ipairs(col) do
        for _, q in ipairs(M.COLLECTOR_QUANTITIES) do
            local row = { c.name, c.x, c.crossings, c.rocks, c.fraction, c.lo, c.hi, q }
            describe_cells(row, c.stats[q])
            rows[#rows + 1] = row
        end
    end
    out("collectors.csv", header, rows)

    header = { "barrier", "x", "impacts", "rocks", "stopped", "passed", "not_reached",
        "fraction_stopped", "fraction_passed", "quantity" }
    for _, h in ipairs(describe_header("", M.QUANTILES)) do header[#header + 1] = h end
    rows = {}
    for _, b in ipairs(bar) do
        for _, q in ipairs(M.BARRIER_QUANTITIES) do
            local row = { b.name, b.x, b.impacts, b.rocks, b.stopped, b.passed, b.not_reached,
                b.fraction_stopped, b.fraction_passed, q }
            describe_cells(row, b.stats[q])
            rows[#rows + 1] = row
        end
    end
    out("barriers.csv", header, rows)

    header = { "angle", "apex_x", "apex_y", "deposited" }
    for _, h in ipairs(describe_header("", M.ANGLE_PERCENTILES)) do header[#header + 1] = h end
    header[#header + 1] = "note"
    rows = {}
    for _, kind in ipairs({ "energy_line", "shadow" }) do
        local row = { kind, kind == "shadow" and ang.apex and ang.apex.x or NaN,
            kind == "shadow" and ang.apex and ang.apex.y or NaN, ang.deposited }
        describe_cells(row, ang[kind])
        if kind == "shadow" then
            local notes = {}
            for _, t in ipairs({ ang.no_apex and "no apex: " .. ang.no_apex, ang.note, ang.warning }) do
                if t then notes[#notes + 1] = t end
            end
            row[#row + 1] = table.concat(notes, "; ")
        end
        rows[#rows + 1] = row
    end
    out("angles.csv", header, rows)
end

--- Computes everything, writes the CSV files into outdir (created if missing) on MPI rank 0
--- only, and returns the summary table (on every rank). opts: confidence, and
--- trajectories = false to skip trajectories.csv (written when records carry `path`).
--- Files (columns in docs/rockfall-statistics.md): endpoints.csv, endpoint_hist.csv,
--- endpoint_percentiles.csv, stops.csv, reach.csv, envelopes.csv (when analysis.envelope),
--- collectors.csv, barriers.csv, angles.csv, summary.csv, profile.csv (when
--- analysis.profile), trajectories.csv (when paths).
function M.write(records, analysis, outdir, opts)
    analysis = analysis or {}
    opts = opts or {}
    local level = opts.confidence or analysis.confidence or M.CONFIDENCE
    local d = direction_of(analysis, "write")
    local ep = M.endpoints(records, { confidence = level, envelope = analysis.envelope,
        direction = d, bins = opts.bins })
    local env = analysis.envelope and M.envelopes(records, analysis, { confidence = level }) or nil
    local col = M.collectors(records, analysis, { confidence = level })
    local bar = M.barriers(records, analysis, { confidence = level })
    local ang = M.angles(records, analysis, { confidence = level, deposited = opts.deposited })
    local ret = M.retention(records, analysis, { confidence = level })
    local rest = M.restitution(records, analysis, { confidence = level })

    local summary = { n = #records, confidence = level, direction = d, stops = ep.stop_count,
        percentiles = ep.percentiles, energy_line = ang.energy_line, shadow = ang.shadow,
        apex = ang.apex, no_apex = ang.no_apex, shadow_note = ang.note,
        shadow_warning = ang.warning, deposited = ang.deposited,
        beyond_apex = ang.beyond_apex,
        collectors = col, barriers = bar, retention = ret, restitution = rest, outdir = outdir,
        files = {} }

    summary.rows = summary_rows(records, ep, ang, col, bar, ret, rest)

    if not is_rank0() then return summary end
    local t = rawget(_G, "talus")
    if t and t.mkdir then
        t.mkdir(outdir)
    else
        os.execute('mkdir -p "' .. tostring(outdir):gsub('"', '\\"') .. '"')
    end
    local function out(name, header, rows)
        local path = outdir .. "/" .. name
        write_csv(path, header, rows)
        summary.files[#summary.files + 1] = path
    end

    write_point_files(out, records, ep, ang)
    write_line_files(out, env, col, bar, ang)
    write_retention_files(out, ret)
    write_restitution_file(out, rest)
    out("summary.csv", { "section", "name", "value", "ci_lo", "ci_hi" }, summary.rows)

    local pts = profile_points(analysis, "write")
    if pts then
        local rows = {}
        for i, p in ipairs(pts) do rows[i] = { p[1], p[2] } end
        out("profile.csv", { "x", "y" }, rows)
    end

    if opts.trajectories ~= false then
        local rows = {}
        for i, r in ipairs(records) do
            for _, p in ipairs(r.path or {}) do
                rows[#rows + 1] = { r.rock or i, p.t or p[1], p.x or p[2], p.y or p[3] }
            end
        end
        if #rows > 0 then out("trajectories.csv", { "rock", "t", "x", "y" }, rows) end
    end
    return summary
end

return M
