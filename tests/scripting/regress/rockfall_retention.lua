-- SPDX-License-Identifier: MIT
-- Catchment retention (rockfall.stats.retention, docs/rockfall-statistics.md): the share of the
-- rocks retained within a distance of the toe, Pierson et al.'s (2001) cumulative curve, with
-- Wilson bands; the width a retention needs; named catchments. Checked against the binomial
-- closed form: hand-counted records with Wilson's formula written out here, and a simulation of
-- rocks stopping at exponentially distributed distances, whose retained counts must follow
-- Binomial(n, p(W)) (mean and variance) and whose bands must cover p(W) as often as the exact
-- binomial sum says.
local T = require("testlib")
local stats = require("rockfall_stats")
local rockfall = require("rockfall")
local U = require("talus_util.random")

local function isnan(v) return v ~= v end

-- Wilson's score interval, written out (Wilson 1927), with z = 1.959963984540054 for 95 %.
local Z = 1.959963984540054
local function wilson(k, n)
    local p, z2 = k / n, Z * Z
    local c = (p + z2 / (2 * n)) / (1 + z2 / n)
    local h = Z / (1 + z2 / n) * math.sqrt(p * (1 - p) / n + z2 / (4 * n * n))
    return math.max(0, c - h), math.min(1, c + h)
end

-- 1. The toe. The held-out ditch slope (40 deg, a 2 m ditch with 50 deg walls): the foot of the
-- slope is the bottom of the ditch's near wall (the profile's lowest level); on Nejati's (2008)
-- benches the foot of the last cliff; a given toe wins.
local function t(deg) return math.tan(math.rad(deg)) end
local toe0 = 30 / t(40)
local wall = 2 / t(50)
local ditch = { { 0, 30 }, { toe0, 0 }, { toe0 + wall, -2 }, { toe0 + wall + 3, -2 },
    { toe0 + 2 * wall + 3, 0 }, { 120, 0 } }
local toe = stats.toe({ profile = ditch })
T.near(toe.x, toe0 + wall, 1e-12, "ditch: the toe is the bottom of the near wall")
local nejati = { { 0, 60 }, { 7.3, 40 }, { 19.3, 40 }, { 26.2, 20 }, { 38.6, 20 }, { 46, 0 }, { 170, 0 } }
T.check(stats.toe({ profile = nejati }).x == 46, "Nejati: the foot of the last cliff")
T.check(stats.toe({ profile = ditch, toe = 30 }).rule == "given", "a given toe")
-- A gentle run-out that keeps falling (2 deg) does not move the toe to the profile's end.
T.check(stats.toe({ profile = { { 0, 20 }, { 20, 0 }, { 100, -2.8 } } }).x == 20,
    "a run-out falling at 2 deg: the toe stays at the foot of the slope")

-- 2. Hand-counted records on the ditch profile, toe at x0 = toe0 + wall: 10 rocks.
local x0 = toe0 + wall
local cases = { -- {stop, distance from the toe}
    { "rest", -5 }, { "rest", 0.5 }, { "rest", 1 }, { "rest", 2.5 }, { "rest", 2.9 },
    { "barrier", 6 }, { "rest", 8 }, { "left", 90 }, { "time", 3 }, { "rest", 40 } }
local records = {}
for i, c in ipairs(cases) do
    records[i] = { rock = i, stop = c[1], end_x = x0 + c[2], end_y = 0, release = { x = 0.5, y = 31 },
        impacts = { { x = x0 + math.max(c[2], 0) } } }
end
local an = { profile = ditch, toe = x0, catchments = { { name = "ditch", x_from = toe0, x_to = x0 + 3 } },
    envelope = { x0 = 0, x1 = 120, dx = 1 } }
