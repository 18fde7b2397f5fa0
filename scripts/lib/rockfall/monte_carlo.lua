-- SPDX-License-Identifier: MIT
-- rockfall/monte_carlo.lua: the rocks of an analysis run independently on all cores (talus.map), written and
-- summed up.
local Rand = require("rockfall.random")
local fnv1a = require("talus_util.random").fnv1a
local An = require("rockfall.analysis")
local Run = require("rockfall.run")
local Out = require("rockfall.output")
local K = require("rockfall.check")

-- The library's version: part of a checkpoint's key (rockfall.version).
local VERSION = "1.0"
local fail, check_keys, need_analysis, check_hook = K.fail, K.check_keys, K.need_analysis, K.check_hook
local rock_seed = Rand.rock_seed
local describe = An.describe
local run_rock = Run.run_rock
local write_rows, write_csv = Out.write_rows, Out.write_csv

local function serial_map(n, fn)
    local r = {}
    for i = 1, n do r[i] = fn(i) end
    return r
end

--- A fixed text of a plain value (keys sorted, numbers exact): the analysis' fingerprint.
local function canonical(v, out)
    local t = type(v)
    if t == "table" then
        local keys = {}
        for k in pairs(v) do keys[#keys + 1] = k end
        table.sort(keys, function(a, b)
            if type(a) ~= type(b) then return type(a) < type(b) end
            return a < b
        end)
        out[#out + 1] = "{"
        for _, k in ipairs(keys) do
            canonical(k, out)
            out[#out + 1] = "="
            canonical(v[k], out)
            out[#out + 1] = ";"
        end
        out[#out + 1] = "}"
    elseif t == "number" then
        out[#out + 1] = math.type(v) == "integer" and string.format("%d", v) or string.format("%a", v)
    else
        out[#out + 1] = t:sub(1, 1) .. tostring(v)
    end
    return out
end

--- Runs the analysis' rocks independently (talus.map when present: all cores, MPI ranks),
--- writes the CSVs on rank 0, then the statistics of rockfall_stats when that module exists.
--- opts: n, outdir, jobs, impacts (bool), trajectories (bool, or a number of rocks to keep
--- paths of: the first k), quiet, stats, on_model / on_end (run_rock's hooks, called in the
--- process that runs the rock), resume (default true with an outdir: rocks a previous run of
--- the same analysis wrote are taken from outdir/checkpoint, not run again).
--- A rock that fails (an error in its run or in a hook) is recorded in info.failed ({rock =,
--- seed =, message =}) and in outdir/rock_failed.csv; the others go on. Returns the records of
--- the rocks that ran, in rock order, and info.
local function monte_carlo(an, opts)
    need_analysis(an)
    opts = opts or {}
    check_keys(opts, { "n", "outdir", "jobs", "impacts", "trajectories", "quiet", "stats", "on_model",
        "on_end", "resume" }, "monte_carlo options")
    check_hook(opts, "on_model", "monte_carlo options")
    check_hook(opts, "on_end", "monte_carlo options")
    local n = opts.n or an.n
    if math.type(n) ~= "integer" or n < 1 then fail("monte_carlo: n must be an integer >= 1 (got %s)", tostring(n)) end
    local traj = opts.trajectories
    local keep = traj == true and n or (type(traj) == "number" and traj or 0)
    local clock = os.clock()
    local run = function(i)
        return run_rock(an, i, { trajectory = i <= keep, on_model = opts.on_model, on_end = opts.on_end })
    end
    local results
    if talus.map then
        local mopts = { jobs = opts.jobs }
        if opts.outdir and opts.resume ~= false then
            -- Each finished rock is kept on disk at once; the key ties it to this analysis, so a
            -- changed analysis in the same outdir runs every rock again.
            mopts.checkpoint = opts.outdir .. "/checkpoint"
            mopts.key = "rockfall " .. VERSION .. " talus " .. tostring(talus.version) .. " "
                .. fnv1a(table.concat(canonical(an, {})))
                .. " paths " .. keep
        end
        results = talus.map(n, run, mopts)
    else
        results = serial_map(n, run)
    end
    local cpu = os.clock() - clock
    -- The rocks that ran, in order; the failed ones with their seeds.
    local records, failed = {}, nil
    for i = 1, n do
        if results[i] ~= nil then records[#records + 1] = results[i] end
    end
    if results.failed then
        failed = {}
        for k, f in ipairs(results.failed) do
            failed[k] = { rock = f.index, seed = rock_seed(an.seed, f.index), message = f.message }
        end
    end
    local rank = talus.rank and talus.rank() or 0
    local info = { cpu = cpu, files = {}, parallel = talus.map ~= nil, failed = failed }
    if failed and not opts.quiet and rank == 0 then
        print(string.format("rockfall: %d of %d rocks failed; the first, rock %d (seed %d): %s%s", #failed, n,
            failed[1].rock, failed[1].seed, failed[1].message,
            opts.outdir and "; all in " .. opts.outdir .. "/rock_failed.csv; a rerun into the same outdir runs "
                .. "only the rocks not written" or ""))
    end
    if opts.outdir and rank == 0 then
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
        if opts.stats ~= false then
            local ok, stats = pcall(require, "rockfall.stats")
            if ok and type(stats) == "table" and stats.write then
                local summary = stats.write(records, describe(an), opts.outdir)
                info.stats, info.summary = true, summary
                info.apex, info.shadow_note = summary.apex, summary.shadow_note
                info.no_apex, info.shadow_warning = summary.no_apex, summary.shadow_warning
                if not opts.quiet then
                    -- The apex decides every shadow angle: say which one was used.
                    local a = summary.apex
                    print(a and string.format("rockfall: shadow angles from the apex (%.4g, %.4g): %s",
                        a.x, a.y, a.rule)
                        or "rockfall: no shadow angles: " .. tostring(summary.no_apex)
                            .. "; give shadow_apex = {x, y} if there is a talus apex")
                    if summary.shadow_note then print("rockfall: note: " .. summary.shadow_note) end
                    if summary.shadow_warning then print("rockfall: warning: " .. summary.shadow_warning) end
                    local toe = summary.retention and summary.retention.toe
                    if toe then
                        print(string.format("rockfall: catchment retention from the toe x = %.4g: %s", toe.x,
                            toe.rule))
                    end
                end
            elseif not opts.quiet then
                print("rockfall: statistics module rockfall_stats not found; wrote per-rock CSVs only")
            end
        end
    end
    return records, info
end

return { monte_carlo = monte_carlo, VERSION = VERSION }
