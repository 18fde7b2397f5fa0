-- SPDX-License-Identifier: MIT
-- The common library of the shipped Lua libraries (scripts/lib/talus_util): the CSV writer's one
-- cell format (NaN, infinities, booleans, integers, digits, quoting) read back byte for byte;
-- the option checker's did-you-mean; interpolation's three rules outside the points; the
-- generators against splitmix64's published first outputs and against the streams the rockfall
-- Monte Carlo and the material packings drew before the library existed; the statistics
-- against closed forms.
local T = require("testlib")
local Csv = require("talus_util.csv")
local Opt = require("talus_util.options")
local Interp = require("talus_util.interp")
local Rand = require("talus_util.random")
local S = require("talus_util.stats")
local outdir = arg[1] or "out"
talus.mkdir(outdir)

local function slurp(file)
    local f = assert(io.open(file, "r"))
    local text = f:read("a")
    f:close()
    return text
end

-- 1. CSV: one cell format.
T.check(Csv.cell(0 / 0) == "nan" and Csv.cell(-(0 / 0)) == "nan", "NaN of either sign is nan")
T.check(Csv.cell(math.huge) == "inf" and Csv.cell(-math.huge) == "-inf", "infinities")
T.check(Csv.cell(true) == "1" and Csv.cell(false) == "0", "booleans are 1 and 0")
T.check(Csv.cell(nil) == "", "nil is an empty cell")
T.check(Csv.cell(-6457827717110365317) == "-6457827717110365317", "an integer is written exactly")
T.check(Csv.cell(0.1) == "0.10000000000000001", "17 digits by default: " .. Csv.cell(0.1))
T.check(tonumber(Csv.cell(1 / 3)) == 1 / 3, "the default reads back to the same double")
T.check(Csv.cell(1 / 3, 10) == "0.3333333333", "digits = 10")
T.check(Csv.cell(2.0) == "2", "an integral float without a decimal point (%g)")
T.check(Csv.cell("a,b") == '"a,b"' and Csv.cell('say "x"') == '"say ""x"""', "quoted where needed")
T.check(Csv.cell("plain") == "plain", "a plain string is not quoted")
local file = outdir .. "/talus_util_cells.csv"
T.check(Csv.write(file, { "a", "b", "c", "d" }, { { 1, 0 / 0, true, "x,y" }, { 2.5, nil, false } },
    { digits = 12 }), "write")
T.check(slurp(file) == 'a,b,c,d\n1,nan,1,"x,y"\n2.5,,0,\n', "the file, byte for byte: " .. slurp(file))
T.check(Csv.write_records(file, { { x = 1, y = "s" } }, { "y", "x" }), "records")
T.check(slurp(file) == "y,x\ns,1\n", "records in the columns' order")
local devfull = io.open("/dev/full", "w")
if devfull then
    devfull:close()
    local ok, why = Csv.write("/dev/full", { "a" }, { { 1 } })
    T.check(not ok and why:find("cannot write '/dev/full'", 1, true) and why:find("No space left", 1, true),
        "a full disk is an error naming the file: " .. tostring(why))
end
local ok, why = Csv.write(outdir .. "/no/such/dir/x.csv", { "a" }, {})
T.check(not ok and why:find("no/such/dir/x.csv", 1, true), "a missing directory names the file")

-- 2. Options: one checker, with the engine's did-you-mean.
T.check(Opt.unknown({ ratio = 1 }, { "ratio", "stress" }) == nil, "known keys pass")
local msg = Opt.unknown({ ratoi = 1 }, { "ratio", "stress" })
T.check(msg == "unknown option 'ratoi'; did you mean 'ratio'? (known: ratio, stress)", "did you mean: " .. msg)
msg = Opt.unknown({ zzz = 1 }, { stress = true, ratio = true }, "analysis.seeders[2]")
T.check(msg == "unknown option 'zzz' in analysis.seeders[2] (known: ratio, stress)", "a set, a place: " .. msg)
msg = Opt.unknown({ b2 = 1, a1 = 1 }, { "c" })
T.check(msg:find("'a1'", 1, true), "the first unknown key in sorted order, whatever pairs() gives")
local line = T.line() + 1
T.fails(function() Opt.check({ strss = 1 }, { "stress" }, nil, "my.routine: ") end,
    { T.script() .. ":" .. line .. ": my.routine: unknown option 'strss'; did you mean 'stress'?" }, "check raises")