local ret = stats.retention(records, an, { distances = { 0, 1, 3, 10, 50 } })
-- Retained within W: rest or barrier and distance <= W. W = 0: rock 1 (above the toe); W = 1:
-- + rocks 2, 3; W = 3: + 4, 5 (rock 9 hit the time cap: nowhere); W = 10: + 6 (barrier), 7;
-- W = 50: + 10. Rocks 8 (left) and 9 (time) are retained nowhere.
local want = { 1, 3, 5, 7, 8 }
for i, c in ipairs(ret.curve) do
    T.check(c.retained == want[i], string.format("W = %g: %d retained (got %d)", c.distance, want[i], c.retained))
    T.near(c.fraction, want[i] / 10, 1e-15, "fraction at W = " .. c.distance)
    local lo, hi = wilson(want[i], 10)
    T.near(c.lo, lo, 1e-8, "Wilson low at W = " .. c.distance)
    T.near(c.hi, hi, 1e-8, "Wilson high at W = " .. c.distance)
    T.near(c.x, x0 + c.distance, 1e-12, "x of W = " .. c.distance)
end
T.check(ret.above_toe == 1 and ret.nowhere == 2, "1 above the toe, 2 retained nowhere")
-- Widths: sorted distances 0 (rock 1 clamped), 0.5, 1, 2.5, 2.9, 6, 8, 40, inf, inf.
-- q90: h = 9.1 -> between x_(9) = inf and x_(10): inf (no width retains 90 %).
-- q50 asked: h = 5.5 -> 2.9 + 0.5 (6 - 2.9) = 4.45.
local wret = stats.retention(records, an, { widths = { 0.5, 0.9 } })
T.near(wret.widths[1].width, 4.45, 1e-12, "the width retaining half")
T.check(wret.widths[2].width == math.huge, "no width retains 90 % when 20 % are retained nowhere")
-- The named ditch, x from the near wall's top to 3 m past the toe: rocks 2..5 stopped in it
-- (rock 1 stopped above it, rock 9 hit the time cap); reached: every rock with x_far >= toe0.
local c = ret.catchments[1]
T.check(c.name == "ditch" and c.retained == 4 and c.reached == 10, "ditch: 4 retained of 10 reached")
local lo, hi = wilson(4, 10)
T.near(c.lo, lo, 1e-8, "ditch Wilson low")
T.near(c.of_reached, 0.4, 1e-15, "ditch retention of the rocks that reached it")
T.fails(function() stats.retention(records, { profile = ditch, catchments = { { x_from = 5, x_to = 1 } } }) end,
    { "catchments[1] must be {name =, x_from =, x_to =}" }, "a catchment that ends before it starts")
local none = stats.retention({}, an, { distances = { 0, 5 } })
T.check(none.curve[1].retained == 0 and isnan(none.curve[1].fraction) and isnan(none.curve[1].lo),
    "0 rocks: NaN")

