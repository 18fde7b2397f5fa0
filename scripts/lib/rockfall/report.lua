-- SPDX-License-Identifier: MIT
-- rockfall/report.lua: what a Monte Carlo writes and says once its rocks ran: the per-rock CSVs, the
-- failed rocks, the statistics (rockfall.stats), the precision reached, and the notes a user
-- must read (the shadow apex, the toe, failures).
local Out = require("rockfall.output")
local An = require("rockfall.analysis")
local write_rows, write_csv = Out.write_rows, Out.write_csv

local function say(opts, rank, fmt, ...)
    if not opts.quiet and rank == 0 then print(string.format(fmt, ...)) end
end

--- The precision reached, printed: "rockfall: 95 % run-out 52 m [52, 55.34], +-1.67 m (wanted
--- +-2 m)", then how many rocks and looks it took.
local function print_precision(seq, opts, rank)
    local last = seq.history[#seq.history]
    for i, t in ipairs(seq.targets) do
        local e, unit = last.estimates[i], t.unit ~= "" and " " .. t.unit or ""
        say(opts, rank, "rockfall: %s %.4g%s [%.4g, %.4g], +-%.3g%s (wanted +-%g%s)%s", t.label, e.value, unit,
            e.lo, e.hi, e.half, unit, t.within, unit, e.met and "" or ": NOT reached")
    end
    say(opts, rank, "rockfall: %s after %d rocks in %d looks (each interval at %.4g %% confidence, so that "
        .. "stopping at the first look that has them keeps %g %%)", seq.met and "known" or "max_n reached",
        seq.n, seq.looks, 100 * seq.level, 100 * seq.confidence)
end

--- precision.csv: one row per look and target.
local function write_precision(seq, outdir)
    local rows = {}
    for _, look in ipairs(seq.history) do
        for i, e in ipairs(look.estimates) do
            local t = seq.targets[i]
            rows[#rows + 1] = { look.look, look.n, t.label, e.value, e.lo, e.hi, e.half, t.within, e.met,
                seq.level }
        end
    end
    local file = outdir .. "/precision.csv"
    write_rows(file, { "look", "rocks", "statistic", "value", "ci_lo", "ci_hi", "half_width", "within", "met",
        "level" }, rows)
    return file
end

--- The statistics (rockfall.stats) and the notes about them.
local function write_stats(an, opts, records, info, rank)
    local ok, stats = pcall(require, "rockfall.stats")
    if not (ok and type(stats) == "table" and stats.write) then
        say(opts, rank, "rockfall: statistics module rockfall_stats not found; wrote per-rock CSVs only")
        return
    end
    local summary = stats.write(records, An.describe(an), opts.outdir)
    info.stats, info.summary = true, summary
    info.apex, info.shadow_note = summary.apex, summary.shadow_note
    info.no_apex, info.shadow_warning = summary.no_apex, summary.shadow_warning
    -- The apex decides every shadow angle: say which one was used.
    local a = summary.apex
    if a then
        say(opts, rank, "rockfall: shadow angles from the apex (%.4g, %.4g): %s", a.x, a.y, a.rule)
    else
        say(opts, rank, "rockfall: no shadow angles: %s; give shadow_apex = {x, y} if there is a talus apex",
            tostring(summary.no_apex))
    end
    if summary.shadow_note then say(opts, rank, "rockfall: note: %s", summary.shadow_note) end
    if summary.shadow_warning then say(opts, rank, "rockfall: warning: %s", summary.shadow_warning) end
    local toe = summary.retention and summary.retention.toe
    if toe then say(opts, rank, "rockfall: catchment retention from the toe x = %.4g: %s", toe.x, toe.rule) end
end

--- After the rocks: says what failed and the precision reached, and on rank 0 with an outdir
--- writes the per-rock CSVs, rock_failed.csv, precision.csv and the statistics. Fills info.files.
local function finish(an, opts, records, info, keep)
    local rank = talus.rank and talus.rank() or 0
    local failed = info.failed
    if failed then
        say(opts, rank, "rockfall: %d of %d rocks failed; the first, rock %d (seed %d): %s%s", #failed, info.n,
            failed[1].rock, failed[1].seed, failed[1].message,
            opts.outdir and "; all in " .. opts.outdir .. "/rock_failed.csv; a rerun into the same outdir runs "
                .. "only the rocks not written" or "")
    end
    if info.precision then print_precision(info.precision, opts, rank) end
    if not opts.outdir or rank ~= 0 then return end
    info.files = write_csv(records, an, opts.outdir, { impacts = opts.impacts, trajectories = keep > 0 })
    local rows = {}
    for k, f in ipairs(failed or {}) do rows[k] = { f.rock, f.seed, f.message } end
    local file = opts.outdir .. "/rock_failed.csv"
    if #rows > 0 then
        write_rows(file, { "rock", "seed", "message" }, rows)
        info.files[#info.files + 1] = file
    else
        os.remove(file) -- from an earlier run whose failed rocks ran now
    end
    if info.precision then
        info.files[#info.files + 1] = write_precision(info.precision, opts.outdir)
    else
        os.remove(opts.outdir .. "/precision.csv") -- from an earlier run asked for a precision
    end
    if opts.stats ~= false then write_stats(an, opts, records, info, rank) end
end

return { finish = finish }
