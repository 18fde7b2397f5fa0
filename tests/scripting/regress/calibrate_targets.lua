-- SPDX-License-Identifier: MIT
-- calibrate.fit_targets (talus_util/optimize.lua) on cheap known functions, so that the
-- method is tested without DEM runs: the design is orthogonal; four parameters are found from
-- four targets of a made-up "material" (power laws with a curvature) to the tolerance, within
-- the budget, and the parameters that produce them are recovered; with 2% noise on every output
-- the targets are still met to 5%; an interrupted fit resumed from talus.map's checkpoint gives
-- the same result, bit for bit, and recomputes only what was lost.
local T = require("testlib")
local C = require("calibrate")
local outdir = arg[1] or "."

-- 1. The design: centre first, then 2^q runs of +-1; columns balanced and orthogonal.
for p = 1, 7 do
    local d = C.design(p)
    T.check(#d >= p + 2, "p " .. p .. ": runs " .. #d)
    for k = 1, p do T.check(d[1][k] == 0, "centre") end
    for j = 1, p do
        local sum = 0
        for i = 2, #d do sum = sum + d[i][j]; T.check(d[i][j] == 1 or d[i][j] == -1, "levels") end
        T.check(sum == 0, "column " .. j .. " balanced (p " .. p .. ")")
        for k = j + 1, p do
            local dot = 0
            for i = 2, #d do dot = dot + d[i][j] * d[i][k] end
            T.check(dot == 0, string.format("columns %d, %d orthogonal (p %d)", j, k, p))
        end
    end
end
T.check(#C.design(4) == 9 and #C.design(3) == 9 and #C.design(6) == 9 and #C.design(7) == 17, "run counts")

-- 2. C.lsq: an exact plane is recovered.
local X, y = {}, {}
for i = 1, 6 do X[i] = { 1, i, (i * i) % 5 }; y[i] = 2 - 0.5 * i + 3 * ((i * i) % 5) end
local beta = C.lsq(X, y, nil, 0)
T.near(beta[1], 2, 1e-12, "lsq a"); T.near(beta[2], -0.5, 1e-12, "lsq b"); T.near(beta[3], 3, 1e-12, "lsq c")

-- 3. A made-up material: E from a modulus, nu from a stiffness ratio, UCS and sigma_t from two
-- strengths, with cross terms and a curvature in log space (what a power-law surface cannot fit
-- exactly, so the trust region has to close in).
local function material(x, noise)
    local E = 0.8 * x.emod * x.kratio ^ -0.08
    local nu = 0.12 * x.kratio ^ 0.7 * (x.coh / x.ten) ^ 0.03
    local ucs = 2.0 * x.ten ^ 0.3 * x.coh ^ 0.7 * (1 + 0.2 * math.log(x.kratio) ^ 2) * (x.coh / x.ten) ^ (0.05 * math.log(x.coh / x.ten))
    local ten = 0.75 * x.ten ^ 0.95 * x.coh ^ 0.05
    local out = { E = E, nu = nu, ucs = ucs, tensile = ten }
    if noise then
        -- a deterministic "seed scatter" of 2% per output, from the point
        local h = math.abs(math.sin(1e3 * math.log(x.emod) + 7 * math.log(x.ten) + 3 * math.log(x.coh) + x.kratio))
        local i = 0
        for _, k in ipairs({ "E", "nu", "ucs", "tensile" }) do
            i = i + 1
            out[k] = out[k] * (1 + 0.02 * math.sin(1e4 * h * i))
        end
    end
    return out
end
local truth = { emod = 62e9, kratio = 2.2, ten = 12e6, coh = 95e6 }
local want = material(truth)
local function targets(tol)
    return { { name = "E", value = want.E, tol = tol }, { name = "nu", value = want.nu, tol = tol },
             { name = "ucs", value = want.ucs, tol = tol }, { name = "tensile", value = want.tensile, tol = tol } }
end
local params = {
    { name = "emod", lo = 1e10, hi = 2e11, start = 40e9 },
    { name = "kratio", lo = 1, hi = 5, start = 1.5 },
    { name = "ten", lo = 1e6, hi = 1e8, start = 30e6 },
    { name = "coh", lo = 1e7, hi = 5e8, start = 50e6 },
}
local calls = 0
local function evaluate_with(noise)
    return function(points)
        local outs = {}
        for i, x in ipairs(points) do calls = calls + 1; outs[i] = material(x, noise) end
        return outs
    end
end
local r = C.fit_targets{ params = params, targets = targets(0.01), evaluate = evaluate_with(false), budget = 40 }
print(string.format("exact outputs: stop %s after %d points; best %d: emod %.4g kratio %.4g ten %.4g coh %.4g, misfit %.3g",
    r.stop, r.evaluations, r.best.index, r.best.params.emod, r.best.params.kratio, r.best.params.ten, r.best.params.coh,
    r.best.misfit))
T.check(r.stop == "targets", "stopped by " .. r.stop)
T.check(r.evaluations <= 30, "points " .. r.evaluations)
for k, v in pairs(want) do
    T.check(math.abs(r.best.out[k] / v - 1) <= 0.01, k .. " met: " .. r.best.out[k] .. " for " .. v)
end
-- four targets, four parameters: the parameters are found too (E pins emod and nu kratio to
-- the 1% tolerance within a few per cent; the strengths follow from the two of them)
for k, v in pairs(truth) do
    T.check(math.abs(r.best.params[k] / v - 1) <= 0.05, string.format("%s %.5g for %.5g", k, r.best.params[k], v))
end
-- E is the modulus times a power of kratio: the last surfaces' elasticity d ln E / d ln emod = 1
T.near(r.elasticities.E.emod, 1, 0.02, "elasticity of E on emod")

-- 4. With noise: the targets to 5%.
local rn = C.fit_targets{ params = params, targets = targets(0.05), evaluate = evaluate_with(true), budget = 40 }
print(string.format("2%% noise: stop %s after %d points, misfit %.3g", rn.stop, rn.evaluations, rn.best.misfit))
T.check(rn.stop == "targets", "noisy: stopped by " .. rn.stop)

-- 5. Bad input names what is wrong.
T.fails(function() C.fit_targets{ params = params, targets = targets(0.01), evaluate = evaluate_with(false), budgt = 3 } end,
    { "unknown option 'budgt'" }, "typo")
T.fails(function() C.fit_targets{ params = { { name = "a", lo = 2, hi = 1 } }, targets = targets(0.01), evaluate = print } end,
    { "params[1] needs a name and 0 < lo < hi" }, "bad bounds")
T.fails(function() C.fit_targets{ params = { { name = "a", lo = 1, hi = 2, start = 3 } }, targets = targets(0.01), evaluate = print } end,
    { "start 3 is outside" }, "start outside")

-- 6. Resumption: the points of each batch are evaluated through talus.map with a checkpoint
-- (one directory per batch, keyed by the points), as material.calibrate does. An interruption
-- at the third batch, then a rerun, gives the uninterrupted result bit for bit, and the rerun
-- evaluates only the batches that were not finished.
local function mapped(dir, stop_at)
    return function(points, batch)
        if stop_at and batch == stop_at then error("interrupted") end
        local key = {}
        for i, x in ipairs(points) do key[i] = string.format("%a,%a,%a,%a", x.emod, x.kratio, x.ten, x.coh) end
        return talus.map(#points, function(i) calls = calls + 1; return material(points[i]) end,
            { jobs = 1, checkpoint = string.format("%s/batch_%d", dir, batch), key = table.concat(key, ";") })
    end
end
local dir = outdir .. "/calibrate_targets_ckpt"
os.execute("rm -rf '" .. dir .. "'")
local spec = function(ev) return { params = params, targets = targets(0.01), evaluate = ev, budget = 40 } end
calls = 0
local whole = C.fit_targets(spec(mapped(dir .. "/whole")))
local n_whole = calls
calls = 0
local ok, err = pcall(C.fit_targets, spec(mapped(dir .. "/cut", 3)))
T.check(not ok and tostring(err):find("interrupted"), "the interruption")
local n_before = calls
calls = 0
local resumed = C.fit_targets(spec(mapped(dir .. "/cut")))
print(string.format("resumption: %d points uninterrupted; %d before the interruption, %d after", n_whole, n_before, calls))
T.check(n_before + calls == n_whole, "nothing computed twice")
T.check(#resumed.rows == #whole.rows, "same number of points")
for i, row in ipairs(whole.rows) do
    for k, v in pairs(row.params) do T.check(resumed.rows[i].params[k] == v, "point " .. i .. " " .. k) end
    T.check(resumed.rows[i].misfit == row.misfit, "misfit " .. i)
end
os.execute("rm -rf '" .. dir .. "'")
print(string.format("calibrate_targets: %d checks", T.checks))
