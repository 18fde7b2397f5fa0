-- SPDX-License-Identifier: MIT
-- Genesis' floater step (scripts/lib/material/floaters.lua, docs/material.md "Genesis" step 3):
-- the circles tangent to three sites (balls and walls) against closed forms, and the choice of
-- a floater's new circle.
local T = require("testlib")
local M = require("material")

-- The roots come from a 2 x 2 solve and a quadratic on numbers of order 1: agreement to 1e-12
-- (a few hundred ulps) is what double precision gives; a wrong sign or branch is off by O(1).
local tol = 1e-12
local s3 = math.sqrt(3)

-- 1. Three unit circles touching pairwise (centres on an equilateral triangle of side 2): the
-- inner Soddy circle, at the centroid, radius 2/sqrt(3) - 1. The outer Soddy circle touches
-- them internally, so it is not a solution of the external tangency asked.
local A, B, C = { x = 0, y = 0, r = 1 }, { x = 2, y = 0, r = 1 }, { x = 1, y = s3, r = 1 }
local sol = M.tangent_circles(A, B, C)
T.check(#sol == 1, "equilateral: one external tangent circle, got " .. #sol)
T.near(sol[1][1], 1, tol, "equilateral x")
T.near(sol[1][2], s3 / 3, tol, "equilateral y")
T.near(sol[1][3], 2 / s3 - 1, tol, "equilateral radius")

-- 2. A corner (walls x = 0 and y = 0, inward normals +x, +y) and a unit circle at (3, 3):
-- centre (rho, rho), sqrt(2) |3 - rho| = rho + 1, so rho = (3 sqrt 2 - 1)/(sqrt 2 + 1) in the
-- corner and (3 sqrt 2 + 1)/(sqrt 2 - 1) beyond the circle.
local wx, wy = { nx = 1, ny = 0, w = 0 }, { nx = 0, ny = 1, w = 0 }
sol = M.tangent_circles(wx, wy, { x = 3, y = 3, r = 1 })
table.sort(sol, function(a, b) return a[3] < b[3] end)
local r2 = math.sqrt(2)
T.check(#sol == 2, "corner: two circles, got " .. #sol)
T.near(sol[1][3], (3 * r2 - 1) / (r2 + 1), tol, "corner radius (inside)")
T.near(sol[1][1], sol[1][3], tol, "corner centre on the diagonal")
T.near(sol[2][3], (3 * r2 + 1) / (r2 - 1), 1e-11, "corner radius (beyond)")

-- 3. Three walls (x = 0, x = 4, y = 0): the circle of radius 2 at (2, 2).
sol = M.tangent_circles(wx, { nx = -1, ny = 0, w = -4 }, wy)
T.check(#sol == 1, "three walls: one circle")
T.near(sol[1][1], 2, tol, "three walls x"); T.near(sol[1][2], 2, tol, "three walls y")
T.near(sol[1][3], 2, tol, "three walls radius")
-- two parallel walls and a third parallel: no single circle
T.check(#M.tangent_circles(wx, { nx = -1, ny = 0, w = -4 }, { nx = 1, ny = 0, w = 1 }) == 0, "parallel walls")

-- 4. A floater of radius 0.1 at the centre of the equilateral cage (coordinates relative to
-- it), with a fourth ball farther out: it is moved/grown to the inscribed circle (the
-- smallest tangent circle at least as large, empty, its three normals 120 degrees apart).
local function rel(s)
    local o = { r = s.r, x = s.x - 1, y = s.y - s3 / 3 }
    o.gap = math.sqrt(o.x ^ 2 + o.y ^ 2) - o.r
    return o
end
local sites = { rel(A), rel(B), rel(C), rel({ x = 1, y = -s3, r = 1 }) }
table.sort(sites, function(a, b) return a.gap < b.gap end)
local c = M.floater_circle(sites, 0.1, 1, 8)
T.check(c ~= nil, "floater: a circle found")
T.near(c[3], 2 / s3 - 1, tol, "floater radius: the inscribed circle")
T.near(c[1], 0, tol, "floater x"); T.near(c[2], 0, tol, "floater y")
-- a floater larger than twice the cage's hole is not made to fit (radius range [R/2, 2R])
T.check(M.floater_circle(sites, 0.5, 1, 8) == nil, "floater too large for the cage")
-- the same cage asked to keep a partner that is not one of the three: nothing qualifies
sites[1].key, sites[4].key = "a", "far"
T.check(M.floater_circle(sites, 0.1, 1, 8, { far = true }) == nil, "must-keep partner not in the cage")
T.check(M.floater_circle(sites, 0.1, 1, 8, { a = true }) ~= nil, "must-keep partner in the cage")
print("material_floater: " .. T.checks .. " checks")