-- 3. The binomial closed form. Rocks stop at distances D ~ Exponential(mean 5 m) from the toe,
-- so p(W) = 1 - exp(-W/5). Over M samples of n rocks, the count retained within W is
-- Binomial(n, p): its mean n p and variance n p (1 - p); and the 95 % band covers p(W) in the
-- share of samples sum_k C(n,k) p^k (1-p)^(n-k) [lo(k) <= p <= hi(k)] (the exact coverage of
-- Wilson's interval at this n and p).
local n, M, mean = 40, 2000, 5
local Ws = { 2, 5, 15 }
local rng = U.splitmix64(20011)
local sum, sum2, covered = {}, {}, {}
for j = 1, #Ws do sum[j], sum2[j], covered[j] = 0, 0, 0 end
local sample = {}
for _ = 1, M do
    for i = 1, n do
        sample[i] = { stop = "rest", end_x = x0 - mean * math.log(rng:uniform_open()), end_y = 0 }
    end
    local r = stats.retention(sample, { profile = ditch, toe = x0 }, { distances = Ws })
    for j, w in ipairs(Ws) do
        local k = r.curve[j].retained
        local p = 1 - math.exp(-w / mean)
        sum[j], sum2[j] = sum[j] + k, sum2[j] + k * k
        if r.curve[j].lo <= p and p <= r.curve[j].hi then covered[j] = covered[j] + 1 end
    end
end
for j, w in ipairs(Ws) do
    local p = 1 - math.exp(-w / mean)
    local m, v = sum[j] / M, sum2[j] / M - (sum[j] / M) ^ 2
    -- The sample mean's standard error is sqrt(n p q / M); the variance's about
    -- n p q sqrt(2 / M) (nearly normal counts): 4 standard errors each.
    T.near(m, n * p, 4 * math.sqrt(n * p * (1 - p) / M), string.format("W = %g: mean count n p", w))
    T.near(v, n * p * (1 - p), 4 * n * p * (1 - p) * math.sqrt(2 / M), string.format("W = %g: variance n p q", w))
    local exact = 0
    local logc = 0 -- log C(n, k)
    for k = 0, n do
        if k > 0 then logc = logc + math.log((n - k + 1) / k) end
        local l, h = wilson(k, n)
        if l <= p and p <= h then
            exact = exact + math.exp(logc + k * math.log(p) + (n - k) * math.log(1 - p))
        end
    end
    local share = covered[j] / M
    print(string.format("W = %g m, p = %.4f: mean count %.3f (n p %.3f), variance %.3f (n p q %.3f), "
        .. "band coverage %.4f (binomial sum %.4f)", w, p, m, n * p, v, n * p * (1 - p), share, exact))
    T.near(share, exact, 4 * math.sqrt(exact * (1 - exact) / M),
        string.format("W = %g: band coverage %.4f against the binomial sum %.4f", w, share, exact))
    T.check(exact > 0.92, string.format("Wilson's coverage near 95 %% (%.4f)", exact))
end

-- 4. rockfall.analysis{} takes toe and catchments, checks them and hands them on; the files.
local function analysis(extra)
    local opts = { profile = ditch, seeders = { { kind = "point", at = { 1, 31 } } },
        materials = { slope = { model = "linear", props = { kn = 1e7, ks = 5e6, fric = 0.5 } } } }
    for k, v in pairs(extra) do opts[k] = v end
    return rockfall.analysis(opts)
end
local d = rockfall.describe(analysis({ toe = 36, catchments = { { name = "ditch", x_from = 35, x_to = 41 } } }))
T.check(d.toe == 36 and d.catchments[1].name == "ditch" and d.catchments[1].x_to == 41, "describe() carries them")
T.fails(function() analysis({ catchments = { { name = "a", x_from = 40, x_to = 30 } } }) end,
    { "analysis.catchments[1].x_to must be >=" }, "x_to before x_from")
T.fails(function() analysis({ catchments = { { name = "a", x_from = 1, x_to = 2 }, { name = "a", x_from = 3, x_to = 4 } } }) end,
    { "the name 'a' is taken by catchments[1]" }, "two catchments of one name")
T.fails(function() analysis({ catchments = { { name = "a", from = 1, x_to = 2 } } }) end,
    { "unknown option 'from'" }, "a misspelt key")
local out = (arg[1] or "out") .. "/rockfall_retention"
local summary = stats.write(records, an, out)
local lines = {}
for line in io.lines(out .. "/retention.csv") do lines[#lines + 1] = line end
T.check(lines[1] == "distance,x,retained,fraction,ci_lo,ci_hi" and #lines == 1 + 1 + math.ceil(120 - x0),
    "retention.csv: a row per metre from the toe to the profile's end")
local csv = io.open(out .. "/catchments.csv"):read("a")
T.check(csv:find("\nditch," .. string.format("%.12g", toe0), 1, true) and csv:find(",10,10,4,0.4,", 1, true),
    "catchments.csv: the ditch row: " .. csv)
local srows = io.open(out .. "/summary.csv"):read("a")
T.check(srows:find("catchment:ditch,retained,0.4,", 1, true) and srows:find("retention,width_q95,inf", 1, true),
    "summary.csv: the ditch and the widths")
local printed = {}
stats.print_summary(summary, function(s) printed[#printed + 1] = s end)
T.check(table.concat(printed, "\n"):find("catchment ditch %(x [%d.]+%.%.[%d.]+%): retained 0.4 %["),
    "print_summary has the ditch: " .. table.concat(printed, "\n"))

T.done("rockfall_retention")