-- 3. Interpolation: one function, the rule outside the points explicit.
local pts = { { 0, 0 }, { 1, 2 }, { 1, 1 }, { 3, 0.3 } } -- a vertical step down at x = 1
T.check(Interp.linear(pts, 0.5, "nan") == 1, "inside")
T.check(Interp.linear(pts, 3, "nan") == 0.3 and Interp.linear(pts, 0, "nan") == 0, "the ends are inside")
T.check(Interp.linear(pts, 1, "nan") == 2, "at a vertical step: the first point's height")
T.check(Interp.linear(pts, 2, "clamp") == 1 + (0.3 - 1) * 0.5, "past the step")
T.check(Interp.linear(pts, -1, "clamp") == 0 and Interp.linear(pts, 9, "clamp") == 0.3, "clamp")
local v = Interp.linear(pts, 9, "nan")
T.check(v ~= v, "nan beyond the end")
local e, why2 = Interp.linear(pts, -1, "error")
T.check(e == nil and why2:find("outside", 1, true), "error mode: nil and a message")
local q = { { 0.1, 0.3 }, { 0.7, 0.9 } }
T.check(Interp.linear(q, 0.7, "error") == 0.9, "a point's own value exactly (not 0.1 + (0.9 - 0.3) ...)")
T.check(Interp.linear({ { 3, 0.3 }, { 1, 1 }, { 0, 0 } }, 0.5, "nan") == 0.5, "points in descending x")

-- 4. Random numbers. splitmix64's first outputs for seed 1234567 (Vigna's splitmix64.c; the
-- values of Rosetta Code's "Pseudo-random numbers/Splitmix64" task), and seed 0.
local g = Rand.splitmix64(1234567)
for i, want in ipairs({ 0x599ED017FB08FC85, 0x2C73F08458540FA5, 0x883EBCE5A3F27C77, 0x3FBEF740E9177B3F,
    0xE3B8346708CB5ECD }) do
    local got = g:next()
    T.check(got == want, string.format("splitmix64(1234567) output %d: %016x, expected %016x", i, got, want))
end
T.check(Rand.splitmix64(0):next() == 0xE220A8397B1DCDAF, "splitmix64(0)")
-- The streams drawn before the library existed (values printed by the old rockfall.lua and
-- material/util.lua): the rockfall Monte Carlo's rocks and the material packings are unchanged.
local rf = require("rockfall")
T.check(rf.rock_seed(1, 1) == 0xBFEF8030DDC2D772, "rockfall.rock_seed(1, 1)")
local st = rf.stream(rf.rock_seed(1, 1), "position")
T.check(st:uniform() == 0x1.f1f09de5fc39ep-1 and st:normal() == 0x1.58a499d6f773ap-2, "a rock's stream")
local u01 = require("material").drawer(1)
T.check(u01() == 0x1.f6a4698d851cp-8 and u01() == 0x1.68259863b9712p-1 and u01() == 0x1.3b3f836a42a7ap-1,
    "material's xorshift64* stream for seed 1")
-- uniform_open never gives 0: its smallest value is half a cell
local x = Rand.xorshift64star(1)
local lo, hi = 1, 0
for _ = 1, 20000 do
    local u = x:uniform_open()
    lo, hi = math.min(lo, u), math.max(hi, u)
end
T.check(lo > 0 and hi < 1, "uniform_open in (0, 1)")
T.fails(function() Rand.xorshift64star(0) end, { "must not be 0" }, "xorshift64* state 0")

-- 5. Statistics against closed forms.
T.check(S.quantile({ 1, 2, 3, 4 }, 0.5) == 2.5 and S.quantile({ 1, 2, 3, 4 }, 0.9) == 3.7000000000000002,
    "type 7 quantiles (numpy's default: 2.5 and 3.7)")
-- Wilson's interval for 5 of 10 at 95%: 0.2366 .. 0.7634 (Brown, Cai & DasGupta 2001's formula)
local wl, wh = S.wilson(5, 10, 0.95)
T.near(wl, 0.2365931, 1e-6, "Wilson lower")
T.near(wh, 0.7634069, 1e-6, "Wilson upper")
T.near(S.normal_quantile(0.975), 1.959963985, 1e-8, "normal quantile")
-- order-statistic interval of the median of 10: ranks 2 and 9, coverage 1 - 2 * 11/1024
local l, u, cov = S.quantile_ci_ranks(10, 0.5, 0.95)
T.check(l == 2 and u == 9, "median ranks of n = 10: " .. tostring(l) .. ", " .. tostring(u))
T.near(cov, 1 - 22 / 1024, 1e-12, "coverage")

T.done("talus_util")
