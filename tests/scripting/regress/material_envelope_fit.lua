-- SPDX-License-Identifier: MIT
-- The strength-envelope fits of material/envelope.lua against closed forms: Mohr-Coulomb c and
-- phi and Hoek-Brown m_i (sigma_ci given or fitted) recovered from peaks computed from known
-- values; least squares left unchanged by residuals orthogonal to the fitted line; the
-- per-seed scatter; the crack initiation and damage thresholds of a made-up test history.
local T = require("testlib")
local M = require("material")

-- 1. Mohr-Coulomb: sigma1 = 2 c cos(phi) / (1 - sin(phi)) + sigma3 (1 + sin(phi)) / (1 - sin(phi)).
local function mc_peak(c, phi, s3)
    local s = math.sin(math.rad(phi))
    return 2 * c * math.cos(math.rad(phi)) / (1 - s) + s3 * (1 + s) / (1 - s)
end
for _, case in ipairs({ { 30e6, 59 }, { 10e6, 30 }, { 55e6, 12.5 }, { 1e5, 45 } }) do
    local c, phi = case[1], case[2]
    local pts = {}
    for _, s3 in ipairs({ 0, 5e6, 10e6, 20e6 }) do pts[#pts + 1] = { s3, mc_peak(c, phi, s3) } end
    local f = M.mohr_coulomb(pts)
    -- four points on a line: the least squares are the line to round-off (sums of ~1e9 Pa
    -- values, 1e-12 relative is a few hundred ulps)
    T.near(f.phi, phi, 1e-10, "phi of c " .. c .. ", phi " .. phi)
    T.near(f.c, c, 1e-10 * c, "c of c " .. c .. ", phi " .. phi)
    T.near(f.intercept, mc_peak(c, phi, 0), 1e-10 * c, "intercept")
    T.check(f.rms < 1e-6 * c, "rms " .. f.rms)
    -- named fields work too
    local g = M.mohr_coulomb({ { sigma3 = 0, sigma1 = pts[1][2] }, { sigma3 = 2e7, sigma1 = pts[4][2] } })
    T.near(g.phi, phi, 1e-10, "two named points")
end
-- Residuals e with sum e = 0 and sum e x = 0 (orthogonal to the columns 1 and sigma3 of the
-- regression) leave the least-squares line where it was, and give rms = sqrt(sum e^2 / n).
-- x = {0, 5, 10, 20} MPa: e = (1, -2, 1, 0) s has sum 0 and sum e x = 0 - 10 + 10 + 0 = 0.
do
    local c, phi, s = 30e6, 59, 4e6
    local xs, e = { 0, 5e6, 10e6, 20e6 }, { 1, -2, 1, 0 }
    local pts = {}
    for i, x in ipairs(xs) do pts[i] = { x, mc_peak(c, phi, x) + e[i] * s } end
    local f = M.mohr_coulomb(pts)
    T.near(f.phi, phi, 1e-10, "phi with orthogonal residuals")
    T.near(f.c, c, 1e-9 * c, "c with orthogonal residuals")
    T.near(f.rms, s * math.sqrt(6 / 4), 1e-9 * s, "rms")
end
-- sigma1 - sigma3 falling with sigma3: phi < 0, no cohesion
local neg = M.mohr_coulomb({ { 0, 100e6 }, { 10e6, 105e6 } })
T.check(neg.phi < 0 and neg.c == nil, "slope below 1: phi " .. neg.phi)
T.fails(function() M.mohr_coulomb({ { 5e6, 1e8 }, { 5e6, 1.1e8 } }) end, { "two or more confinements" }, "one sigma3")
T.fails(function() M.mohr_coulomb({ { 0, 1e8 }, { "a", 1 } }) end, { "point 2" }, "bad point")

-- 2. Hoek-Brown for intact rock: sigma1 = sigma3 + sigma_ci sqrt(m_i sigma3 / sigma_ci + 1).
local function hb_peak(sci, mi, s3) return s3 + sci * math.sqrt(mi * s3 / sci + 1) end
for _, case in ipairs({ { 200e6, 28 }, { 40e6, 7 }, { 150e6, 12.3 } }) do
    local sci, mi = case[1], case[2]
    local pts = {}
    for _, s3 in ipairs({ 0, 2e6, 5e6, 10e6, 30e6 }) do pts[#pts + 1] = { s3, hb_peak(sci, mi, s3) } end
    local fixed = M.hoek_brown(pts, sci)
    T.near(fixed.m_i, mi, 1e-10 * mi, "m_i, sigma_ci given (" .. sci .. ", " .. mi .. ")")
    T.check(fixed.rms < 1e-6 * sci, "rms " .. fixed.rms)
    local free = M.hoek_brown(pts)
    T.near(free.m_i, mi, 1e-9 * mi, "m_i, sigma_ci fitted")
    T.near(free.sigma_ci, sci, 1e-9 * sci, "sigma_ci fitted")
    -- with sigma_ci 10% high the fit of m_i is no longer exact: the residuals grow
    local off = M.hoek_brown(pts, 1.1 * sci)
    T.check(off.rms > 1e-3 * sci, "a wrong sigma_ci leaves residuals " .. off.rms)
end
T.fails(function() M.hoek_brown({ { 0, 1e8 } }, 1e8) end, { "sigma3 > 0" }, "only a UCS point")
T.fails(function() M.hoek_brown({ { 1e6, 1e8 } }, -1) end, { "sigma_ci must be > 0" }, "negative sigma_ci")

-- 3. The scatter over seeds (M.envelope_fit): three seeds of known c, phi.
local tests, truth = {}, { { 1, 28e6, 57 }, { 2, 30e6, 59 }, { 3, 32e6, 61 } }
for _, t in ipairs(truth) do
    for _, s3 in ipairs({ 0, 5e6, 10e6 }) do
        tests[#tests + 1] = { seed = t[1], confinement = s3, peak = mc_peak(t[2], t[3], s3) }
    end
end
local fit = M.envelope_fit(tests)
T.check(#fit.seeds == 3, "three seeds fitted")
for i, s in ipairs(fit.seeds) do
    T.near(s.phi, truth[i][3], 1e-9, "seed " .. i .. " phi")
    T.near(s.c, truth[i][2], 1e-9 * truth[i][2], "seed " .. i .. " c")
    -- sigma_ci of the seed = its test at sigma3 = 0
    T.near(s.sigma_ci, mc_peak(truth[i][2], truth[i][3], 0), 1e-12 * s.sigma_ci, "seed sigma_ci")
end
T.near(fit.phi.mean, 59, 1e-9, "mean phi")
T.near(fit.phi.sd, 2, 1e-9, "sd of phi (57, 59, 61)")
T.near(fit.c.mean, 30e6, 1e-9 * 30e6, "mean c")
T.near(fit.c.sd, 2e6, 1e-8 * 2e6, "sd of c")
T.check(fit.pooled and fit.pooled.phi > 55 and fit.pooled.phi < 63, "pooled phi " .. fit.pooled.phi)

-- 4. Thresholds of a made-up history (row 1 the start, as a test's): E = 50 GPa, nu = 0.25,
-- linear elastic (volumetric strain (1 - nu) eps_a) up to i = 40; from there one crack per
-- step i and a crack volumetric strain of -1e-6 per step; the peak at i = 100 (60 cracks);
-- past i = 80 the cracks dilate faster (-2e-5 per step), so the volumetric strain, growing by
-- 7.5e-6 - 1e-6 per step before, turns at i = 80 (crack damage).
local E, nu = 50e9, 0.25
local rows = {}
for i = 0, 120 do
    local ea = 1e-5 * i
    local sa = i <= 100 and E * ea or E * 1e-3 * (1 - 0.01 * (i - 100))
    local crack_v = (i > 40 and -1e-6 * (i - 40) or 0) + (i > 80 and -2e-5 * (i - 80) or 0)
    rows[i + 1] = { ea = ea, sa = sa, cracks = math.max(0, i - 40), strain_volumetric = sa * (1 - nu) / E + crack_v }
end
local th = M.thresholds({ rows = rows, ipeak = 101, E = E, nu = nu }, { fraction = 0.05 })
-- 5% of the 60 cracks at the peak = 3: i = 43
T.check(th.ci.row == 44, "crack initiation row " .. th.ci.row)
T.near(th.ci.ratio, 0.43, 1e-12, "crack initiation ratio")
T.check(th.ci.cracks == 3, "cracks at initiation")
-- the crack volumetric strain at the peak, -60e-6 - 20 x 2e-5 = -4.6e-4; 5% of it, -2.3e-5, is
-- first reached at i = 63
T.check(th.ci_strain.row == 64, "crack initiation (strain) row " .. th.ci_strain.row)
T.near(th.ci_strain.ratio, 0.63, 1e-12, "crack initiation (strain) ratio")
T.check(th.cd.row == 81, "crack damage row " .. th.cd.row)
T.near(th.cd.ratio, 0.8, 1e-12, "crack damage ratio")
-- no cracks before the peak: no crack initiation
local quiet = {}
for i = 1, 10 do quiet[i] = { ea = i * 1e-5, sa = i * 1e6, cracks = 0, strain_volumetric = i * 1e-5 } end
T.check(M.thresholds({ rows = quiet, ipeak = 10, E = 1e11, nu = 0 }).ci == nil, "no cracks, no initiation")

print(string.format("material_envelope_fit: %d checks", T.checks))
