-- SPDX-License-Identifier: MIT
-- rockfall/monte_carlo.lua: the rocks of an analysis run independently on all cores (talus.map), n of
-- them or until named statistics are known to a stated precision; report.lua writes them.
local Rand = require("rockfall.random")
local fnv1a = require("talus_util.random").fnv1a
local An = require("rockfall.analysis")
local Run = require("rockfall.run")
local K = require("rockfall.check")
local Precision = require("rockfall.precision")
local Report = require("rockfall.report")
local Seq = require("talus_util.sequential")

-- The library's version: part of a checkpoint's key (rockfall.version).
local VERSION = "1.1"
local fail, check_keys, need_analysis, check_hook = K.fail, K.check_keys, K.need_analysis, K.check_hook
local rock_seed = Rand.rock_seed
local describe = An.describe
local run_rock = Run.run_rock

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

--- The checkpoint key of an analysis: a rerun takes only rocks stored with the same key.
local function checkpoint_key(an, keep)
    return "rockfall " .. VERSION .. " talus " .. tostring(talus.version) .. " "
        .. fnv1a(table.concat(canonical(an, {}))) .. " paths " .. keep
end

--- Runs rocks first..last (talus.map when present, else in this process); returns the records
--- of those that ran, in rock order, and the failed ones ({rock =, seed =, message =}).
--- `dir` and `key`: the checkpoint (nil: none).
local function map_rocks(an, first, last, opts, keep, dir, key)
    local run = function(k)
        local i = first + k - 1
        return run_rock(an, i, { trajectory = i <= keep, on_model = opts.on_model, on_end = opts.on_end })
    end
    local count = last - first + 1
    local results
    if talus.map then
        results = talus.map(count, run, { jobs = opts.jobs, checkpoint = dir, key = dir and key or nil })
    else
        results = serial_map(count, run)
    end
    local records, failed = {}, {}
    for k = 1, count do
        if results[k] ~= nil then records[#records + 1] = results[k] end
    end
    for _, f in ipairs(results.failed or {}) do
        local i = first + f.index - 1
        failed[#failed + 1] = { rock = i, seed = rock_seed(an.seed, i), message = f.message }
    end
    return records, failed
end

--- Rocks in batches over talus.map until the statistics of opts.precision are known to their
--- half-widths (talus_util.sequential: looks at n, 2n, 4n, ... up to max_n, each interval at
--- level 1 - (1 - confidence) / looks). Each batch has its own checkpoint, so a rerun replays
--- the same batches. Returns the records, the failed rocks and the sequential result.
local function until_precise(an, opts, keep, key)
    local targets = Precision.check(opts.precision, an)
    local max_n = opts.max_n or 20000
    if math.type(max_n) ~= "integer" or max_n < 1 then
        fail("monte_carlo: max_n must be an integer >= 1 (got %s)", tostring(max_n))
    end
    local first = math.min(opts.n or 100, max_n)
    local growth = opts.growth or 2
    if type(growth) ~= "number" or growth <= 1 then fail("monte_carlo: growth must be a number > 1") end
    local level = opts.confidence or 0.95
    if type(level) ~= "number" or not (level > 0 and level < 1) then
        fail("monte_carlo: confidence must be a level in (0, 1) (got %s)", tostring(level))
    end
    local desc = describe(an)
    local records, failed = {}, {}
    local seq_targets = {}
    for i, t in ipairs(targets) do
        seq_targets[i] = { within = t.within,
            estimate = function(level) return Precision.estimate(t, records, desc, level) end }
    end
    local seq = Seq.run{ schedule = Seq.schedule(first, max_n, growth), level = level,
        targets = seq_targets,
        more = function(a, b)
            local dir = opts.outdir and opts.resume ~= false
                and string.format("%s/checkpoint/rocks_%d-%d", opts.outdir, a, b) or nil
            local recs, fails = map_rocks(an, a, b, opts, keep, dir, key .. " rocks " .. a .. "-" .. b)
            for _, r in ipairs(recs) do records[#records + 1] = r end
            for _, f in ipairs(fails) do failed[#failed + 1] = f end
        end }
    seq.targets, seq.confidence = targets, level
    return records, failed, seq
end

--- Runs the analysis' rocks independently (talus.map when present: all cores, MPI ranks),
--- writes the CSVs on rank 0, then the statistics of rockfall_stats when that module exists.
--- opts: n, outdir, jobs, impacts (bool), trajectories (bool, or a number of rocks to keep
--- paths of: the first k), quiet, stats, on_model / on_end (run_rock's hooks, called in the
--- process that runs the rock), resume (default true with an outdir: rocks a previous run of
--- the same analysis wrote are taken from outdir/checkpoint, not run again); precision (a list
--- of targets: run until each is known to its half-width; n is then the first batch, default
--- 100), max_n (20000), growth (2), confidence (0.95) (docs/rockfall.md, "Rockfall by the
--- answer").
--- A rock that fails (an error in its run or in a hook) is recorded in info.failed ({rock =,
--- seed =, message =}) and in outdir/rock_failed.csv; the others go on. Returns the records of
--- the rocks that ran, in rock order, and info.
local function monte_carlo(an, opts)
    need_analysis(an)
    opts = opts or {}
    check_keys(opts, { "n", "outdir", "jobs", "impacts", "trajectories", "quiet", "stats", "on_model",
        "on_end", "resume", "precision", "max_n", "growth", "confidence" }, "monte_carlo options")
    check_hook(opts, "on_model", "monte_carlo options")
    check_hook(opts, "on_end", "monte_carlo options")
    local n = opts.n or (opts.precision and 100) or an.n
    if math.type(n) ~= "integer" or n < 1 then fail("monte_carlo: n must be an integer >= 1 (got %s)", tostring(n)) end
    if not opts.precision then
        for _, k in ipairs({ "max_n", "growth", "confidence" }) do
            if opts[k] ~= nil then fail("monte_carlo: %s goes with precision", k) end
        end
    end
    local traj = opts.trajectories
    local keep = traj == true and (opts.precision and math.maxinteger or n) or (type(traj) == "number" and traj or 0)
    local clock = os.clock()
    -- Each finished rock is kept on disk at once; the key ties it to this analysis, so a changed
    -- analysis in the same outdir runs every rock again.
    local key = checkpoint_key(an, traj == true and (opts.precision and "all" or n) or keep)
    local records, failed, seq
    if opts.precision then
        records, failed, seq = until_precise(an, opts, keep, key)
        n = seq.n
    else
        local dir = opts.outdir and opts.resume ~= false and opts.outdir .. "/checkpoint" or nil
        records, failed = map_rocks(an, 1, n, opts, keep, dir, key)
    end
    local info = { cpu = os.clock() - clock, files = {}, parallel = talus.map ~= nil,
        failed = #failed > 0 and failed or nil, precision = seq, n = n }
    Report.finish(an, opts, records, info, keep)
    return records, info
end

return { monte_carlo = monte_carlo, VERSION = VERSION }
