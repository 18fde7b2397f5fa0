-- SPDX-License-Identifier: MIT
-- rockfall_stats (scripts/lib/rockfall/stats/) against a hand-computed small Monte Carlo:
-- 20 synthetic per-rock records whose end points, envelope entries, collector crossings and
-- barrier impacts are chosen so that every statistic can be worked out by hand (the working
-- is in the comments). Then the edge cases: 0 rocks, 1 rock, all rocks stopped by a barrier,
-- bins no rock reaches, bad input. Writes the CSV files into <outdir>/rockfall_stats (arg[1]),
-- which tests/scripts/test_plot_rockfall.py plots.
-- (This file is not called rockfall_stats.lua: the script's own directory comes first in
-- package.path, and require("rockfall_stats") would load the test itself.)
--
-- Tolerances: the statistics are sums, one division and one interpolation of exact inputs, so
-- they agree with the hand values to rounding (1e-12 relative); the Wilson bounds use a normal
-- quantile with relative error < 1.2e-9 (Acklam), hence 1e-8 there.
local T = require("testlib")
local S = require("rockfall_stats")

local outdir = (arg[1] or "out") .. "/rockfall_stats"
local NaN = 0 / 0
local function isnan(v) return v ~= v end
local EPS = 1e-12

-- ------------------------------------------------------------------ the synthetic analysis
-- Profile: cliff (0,30)-(5,10) (76 deg), talus slope (5,10)-(25,0) (26.6 deg), flat to
-- (60,0). Release at (0,31) for every rock. Envelope bins of 10 m from 0 to 70 (bin 7,
-- [60,70), lies beyond the profile: no rock reaches it).
local profile = { { 0, 30 }, { 5, 10 }, { 25, 0 }, { 60, 0 } }
local function ground(x)
    if x <= 5 then return 30 - 4 * x end
    if x <= 25 then return 10 - (x - 5) / 2 end
    return 0
end
local analysis = {
    profile = profile,
    envelope = { x0 = 0, x1 = 70, dx = 10 },
    collectors = { { name = "c15", x = 15 }, { name = "c35", x = 35 }, { name = "c50", x = 50 } },
    barriers = { { name = "fence", x = 40 } },
    release = { x = 0, y = 31 },
    seed = 7,
    n = 20,
}

-- End points, sorted: x_(1..20) = 12 14 15 17 18 20 21 22 24 25 26 27 28 30 31 33 35 38 39.5 60.
-- Rock i gets x_(21 - i) (records in DEcreasing end_x, so the code must sort): rock 1 left the
-- profile at x = 60, rock 2 was stopped by the barrier (39.5, in front of it), rock 3 hit the
-- time cap at 38, rocks 4..20 came to rest (17 deposited rocks).
local xs = { 12, 14, 15, 17, 18, 20, 21, 22, 24, 25, 26, 27, 28, 30, 31, 33, 35, 38, 39.5, 60 }
local records = {}
for i = 1, 20 do
    local x = xs[21 - i]
    local stop = (i == 1 and "left") or (i == 2 and "barrier") or (i == 3 and "time") or "rest"
    local r = { rock = i, seed = 1000 + i, shape = "disk", mass = 100, volume = 0.04, r_eq = 0.5,
        release = { x = 0, y = 31, vx = 0, vy = 0, spin = 0 }, stop = stop,
        end_x = x, end_y = ground(x) + 0.5, t_end = 10 + i,
        crossings = {}, barrier = {}, impacts = {}, env_height = {}, env_ke = {} }
    -- Envelope: the rock has an entry in every bin k whose lower edge it reached,
    -- 10 (k - 1) <= end_x, up to bin 6 (the profile ends at 60): height k + i/100, ke 1000x.
    for k = 1, math.min(math.floor(x / 10) + 1, 6) do
        r.env_height[k] = k + i / 100
        r.env_ke[k] = 1000 * (k + i / 100)
    end
    -- Collectors: crossing a line at X when end_x >= X; height i/10, ke_trans 100 i,
    -- ke_rot 10 i, ke 110 i, v = i, spin = -i/2 (rolling down-slope: clockwise, negative).
    for _, c in ipairs(analysis.collectors) do
        if x >= c.x then
            r.crossings[#r.crossings + 1] = { line = c.name, t = c.x / 10, x = c.x, y = ground(c.x),
                height = i / 10, vx = i, vy = 0, v = i, spin = -i / 2, ke_trans = 100 * i,
                ke_rot = 10 * i, ke = 110 * i }
        end
    end
    r.impacts[1] = { t = 1, x = 5, y = 10, vn_in = -10, vt_in = 3, vn_out = 3, vt_out = 2,
        rn = 0.3, rt = 0.67, energy_lost = 1000, material = "bedrock" }
    records[i] = r
