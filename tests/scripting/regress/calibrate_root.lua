-- SPDX-License-Identifier: MIT
-- calibrate.root (talus_util/optimize.lua, through scripts/lib/calibrate/): the Illinois regula falsi finds known roots to
-- the requested bracket width, keeps the bracket, and refuses a bracket without a sign change.
local T = require("testlib")
local C = require("calibrate")

-- known roots: sqrt(2) of x^2 - 2; pi of sin x on [3, 4]; the Dottie number of cos x - x
-- (0.73908513321516064, the fixed point of cos); a root of multiplicity 3, (x - 1)^3, where
-- regula falsi without the Illinois change converges one-sidedly and slowly.
local cases = {
    { f = function(x) return x * x - 2 end, a = 0, b = 2, root = math.sqrt(2) },
    { f = math.sin, a = 3, b = 4, root = math.pi },
    { f = function(x) return math.cos(x) - x end, a = 0, b = 1, root = 0.73908513321516064 },
    { f = function(x) return (x - 1) ^ 3 end, a = 0, b = 3, root = 1 },
    { f = function(x) return math.exp(x) - 10 end, a = 10, b = -5, root = math.log(10) },
}
for i, c in ipairs(cases) do
    -- xtol 1e-12: the returned point lies in the final bracket, whose width is <= xtol, so it
    -- is within 1e-12 of the root (plus the root's own round-off, ~1e-16 relative; for the
    -- triple root f is flat, |f| < 1e-36 within 1e-12, so the bracket test decides alone)
    local x, info = C.root(c.f, c.a, c.b, { xtol = 1e-12 })
    T.near(x, c.root, 2e-12, "root of case " .. i)
    T.check(not info.unconverged, "case " .. i .. " converged")
    -- superlinear on simple roots: measured 6-10 iterations where bisection needs
    -- log2(width/1e-12) = 40-44; at the triple root the bisection safeguard halves the bracket
    -- at least every other step, so <= 2 x 44 + a few (measured 89; unsafeguarded Illinois 145)
    T.check(info.iterations <= (i == 4 and 95 or 15),
        string.format("case %d iterations %d", i, info.iterations))
end

-- ftol stops on the function value
local x = C.root(function(v) return v - 0.3 end, 0, 1, { ftol = 1e-3 })
T.check(math.abs(x - 0.3) <= 1e-3, "ftol")

-- a root at an end is returned at once
T.near(C.root(function(v) return v - 1 end, 1, 2), 1, 0, "root at an end")

-- no sign change: a clear error naming the bracket
T.fails(function() C.root(function(v) return v * v + 1 end, -1, 1) end,
    { "calibrate.root", "does not bracket a root" }, "no sign change")

-- targets: a table is interpolated linearly and refuses extrapolation
local tgt = C.target({ { 2, 0.4 }, { 1, 0.5 } })
T.near(tgt(1.5), 0.45, 1e-15, "table target interpolation")
T.fails(function() tgt(3) end, { "outside the table" }, "table target extrapolation")
-- RocFall law at its reference speed: Rn(9.144) = 0.53 / 2
T.near(C.rocfall()(9.144), 0.265, 1e-15, "rocfall law")

T.done("calibrate_root")
