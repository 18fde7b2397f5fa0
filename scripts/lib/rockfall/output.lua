-- SPDX-License-Identifier: MIT
-- rockfall/output.lua: the per-rock CSV files and the text summary of a set of records.
local Csv = require("talus_util.csv")
local K = require("rockfall.check")
local fail, need_analysis, sorted_keys = K.fail, K.need_analysis, K.sorted_keys

-- The per-rock files keep 10 significant digits (talus_util.csv's format otherwise).
local DIGITS = 10

local function write_rows(file, header, rows)
    local ok, why = Csv.write(file, header, rows, { digits = DIGITS })
    if not ok then fail("%s", why) end
end

--- Writes the per-rock CSVs into outdir: rock_endpoints.csv, rock_crossings.csv,
--- rock_barriers.csv, rock_profile.csv, and when asked rock_impacts.csv and rock_paths.csv
--- (the prefix keeps them apart from the statistics files of rockfall_stats). Returns the
--- file names.
local function write_csv(records, an, outdir, opts)
    need_analysis(an)
    opts = opts or {}
    talus.mkdir(outdir)
    local files = {}
    local ends, cross, bars, imps, paths = {}, {}, {}, {}, {}
    for _, r in ipairs(records) do
        local top = -math.huge
        for _, h in pairs(r.env_height) do top = math.max(top, h) end
        ends[#ends + 1] = { r.rock, r.seed, r.shape, r.mass, r.volume, r.r_eq, r.release.x, r.release.y,
            r.release.vx, r.release.vy, r.release.spin, r.stop, r.end_x, r.end_y, r.t_end, #r.impacts,
            top > -math.huge and top or nil, r.steps }
        for _, c in ipairs(r.crossings) do
            cross[#cross + 1] = { r.rock, c.line, c.t, c.x, c.y, c.height, c.vx, c.vy, c.v, c.spin,
                c.ke_trans, c.ke_rot, c.ke }
        end
        for _, b in ipairs(r.barrier) do
            bars[#bars + 1] = { r.rock, b.name, b.stopped, b.t, b.x, b.y, b.height, b.energy, b.angle,
                b.energy_after }
        end
        for _, im in ipairs(r.impacts) do
            imps[#imps + 1] = { r.rock, im.t, im.x, im.y, im.vn_in, im.vt_in, im.vn_out, im.vt_out, im.rn,
                im.rt, im.energy_lost, im.material, im.duration }
        end
        if r.path then
            for _, p in ipairs(r.path) do paths[#paths + 1] = { r.rock, p[1], p[2], p[3] } end
        end
    end
    local function out(name, header, rows)
        local file = outdir .. "/" .. name
        write_rows(file, header, rows)
        files[#files + 1] = file
    end
    out("rock_endpoints.csv", { "rock", "seed", "shape", "mass", "volume", "r_eq", "release_x", "release_y",
        "release_vx", "release_vy", "release_spin", "stop", "end_x", "end_y", "t_end", "impacts",
        "max_height", "steps" }, ends)
    out("rock_crossings.csv", { "rock", "line", "t", "x", "y", "height", "vx", "vy", "v", "spin", "ke_trans",
        "ke_rot", "ke" }, cross)
    out("rock_barriers.csv", { "rock", "barrier", "stopped", "t", "x", "y", "height", "energy", "angle",
        "energy_after" }, bars)
    local prof = {}
    for k, p in ipairs(an.nominal) do prof[k] = { p[1], p[2], an.segment_material[k] or "" } end
    out("rock_profile.csv", { "x", "y", "material" }, prof)
    if opts.impacts then
        out("rock_impacts.csv", { "rock", "t", "x", "y", "vn_in", "vt_in", "vn_out", "vt_out", "rn", "rt",
            "energy_lost", "material", "duration" }, imps)
    end
    if opts.trajectories then out("rock_paths.csv", { "rock", "t", "x", "y" }, paths) end
    -- breakable rocks (rockfall/breakable.lua): their fragments at the end and their breakage episodes
    local Br = require("rockfall.breakable")
    local frs, brs, crs = Br.csv_rows(records)
    if frs then
        out("rock_fragments.csv", Br.FRAGMENT_HEADER, frs)
        out("rock_breakage.csv", Br.BREAKAGE_HEADER, brs)
        out("rock_fragment_crossings.csv", Br.CROSSING_HEADER, crs)
    end
    return files
end

--- A short text summary of records (counts per stop rule, run-out percentiles, barrier counts).
local function summary(records, an)
    local counts, xs, nb_stop, nb_pass = {}, {}, 0, 0
    for _, r in ipairs(records) do
        counts[r.stop] = (counts[r.stop] or 0) + 1
        xs[#xs + 1] = r.end_x
        for _, b in ipairs(r.barrier) do
            if b.stopped then nb_stop = nb_stop + 1 else nb_pass = nb_pass + 1 end
        end
    end
    table.sort(xs)
    local function q(p) return xs[math.max(1, math.min(#xs, math.ceil(p * #xs)))] end
    local parts = {}
    for _, k in ipairs(sorted_keys(counts)) do parts[#parts + 1] = k .. " " .. counts[k] end
    return string.format("%d rocks: %s; end x median %.1f m, 90%% %.1f m, 95%% %.1f m, max %.1f m; "
        .. "barrier hits: %d stopped, %d passed", #records, table.concat(parts, ", "), q(0.5), q(0.9),
        q(0.95), xs[#xs], nb_stop, nb_pass)
end

return { write_rows = write_rows, write_csv = write_csv, summary = summary }