end
-- Rock 5 crosses c15 a second time later (it rolled back and forth): the crossing counts as an
-- event, but the statistics use each rock's FIRST crossing.
table.insert(records[5].crossings, 2, { line = "c15", t = 99, x = 15, y = 5, height = 99, v = 99,
    spin = 99, ke_trans = 99, ke_rot = 99, ke = 99 })
-- A line the analysis does not list: appended after the listed ones.
records[7].crossings[#records[7].crossings + 1] = { line = "extra", t = 50, x = 31, height = 2 }
-- Rock 20 (end 12) bounced back from an impact at x = 13.5: its farthest point is 13.5.
records[20].impacts[2] = { t = 2, x = 13.5, y = 6, vn_in = -1, vt_in = 1, vn_out = 0, vt_out = 0 }
-- Barrier "fence" at x = 40: rock 1 passed (5000 J, 1.2 m, 10 deg), rock 2 stopped (2000 J,
-- 0.8 m, 20 deg).
records[1].barrier[1] = { name = "fence", stopped = false, t = 4, x = 40, y = 0, height = 1.2,
    energy = 5000, angle = 10 }
records[2].barrier[1] = { name = "fence", stopped = true, t = 4, x = 40, y = 0, height = 0.8,
    energy = 2000, angle = 20 }
-- A few trajectories (rock, t, x, y) for the plot test: a parabola from the release point.
for i = 1, 3 do
    local path = {}
    for j = 0, 10 do
        local t = j * 0.1
        path[#path + 1] = { t, 3 * i * t, 31 - 4.905 * t * t }
    end
    records[i].path = path
end

-- ------------------------------------------------------------------ order-statistic ranks
-- Binomial(20, 0.5): F(5) = 0.020695 <= 0.025 < F(6) = 0.057659, so l = 6; F(13) = 0.942341 <
-- 0.975 <= F(14) = 0.979305, so u = 15 (the classical median interval [x_(6), x_(15)] for n = 20);
-- coverage F(14) - F(5) = 0.958611.
local l, u, cov = S.quantile_ci_ranks(20, 0.5, 0.95)
T.check(l == 6 and u == 15, "n=20 median ranks 6, 15")
T.near(cov, 0.9793052673339844 - 0.020694732666015625, EPS, "n=20 median coverage")
-- Binomial(20, 0.9): F(14) = 0.011253 <= 0.025 < F(15) = 0.043174: l = 15; F(19) = 1 - 0.9^20
-- = 0.878423 < 0.975: no upper rank (20 rocks cannot bound the 90 % quantile from above).
l, u, cov = S.quantile_ci_ranks(20, 0.9, 0.95)
T.check(l == 15 and u == nil, "n=20 q90 ranks 15, none")
T.near(cov, 1 - 0.01125313416450899, EPS, "n=20 q90 one-sided coverage")
-- n = 10, p = 0.5: F(1) = 11/1024 <= 0.025 < F(2) = 56/1024 -> l = 2; F(8) = 1013/1024 >= 0.975
-- > F(7) -> u = 9.
l, u = S.quantile_ci_ranks(10, 0.5, 0.95)
T.check(l == 2 and u == 9, "n=10 median ranks 2, 9")
-- n = 5, p = 0.5: F(0) = 1/32 = 0.031 > 0.025 and F(4) = 31/32 = 0.969 < 0.975: no ranks.
l, u = S.quantile_ci_ranks(5, 0.5, 0.95)
T.check(l == nil and u == nil, "n=5 median: too few rocks for either side")
-- Large n (no underflow of 0.05^n): the normal approximation n p -+ z sqrt(n p (1-p)) gives
-- 95000 -+ 135.1 for n = 1e5, p = 0.95 -> ranks near 94865 and 95136.
l, u = S.quantile_ci_ranks(100000, 0.95, 0.95)
T.check(math.abs(l - 94865) <= 2 and math.abs(u - 95136) <= 2, "n=1e5 q95 ranks " .. l .. " " .. u)
-- Smallest sample with each side (docs/rockfall-statistics.md table): the upper rank u <= n
-- exists iff F(n-1) = 1 - p^n >= 0.975, i.e. n >= ln 0.025 / ln p; the lower rank iff
-- F(0) = (1-p)^n <= 0.025, i.e. n >= ln 0.025 / ln(1-p). p = 0.9: upper from 36 rocks (0.9^35
-- = 0.0250 > 0.025, 0.9^36 = 0.0225); p = 0.95: 72; p = 0.99: 368; p = 0.01: lower from 368.
for _, c in ipairs({ { 0.9, "upper", 36 }, { 0.95, "upper", 72 }, { 0.98, "upper", 183 },
    { 0.99, "upper", 368 }, { 0.5, "upper", 6 }, { 0.5, "lower", 6 }, { 0.01, "lower", 368 },
    { 0.05, "lower", 72 }, { 0.9, "lower", 2 } }) do
    local p, side, nmin = c[1], c[2], c[3]
    local function has(n)
        local lo, hi = S.quantile_ci_ranks(n, p, 0.95)
        if side == "upper" then return hi ~= nil end
        return lo ~= nil
    end
    T.check(has(nmin) and not has(nmin - 1),
        string.format("p = %g: %s bound from n = %d", p, side, nmin))
end
-- Measured coverage. 4000 samples of 20 Uniform(0,1) numbers (math.randomseed(8): the same
-- numbers every run, so the check is deterministic). The median interval [x_(6), x_(15)] must
-- hold the true median 0.5 in F(14) - F(5) = 0.95861 of them, the one-sided q90 bound x_(15)
-- must be <= 0.9 in 1 - F(14) = 0.98875 of them (binomial standard errors 0.0032 and 0.0017;
-- tolerance 4 of them). Wilson's 95 % interval of k ~ Binomial(50, 0.3) from the same stream
-- holds 0.3 in about 95 % of 4000 trials (exact coverage at n = 50, p = 0.3 is 0.9567;
-- SE 0.0032, tolerance 4 SE = 0.013).
math.randomseed(8)
local hold_med, hold_q90, hold_w = 0, 0, 0
for _ = 1, 4000 do
    local sample = {}
    for j = 1, 20 do sample[j] = math.random() end
    table.sort(sample)
    local lo, hi = S.quantile_ci(sample, 0.5, 0.95)
    if lo <= 0.5 and 0.5 <= hi then hold_med = hold_med + 1 end
    lo = S.quantile_ci(sample, 0.9, 0.95)
    if lo <= 0.9 then hold_q90 = hold_q90 + 1 end
    local k = 0
    for _ = 1, 50 do
        if math.random() < 0.3 then k = k + 1 end
    end
    local wl0, wh0 = S.wilson(k, 50, 0.95)
    if wl0 <= 0.3 and 0.3 <= wh0 then hold_w = hold_w + 1 end
end
T.near(hold_med / 4000, 0.95861, 0.013, "measured coverage of the median interval")
T.near(hold_q90 / 4000, 0.98875, 0.007, "measured coverage of the q90 lower bound")
T.near(hold_w / 4000, 0.9567, 0.013, "measured coverage of Wilson's interval")
-- Wilson 15/20: centre (0.75 + z^2/40)/(1 + z^2/20), half width ... = [0.531299, 0.888138].
local wl, wh = S.wilson(15, 20, 0.95)
T.near(wl, 0.531299122381256, 1e-8, "Wilson 15/20 low")
T.near(wh, 0.8881382985923343, 1e-8, "Wilson 15/20 high")
T.check(S.qname(0.5) == "median" and S.qname(0.95) == "q95" and S.qname(0.01) == "q01"
    and S.qname(0.995) == "q99.5", "quantile names")
-- Type 7 on {1, 2, 3, 4}: p = 0.25 -> h = 1.75 -> 1.75; p = 1 -> 4; p = 0 -> 1.
T.near(S.quantile({ 1, 2, 3, 4 }, 0.25), 1.75, EPS, "type 7 interpolation")
T.check(S.quantile({ 1, 2, 3, 4 }, 1) == 4 and S.quantile({ 1, 2, 3, 4 }, 0) == 1, "type 7 ends")

-- ------------------------------------------------------------------ end points
local ep = S.endpoints(records, { bins = { x0 = 0, x1 = 60, dx = 10 }, profile = profile })
T.check(ep.n == 20 and ep.direction == 1, "n and direction (profile falls towards +x)")
-- Type 7, h = 19 p + 1:
--   p50: h = 10.5  -> x_(10) + 0.5 (x_(11) - x_(10)) = 25.5,       CI [x_(6), x_(15)] = [20, 31]
--   p90: h = 18.1  -> 38 + 0.1 * 1.5 = 38.15,                          CI [x_(15), -] = [31, nan]
--   p95: h = 19.05 -> 39.5 + 0.05 * 20.5 = 40.525, l = 17 (F(16) = 0.0159): [35, nan]
--   p98: h = 19.62 -> 39.5 + 0.62 * 20.5 = 52.21,  l = 18 (F(17) = 0.0071): [38, nan]
--   p99: h = 19.81 -> 39.5 + 0.81 * 20.5 = 56.105, l = 19 (F(18) = 0.0169): [39.5, nan]
local want = { { 0.5, 25.5, 20, 31 }, { 0.9, 38.15, 31, NaN }, { 0.95, 40.525, 35, NaN },
    { 0.98, 52.21, 38, NaN }, { 0.99, 56.105, 39.5, NaN } }
for i, w in ipairs(want) do
    local p = ep.percentiles[i]
    T.check(p.p == w[1], "percentile order")
    T.near(p.x, w[2], EPS, "end_x p" .. w[1])
    T.near(p.lo, w[3], EPS, "end_x p" .. w[1] .. " ci low")
    if isnan(w[4]) then
        T.check(isnan(p.hi), "end_x p" .. w[1] .. " has no upper bound with 20 rocks")
    else
        T.near(p.hi, w[4], EPS, "end_x p" .. w[1] .. " ci high")
    end
end
-- Histogram [0,10) [10,20) [20,30) [30,40) [40,50) [50,60): 0, 5 (12 14 15 17 18),
-- 8 (20..28), 6 (30 31 33 35 38 39.5), 0, 0; the rock at 60 is above the last bin.
local counts = { 0, 5, 8, 6, 0, 0 }
local cum = { 0, 0.25, 0.65, 0.95, 0.95, 0.95 }
T.check(#ep.hist.bins == 6 and ep.hist.below == 0 and ep.hist.above == 1, "6 bins, 1 above")
for k = 1, 6 do
    T.check(ep.hist.bins[k].count == counts[k], "hist count bin " .. k)
    T.near(ep.hist.bins[k].fraction, counts[k] / 20, EPS, "hist fraction bin " .. k)
    T.near(ep.hist.bins[k].cumulative, cum[k], EPS, "hist cumulative bin " .. k)
end
-- Reach at the edges 0, 10, ..., 60: x_far >= x for 20, 20, 15 (x_(6..20)), 7 (30 and up), 1,
-- 1, 1 (the rock that left at 60 reached 60).
local reach = { 20, 20, 15, 7, 1, 1, 1 }
T.check(#ep.reach == 7, "reach grid = bin edges")
for k = 1, 7 do
    T.check(ep.reach[k].x == 10 * (k - 1) and ep.reach[k].count == reach[k],
        "reach count at " .. ep.reach[k].x)
    T.near(ep.reach[k].reach, reach[k] / 20, EPS, "reach at " .. ep.reach[k].x)
end
T.near(ep.reach[3].lo, 0.531299122381256, 1e-8, "reach(20) Wilson low")
T.near(ep.reach[1].lo, 0.8388748419471806, 1e-8, "reach(0) = 20/20 Wilson low = 20/(20+z^2)")
T.check(ep.reach[1].hi == 1, "reach(0) Wilson high = 1")
-- x = 13: only rock 20 ends before it (12), but it bounced back from 13.5: all 20 reached 13.
local ep13 = S.endpoints(records, { reach_x = { 13, 13.6 } })
T.check(ep13.reach[1].count == 20 and ep13.reach[2].count == 19, "reach uses the farthest point")
T.check(ep13.x_far[20] == 13.5 and ep13.x_far[1] == 60, "x_far")
-- Stop rules: rest 17, left 1, time 1, barrier 1, in the fixed order.
local st = ep.stops
T.check(st[1].rule == "rest" and st[1].count == 17 and st[2].rule == "left" and st[2].count == 1
    and st[3].rule == "time" and st[3].count == 1 and st[4].rule == "barrier" and st[4].count == 1,
    "stop-rule counts")
-- Automatic bins (no envelope): sqrt(20) -> 5 bins over 12..60, width 48/5 = 9.6 -> nice 10,
-- x0 = floor(12/10) 10 = 10: bins [10,20) ... [60,70), 6 bins, counts 5 8 6 0 0 1.
local auto = S.endpoints(records, {})
T.check(auto.hist.dx == 10 and auto.hist.x0 == 10 and #auto.hist.bins == 6
    and auto.hist.bins[6].count == 1 and auto.hist.bins[1].count == 5, "automatic histogram bins")

-- ------------------------------------------------------------------ envelopes
local env = S.envelopes(records, analysis)
T.check(#env.bins == 7, "7 envelope bins from 0 to 70")
-- Rocks reaching bin k (10 (k-1) <= end_x): bins 1, 2: 20; bin 3 (>= 20): rocks 1..15;
-- bin 4 (>= 30): rocks 1..7; bins 5, 6: rock 1; bin 7: none.
local nbin = { 20, 20, 15, 7, 1, 1, 0 }
for k = 1, 7 do T.check(env.bins[k].n == nbin[k], "envelope bin " .. k .. " rocks") end
-- Bin 3: heights 3 + i/100, i = 1..15 (n = 15, h = 14 p + 1):
--   mean = median = 3.08 (h = 8); q90: h = 13.6 -> 3.13 + 0.6 * 0.01 = 3.136;
--   q95: h = 14.3 -> 3.143; q98: h = 14.72 -> 3.1472.
--   Binomial(15, 0.5): ranks (4, 12) -> median CI [3.04, 3.12]; (15, 0.9): l = 11 -> [3.11, nan];
--   (15, 0.95): l = 12 -> [3.12, nan]; (15, 0.98): l = 13 -> [3.13, nan].
local b3 = env.bins[3].height
T.near(b3.mean, 3.08, EPS, "bin 3 mean height")
T.near(b3.median, 3.08, EPS, "bin 3 median")
T.near(b3.median_lo, 3.04, EPS, "bin 3 median ci low")
T.near(b3.median_hi, 3.12, EPS, "bin 3 median ci high")
T.near(b3.q90, 3.136, EPS, "bin 3 q90")
T.near(b3.q90_lo, 3.11, EPS, "bin 3 q90 ci low")
T.check(isnan(b3.q90_hi), "bin 3 q90: no upper bound")
T.near(b3.q95, 3.143, EPS, "bin 3 q95")
T.near(b3.q95_lo, 3.12, EPS, "bin 3 q95 ci low")
T.near(b3.q98, 3.1472, EPS, "bin 3 q98")
T.near(b3.q98_lo, 3.13, EPS, "bin 3 q98 ci low")
T.near(env.bins[3].ke.q95, 3143, EPS, "bin 3 ke q95 (1000 x the height)")
T.near(env.bins[3].reach, 0.75, EPS, "bin 3 reached by 15 of 20")
-- Bin 4: 4 + i/100, i = 1..7: median 4.04 (h = 4), CI ranks (1, 7) -> [4.01, 4.07];
-- q90: h = 6.4 -> 4.064, l = 4 -> [4.04, nan].
local b4 = env.bins[4].height
T.near(b4.median, 4.04, EPS, "bin 4 median")
T.near(b4.median_lo, 4.01, EPS, "bin 4 median ci low")
T.near(b4.median_hi, 4.07, EPS, "bin 4 median ci high")
T.near(b4.q90, 4.064, EPS, "bin 4 q90")
T.near(b4.q90_lo, 4.04, EPS, "bin 4 q90 ci low")
-- Bin 1: heights 1 + i/100 for all 20: median 1.105, CI [x_(6), x_(15)] = [1.06, 1.15].
T.near(env.bins[1].height.median, 1.105, EPS, "bin 1 median")
T.near(env.bins[1].height.median_lo, 1.06, EPS, "bin 1 median ci low")
T.near(env.bins[1].height.median_hi, 1.15, EPS, "bin 1 median ci high")
-- Bin 6: one rock (6 + 1/100): every quantile is the value, no interval
-- (one rock: F(0) = 1 - p > 0.025 for p <= 0.95).
local b6 = env.bins[6].height
T.check(b6.n == 1 and b6.median == 6.01 and b6.q95 == 6.01 and isnan(b6.median_lo)
    and isnan(b6.q95_lo) and isnan(b6.q95_hi), "bin 6: one rock")
-- ... except q98: F(0) = 0.02 <= 0.025, so the single value is a lower bound at 97.5 %.
T.check(b6.q98_lo == 6.01 and isnan(b6.q98_hi), "bin 6: one rock bounds q98 from below")
-- Bin 7: no rock: n = 0, reach 0, NaN statistics.
local b7 = env.bins[7]
T.check(b7.n == 0 and b7.reach == 0 and isnan(b7.height.mean) and isnan(b7.height.median)
    and isnan(b7.ke.q95) and isnan(b7.height.max), "bin 7: never reached")

-- ------------------------------------------------------------------ collectors
local col = S.collectors(records, analysis)
T.check(#col == 4 and col[1].name == "c15" and col[2].name == "c35" and col[3].name == "c50"
    and col[4].name == "extra", "collectors in analysis order, unlisted lines after")
-- c15: rocks with end_x >= 15: rocks 1..18; rock 5 crossed twice: 19 events.
T.check(col[1].rocks == 18 and col[1].crossings == 19, "c15 rocks and crossings")
T.near(col[1].fraction, 0.9, EPS, "c15 fraction")
-- height i/10, i = 1..18 (h = 17 p + 1): mean 0.95, median 0.95 (h = 9.5), q90 1.63 (h = 16.3),
-- q95 1.715 (h = 17.15), q98 1.766 (h = 17.66), max 1.8; Binomial(18, 0.5) ranks (5, 14) ->
-- median CI [0.5, 1.4]; (18, 0.95): l = 15 -> q95 CI [1.5, nan]. Rock 5's second crossing
-- (height 99) is ignored: max stays 1.8.
local h = col[1].stats.height
T.near(h.mean, 0.95, EPS, "c15 mean height")
T.near(h.median, 0.95, EPS, "c15 median height")
T.near(h.q90, 1.63, EPS, "c15 q90 height")
T.near(h.q95, 1.715, EPS, "c15 q95 height")
T.near(h.q98, 1.766, EPS, "c15 q98 height")
T.near(h.max, 1.8, EPS, "c15 max height (first crossings only)")
T.near(h.median_lo, 0.5, EPS, "c15 median ci low")
T.near(h.median_hi, 1.4, EPS, "c15 median ci high")
T.near(h.q95_lo, 1.5, EPS, "c15 q95 ci low")
-- ke = 110 i: mean 1045; ke_rot = 10 i: max 180; spin |-i/2|: median 4.75, max 9; v = i: q90 16.3.
T.near(col[1].stats.ke.mean, 1045, EPS, "c15 mean ke")
T.near(col[1].stats.ke_rot.max, 180, EPS, "c15 max ke_rot")
T.near(col[1].stats.ke_trans.median, 950, EPS, "c15 median ke_trans")
T.near(col[1].stats.spin.median, 4.75, EPS, "c15 median |spin|")
T.near(col[1].stats.spin.max, 9, EPS, "c15 max |spin|")
T.near(col[1].stats.v.q90, 16.3, EPS, "c15 q90 v")
-- c35: rocks 1..4 (end_x 60, 39.5, 38, 35); c50: rock 1 only.
T.check(col[2].rocks == 4 and col[3].rocks == 1 and col[3].stats.ke.max == 110, "c35, c50")
T.check(col[4].rocks == 1 and isnan(col[4].x) and col[4].stats.height.max == 2
    and col[4].stats.ke.n == 0, "extra line: missing fields are not values")

-- ------------------------------------------------------------------ barriers
local bar = S.barriers(records, analysis)
T.check(#bar == 1 and bar[1].name == "fence" and bar[1].x == 40, "one barrier")
T.check(bar[1].rocks == 2 and bar[1].stopped == 1 and bar[1].passed == 1
    and bar[1].not_reached == 18 and bar[1].impacts == 2,
    "fence: 1 stopped, 1 passed, 18 not reached")
-- energies {2000, 5000}: mean 3500, median 3500, q90 h = 1.9 -> 2000 + 0.9 3000 = 4700; two
-- rocks give no median interval (F(0) = 0.25); q90: F(0) = 0.01 -> lower bound x_(1) = 2000.
local be = bar[1].stats.energy
T.near(be.mean, 3500, EPS, "fence mean energy")
T.near(be.q90, 4700, EPS, "fence q90 energy")
T.check(isnan(be.median_lo) and be.q90_lo == 2000 and be.max == 5000, "fence energy bounds")
T.near(bar[1].stats.height.median, 1.0, EPS, "fence median impact height")
T.near(bar[1].stats.angle.mean, 15, EPS, "fence mean impact angle")

-- ------------------------------------------------------------------ angles
-- Deposited = rest: rocks 4..20, end_x 35, 33, ..., 12. Energy line from (0, 31) to
-- (x, ground(x) + 0.5): e.g. rock 4 (35, 0.5): atan(30.5/35) = 41.0698 deg (the minimum, the
-- farthest rock); rock 20 (12, 7): atan(24/12) = 63.4349 deg.
local ang = S.angles(records, analysis)
T.check(ang.deposited == 17 and ang.beyond_apex == 17, "17 deposited, all beyond the apex")
T.near(ang.per_rock[4].energy_line, math.deg(math.atan(30.5 / 35)), EPS, "energy line rock 4")
T.near(ang.per_rock[20].energy_line, math.deg(math.atan(24 / 12)), EPS, "energy line rock 20")
T.check(isnan(ang.per_rock[1].energy_line) and isnan(ang.per_rock[2].energy_line),
    "not deposited: NaN")
T.near(ang.energy_line.min, 41.069824454274524, EPS, "energy line min")
-- Low percentiles, n = 17, h = 16 p + 1: p05: h = 1.8 -> 41.0698 + 0.8 (42.7454 - 41.0698)
-- = 42.4103; its CI: Binomial(17, 0.05): F(3) = 0.9912 >= 0.975 > F(2) = 0.9497 -> u = 4,
-- no lower rank: [nan, x_(4) = 45.4735] (the upper bound is the design-side one).
T.near(ang.energy_line.q05, 42.41030491810688, 1e-12, "energy line p05")
T.check(isnan(ang.energy_line.q05_lo), "energy line p05: no lower bound from 17 rocks")
T.near(ang.energy_line.q05_hi, 45.47350805873493, EPS, "energy line p05 upper bound x_(4)")
T.near(ang.energy_line.median, 51.34019174590991, EPS, "energy line median")
-- Shadow: apex = toe of the last downslope segment of 45 deg or steeper = (5, 10) (the talus slope is
-- 26.6 deg). Rock 4 (35): atan(10/30) = 18.4349 deg; a rock on the talus slope: the slope
-- angle atan(1/2) = 26.5651 deg.
T.check(ang.apex.x == 5 and ang.apex.y == 10, "apex at the cliff toe")
T.near(ang.per_rock[4].shadow, math.deg(math.atan(10 / 30)), EPS, "shadow rock 4")
T.near(ang.per_rock[20].shadow, math.deg(math.atan(0.5)), EPS, "shadow rock on the talus")
T.near(ang.shadow.min, 18.43494882292201, EPS, "shadow min")
T.near(ang.shadow.q10, 20.484036238474413, 1e-12, "shadow p10")
-- A given apex wins; a steeper threshold than the cliff leaves no apex (no shadow angles).
local a2 = S.angles(records,
    { profile = profile, release = analysis.release, shadow_apex = { 25, 0 } })
T.check(a2.beyond_apex == 7 and a2.apex.x == 25, "given apex: 7 rocks beyond x = 25 (26..35)")
T.near(a2.shadow.min, math.deg(math.atan(0, 10)), EPS, "given apex on the flat: 0 deg")
local a3 = S.angles(records, { profile = profile, release = analysis.release, shadow_steep = 80 })
T.check(a3.apex == nil and a3.shadow.n == 0 and isnan(a3.shadow.min), "no steep segment: no apex")
T.check(ang.note == nil, "apex above the floor: no note")
-- A cliff straight onto a flat floor (Nejati's 2008 last step): no talus, so no apex and no
-- shadow angles (once the apex was the cliff's toe and every angle on the floor atan(0) = 0).
local a4 = S.angles(records,
    { profile = { { 0, 30 }, { 5, 0 }, { 60, 0 } }, release = analysis.release })
T.check(a4.apex == nil and a4.shadow.n == 0 and a4.no_apex
    and a4.no_apex:find("does not go down", 1, true), "cliff onto a flat: no apex, the reason")
-- A given apex at the bottom: its angles are 0, and the result says so.
local a5 = S.angles(records, { profile = { { 0, 30 }, { 5, 0 }, { 60, 0 } },
    release = analysis.release, shadow_apex = { 5, 0 } })
T.check(a5.shadow.max == 0 and a5.note and a5.note:find("shadow_apex", 1, true),
    "a given apex at the bottom: note")

-- ------------------------------------------------------------------ a slope falling towards -x
-- The same analysis mirrored (x -> -x): the direction is inferred from the profile (its first
-- point, x = -60, is lower than its last), percentiles mirror (p50 = -25.5 with the interval
-- [-31, -20]; p90 = -38.15 with the bound on the other side), reach counts and angles are
-- unchanged.
local mprofile, mrecords = {}, {}
for i = #profile, 1, -1 do mprofile[#mprofile + 1] = { -profile[i][1], profile[i][2] } end
for i, r in ipairs(records) do
    local m = {}
    for k, v in pairs(r) do m[k] = v end
    m.end_x = -r.end_x
    m.release = { x = -r.release.x, y = r.release.y }
    m.impacts, m.crossings, m.path = {}, {}, nil
    for j, e in ipairs(r.impacts) do m.impacts[j] = { x = -e.x } end
    mrecords[i] = m
end
local mep = S.endpoints(mrecords, { profile = mprofile, reach_x = { -20, -13 } })
T.check(mep.direction == -1, "direction -1 from the profile")
T.near(mep.percentiles[1].x, -25.5, EPS, "mirrored p50")
T.near(mep.percentiles[1].lo, -31, EPS, "mirrored p50 low")
T.near(mep.percentiles[1].hi, -20, EPS, "mirrored p50 high")
T.near(mep.percentiles[2].x, -38.15, EPS, "mirrored p90")
T.check(isnan(mep.percentiles[2].lo) and mep.percentiles[2].hi == -31, "mirrored p90 bound")
T.check(mep.reach[1].count == 15 and mep.reach[2].count == 20, "mirrored reach (and x_far)")
local mang = S.angles(mrecords, { profile = mprofile, release = analysis.release })
T.check(mang.apex.x == -5 and mang.apex.y == 10, "mirrored apex")
T.near(mang.energy_line.min, 41.069824454274524, EPS, "mirrored energy line min")
T.near(mang.shadow.min, 18.43494882292201, EPS, "mirrored shadow min")

-- ------------------------------------------------------------------ files
local summary = S.write(records, analysis, outdir)
S.print_summary(summary)
T.check(summary.n == 20 and summary.stops.rest == 17, "summary counts")
local function lines(name)
    local out = {}
    for line in io.lines(outdir .. "/" .. name) do out[#out + 1] = line end
    return out
end
local e = lines("endpoints.csv")
T.check(#e == 21
    and e[1]:find("^rock,seed,shape,mass,stop,release_x,release_y,end_x,end_y,t_end,x_far,")
    and e[2]:find("^1,1001,disk,100,left,0,31,60,0.5,11,60,nan,nan$"),
    "endpoints.csv: " .. tostring(e[2]))
local pc = lines("endpoint_percentiles.csv")
T.check(pc[2] == "0.5,25.5,20,31,0.958610534668", "percentiles row: " .. pc[2])
T.check(lines("reach.csv")[4]:find("^20,15,0.75,0.5312991"), "reach row")
local envl = lines("envelopes.csv")
T.check(#envl == 8 and envl[8]:find("^7,60,70,65,0,0,0,nan"), "envelopes.csv bin 7")
T.check(#lines("collectors.csv") == 1 + 4 * 6 and #lines("barriers.csv") == 1 + 3,
    "collectors/barriers rows")
T.check(#lines("trajectories.csv") == 1 + 3 * 11 and lines("trajectories.csv")[2] == "1,0,0,31",
    "trajectories")
T.check(#lines("profile.csv") == 5 and lines("profile.csv")[3] == "5,10", "profile.csv")
local sm = table.concat(lines("summary.csv"), "\n")
T.check(sm:find("end_x,median,25.5,20,31", 1, true) and sm:find("barrier:fence,stopped,1", 1, true),
    "summary.csv")

-- ------------------------------------------------------------------ edge cases
-- 0 rocks: nothing to rank; every statistic NaN, counts 0; the files are still written.
local e0 = S.endpoints({}, { envelope = analysis.envelope })
T.check(e0.n == 0 and isnan(e0.percentiles[1].x) and isnan(e0.percentiles[1].lo)
    and e0.hist.bins[1].count == 0 and isnan(e0.hist.bins[1].fraction) and isnan(e0.reach[1].reach)
    and e0.stops[1].count == 0, "0 rocks")
local s0 = S.write({}, analysis, outdir .. "/empty")
T.check(s0.n == 0 and #lines("empty/endpoints.csv") == 1, "0 rocks: header-only files")
-- 1 rock: every percentile is its end_x, no interval (p <= 0.95); reach 1 with Wilson [0.2065, 1].
local one = { records[10] }
local e1 = S.endpoints(one, { envelope = analysis.envelope })
T.check(e1.percentiles[1].x == records[10].end_x and isnan(e1.percentiles[1].lo)
    and isnan(e1.percentiles[1].hi), "1 rock: median is its end point, no interval")
T.near(e1.reach[1].lo, 0.20654931437723745, 1e-8, "1 rock: Wilson low = 1/(1 + z^2)")
T.check(S.angles(one, analysis).energy_line.n == 1, "1 rock: one angle")
-- All rocks stopped by the barrier: stopped = N, passed 0, nothing deposited, nothing beyond.
local all = {}
for i = 1, 4 do
    all[i] = { rock = i, stop = "barrier", end_x = 39.5, end_y = 0.5, release = { x = 0, y = 31 },
        barrier = { { name = "fence", stopped = true, t = 4, x = 40, height = i, energy = 1000 * i,
            angle = 5 } } }
end
local ball = S.barriers(all, analysis)
T.check(ball[1].stopped == 4 and ball[1].passed == 0 and ball[1].not_reached == 0, "all stopped")
T.near(ball[1].stats.energy.median, 2500, EPS, "all stopped: median impact energy")
local eall = S.endpoints(all, { envelope = analysis.envelope })
T.check(eall.stop_count.barrier == 4 and eall.reach[5].count == 0 and eall.reach[4].count == 4,
    "all stopped: nobody reaches 40")
T.check(S.angles(all, analysis).deposited == 0, "all stopped: none deposited")
T.check(#S.envelopes(all, analysis).bins == 7, "records without envelope entries")
-- Bad input names what and where.
T.fails(function() S.envelopes(records, {}) end,
    { "rockfall_stats.envelopes", "analysis.envelope" }, "missing envelope")
T.fails(function() S.endpoints({ { rock = 3 } }) end,
    { "record 1 (rock 3): end_x must be a number" }, "missing end_x")
T.fails(function() S.endpoints({ 5 }) end, { "record 1 is a number" }, "not a table")
T.fails(function() S.envelopes(records, { envelope = { 0, 10, -1 } }) end, { "dx > 0" }, "bad dx")
T.fails(function() S.angles({ { end_x = 1, end_y = 0, stop = "rest" } }, {}) end,
    { "no release point" }, "no release point")

T.done("rockfall_statistics")
