-- SPDX-License-Identifier: MIT
-- A Monte Carlo that runs until named statistics are known to a stated precision
-- (rockfall.monte_carlo{precision = ...}, talus_util.sequential; docs/rockfall.md, "Rockfall by
-- the answer"). 1. The stopping rule on a known distribution: looks at 100, 200, 400, ...; stop
-- at the first look where the interval of the 95 % quantile (or of a probability) is narrower
-- than asked. Stopping on a narrow interval is a sequential test: with each look at the nominal
-- 95 % the interval at the stop covers less often; with each look at 1 - 0.05 / looks
-- (Bonferroni) it covers at least 95 % of the time. Checked over 2000 simulated Monte Carlos
-- against the true quantile and probability. 2. The rockfall Monte Carlo: it stops at a look,
-- its rocks are those of a plain run of that many, its batches resume from their checkpoints,
-- and what it reached is printed and written (precision.csv).
local T = require("testlib")
local Seq = require("talus_util.sequential")
local S = require("talus_util.stats")
local U = require("talus_util.random")
local rockfall = require("rockfall")

-- 1a. The schedule and the level of each look.
local sch = Seq.schedule(100, 1000)
T.check(#sch == 5 and sch[1] == 100 and sch[2] == 200 and sch[4] == 800 and sch[5] == 1000,
    "looks at 100, 200, 400, 800, 1000: " .. table.concat(sch, ", "))
T.check(#Seq.schedule(10, 10) == 1 and #Seq.schedule(3, 40, 1.5) == 8, "one look; growth 1.5")
T.near(Seq.look_level(0.95, 5), 0.99, 1e-15, "each of 5 looks at 99 %")

-- 1b. Coverage. Run-outs ~ Exponential(mean 10 m): the 95 % run-out is 10 ln 20 = 29.957 m.
-- Asked to +-6 m; each simulated Monte Carlo draws its rocks from its own stream.
local xi = 10 * math.log(20)
local function simulate(M, level_of, quantile)
    local covered, rocks = 0, 0
    for rep = 1, M do
        local rng = U.splitmix64(1000 + rep)
        local sample = {}
        local seq = Seq.run{ schedule = Seq.schedule(100, 6400), level = 0.95,
            more = function(a, b)
                for i = a, b do
                    sample[i] = quantile and -10 * math.log(rng:uniform_open())
                        or (rng:uniform() < 0.1 and 1 or 0)
                end
            end,
            targets = { { within = quantile and 6 or 0.025, estimate = function(level)
                level = level_of and level_of(level) or level
                if quantile then
                    local s = {}
                    for i, v in ipairs(sample) do s[i] = v end
                    table.sort(s)
                    local lo, hi = S.quantile_ci(s, 0.95, level)
                    return S.quantile(s, 0.95), lo, hi
                end
                local k = 0
                for _, v in ipairs(sample) do k = k + v end
                local lo, hi = S.wilson(k, #sample, level)
                return k / #sample, lo, hi
            end } } }
        local e = seq.history[seq.looks].estimates[1]
        local truth = quantile and xi or 0.1
        if seq.met and e.lo <= truth and truth <= e.hi then covered = covered + 1 end
        rocks = rocks + seq.n
    end
    return covered / M, rocks / M
end
local M = 2000
local sigma = math.sqrt(0.05 * 0.95 / M)
local cov, mean_n = simulate(M, nil, true)
local naive, naive_n = simulate(M, function() return 0.95 end, true)
print(string.format("95 %% run-out to +-6 m: coverage %.4f with each look at 1 - 0.05/looks (%.0f rocks on "
    .. "average); %.4f with each look at 95 %% (%.0f rocks)", cov, mean_n, naive, naive_n))
T.check(cov >= 0.95 - 3 * sigma, string.format("the rule keeps 95 %% coverage (%.4f)", cov))
local pcov, pn = simulate(M, nil, false)
local pnaive = simulate(M, function() return 0.95 end, false)
print(string.format("a probability of 0.1 to +-0.025: coverage %.4f (%.0f rocks on average); %.4f with each "
    .. "look at 95 %%", pcov, pn, pnaive))
T.check(pcov >= 0.95 - 3 * sigma, string.format("probability: coverage %.4f", pcov))

-- 2. The rockfall Monte Carlo, on a short slope with a fence: the reach probability at x = 30 m
-- to +-0.15 (a few looks of 8, 16, 32, ... rocks).
local function analysis()
    return rockfall.analysis{
        profile = { { 0, 10 }, { 17.32, 0 }, { 60, 0 } },
        materials = { slope = { model = "linear",
            props = { kn = 1e8, ks = 5e7, fric = 0.5, dp_nratio = rockfall.dp_nratio(0.4) } } },
        seeders = { { kind = "line", from = { 0.5, 11 }, to = { 1.5, 11 }, vx = { dist = "uniform", min = 0.5, max = 3 },
            rock = { shape = "ngon", n = 5, radius = 0.3, scale = { dist = "uniform", min = 0.7, max = 1.3 } } } },
        barriers = { { name = "fence", x = 25, energy = 2e3, height = 1.5 } },
        seed = 5, t_max = 6,
    }
end
local out = (arg[1] or "out") .. "/rockfall_precision"
os.execute("rm -rf '" .. out .. "'")
local an = analysis()
local target = { { stat = "reach", x = 30, within = 0.15 } }
local recs, info = rockfall.monte_carlo(an, { precision = target, n = 8, max_n = 256, outdir = out, jobs = 1,
    quiet = true })
local p = info.precision
print(string.format("reach at x = 30 m: %.3f [%.3f, %.3f] after %d rocks, %d looks, met %s", p.history[p.looks].estimates[1].value,
    p.history[p.looks].estimates[1].lo, p.history[p.looks].estimates[1].hi, p.n, p.looks, tostring(p.met)))
T.check(p.met and p.n == 8 * 2 ^ (p.looks - 1) and #recs == p.n and info.n == p.n, "stopped at a look: " .. p.n)
T.check(p.looks > 1 and not p.history[p.looks - 1].estimates[1].met, "and not before it")
T.check(p.history[p.looks].estimates[1].half <= 0.15, "the half-width asked for")
T.near(p.level, 1 - 0.05 / #Seq.schedule(8, 256), 1e-15, "each look at 1 - 0.05 / 6")
-- The same rocks as a plain run of that many (the batches are rocks 1..8, 9..16, ...).
local plain = rockfall.monte_carlo(an, { n = p.n, jobs = 1, quiet = true, stats = false })
T.check(T.digest(plain) == T.digest(recs), "the records of a plain run of " .. p.n .. " rocks, bit for bit")
-- Written: precision.csv (a row per look), the statistics of all the rocks.
local rows = 0
for line in io.lines(out .. "/precision.csv") do
    rows = rows + 1
    if rows == 1 then T.check(line == "look,rocks,statistic,value,ci_lo,ci_hi,half_width,within,met,level", line) end
end
T.check(rows == 1 + p.looks, "precision.csv: one row per look")
T.check(io.open(out .. "/summary.csv"):read("a"):find("rocks,n," .. p.n, 1, true), "the statistics of all the rocks")
-- A rerun resumes: every batch from its checkpoint, the same answer.
local f = io.open(out .. "/checkpoint/rocks_9-16/item_1.tmv")
T.check(f ~= nil, "each batch has its checkpoint")
if f then f:close() end
local again, info2 = rockfall.monte_carlo(an, { precision = target, n = 8, max_n = 256, outdir = out, jobs = 1,
    quiet = true })
T.check(info2.precision.n == p.n and T.digest(again) == T.digest(recs), "the rerun: the same rocks and stop")
-- Not reached within max_n: said, and every rock run.
local printed = {}
local saved = print
print = function(...) printed[#printed + 1] = table.concat({ ... }, " ") end
local _, info3 = rockfall.monte_carlo(an, { precision = { { stat = "run_out", p = 0.9, within = 0.01 } }, n = 8,
    max_n = 20, jobs = 1 })
print = saved
T.check(not info3.precision.met and info3.n == 20, "max_n reached without the precision")
T.check(table.concat(printed, "\n"):find("90 %% run%-out .*NOT reached") and table.concat(printed, "\n"):find("max_n reached after 20 rocks"),
    "said: " .. table.concat(printed, "\n"))
-- Input errors.
T.fails(function() rockfall.monte_carlo(an, { precision = { { stat = "run_outt", p = 0.95, within = 2 } } }) end,
    { "precision[1].stat must be one of", "did you mean 'run_out'" }, "an unknown statistic")
T.fails(function() rockfall.monte_carlo(an, { precision = { { stat = "barrier_energy", barrier = "fense", p = 0.95, within = 1 } } }) end,
    { "no barrier 'fense' in the analysis (known: fence)" }, "an unknown barrier")
T.fails(function() rockfall.monte_carlo(an, { precision = { { stat = "run_out", p = 95, within = 2 } } }) end,
    { "precision[1].p must be <= 1" }, "p as a percentage")
T.fails(function() rockfall.monte_carlo(an, { n = 5, max_n = 10 }) end, { "max_n goes with precision" }, "max_n alone")
T.fails(function() rockfall.monte_carlo(an, { precision = target, confidence = 95 }) end,
    { "confidence must be a level in (0, 1) (got 95)" }, "a confidence in percent")

T.done("rockfall_precision")
