-- SPDX-License-Identifier: MIT
-- material/envelope.lua: the strength envelope of a bonded material: biaxial tests at several
-- confinements over seeds, the Mohr-Coulomb and Hoek-Brown fits of their peaks, and the crack
-- initiation and crack damage thresholds of each test (docs/material.md, "Strength envelope").
local U = require("material.util")
local S = require("material.specimen")
local C = require("material.compress")
local St = require("material.statistics")
local raise = require("talus_util.errors").raise

local Env = {}

-- points: {{s3, s1}, ...} or {{sigma3 =, sigma1 =}, ...}; returns two lists
local function xy(points, where)
    local xs, ys = {}, {}
    for i, p in ipairs(points) do
        local x, y = p.sigma3 or p[1], p.sigma1 or p[2]
        if type(x) ~= "number" or type(y) ~= "number" or x ~= x or y ~= y then
            raise(string.format("material.%s: point %d is not a pair of numbers {sigma3, sigma1}", where, i))
        end
        xs[i], ys[i] = x, y
    end
    return xs, ys
end

--- The Mohr-Coulomb envelope of peak stresses: least squares of sigma1 = a + k sigma3 over
--- `points` = {{sigma3, sigma1}, ...} (compression positive, Pa; at least two distinct sigma3),
--- then k = (1 + sin phi) / (1 - sin phi) and a = 2 c cos phi / (1 - sin phi) = 2 c sqrt(k):
--- phi = asin((k - 1) / (k + 1)), c = a / (2 sqrt(k)). Returns { c (Pa), phi (degrees),
--- intercept = a (the fitted uniaxial strength), slope = k, rms (of the sigma1 residuals), n }.
--- A slope k <= 1 (sigma1 - sigma3 falling with the confinement) gives phi <= 0 and c = nil.
function Env.mohr_coulomb(points)
    local xs, ys = xy(points, "mohr_coulomb")
    local n = #xs
    local mx, my = 0, 0
    for i = 1, n do mx = mx + xs[i]; my = my + ys[i] end
    mx, my = mx / n, my / n
    local sxx, sxy = 0, 0
    for i = 1, n do sxx = sxx + (xs[i] - mx) ^ 2; sxy = sxy + (xs[i] - mx) * (ys[i] - my) end
    if n < 2 or sxx == 0 then
        raise("material.mohr_coulomb: needs points at two or more confinements")
    end
    local k = sxy / sxx
    local a = my - k * mx
    local res = 0
    for i = 1, n do res = res + (ys[i] - a - k * xs[i]) ^ 2 end
    local sinphi = (k - 1) / (k + 1)
    return { phi = math.deg(math.asin(math.max(-1, math.min(1, sinphi)))), c = k > 1 and a / (2 * math.sqrt(k)) or nil,
             intercept = a, slope = k, rms = math.sqrt(res / n), n = n }
end

--- The Hoek-Brown envelope of intact rock, sigma1 = sigma3 + sigma_ci sqrt(m_i sigma3 / sigma_ci
--- + 1) (Hoek & Brown 1980), fitted as Hoek & Brown (1997) do: the linear least squares of
--- y = (sigma1 - sigma3)^2 against x = sigma3, y = sigma_ci^2 + m_i sigma_ci x. With `sigma_ci`
--- given (the uniaxial strength measured by UCS tests) only m_i is fitted: the line through
--- (0, sigma_ci^2), m_i = sum x (y - sigma_ci^2) / (sigma_ci sum x^2); without it both
--- (sigma_ci^2 = the intercept). Returns { m_i, sigma_ci, rms (of sigma1), n }.
function Env.hoek_brown(points, sigma_ci)
    local xs, ys = xy(points, "hoek_brown")
    local n = #xs
    local X, Y = {}, {}
    for i = 1, n do X[i] = xs[i]; Y[i] = (ys[i] - xs[i]) ^ 2 end
    local m
    if sigma_ci then
        if not (sigma_ci > 0) then raise("material.hoek_brown: sigma_ci must be > 0") end
        local sxx, sxy = 0, 0
        for i = 1, n do sxx = sxx + X[i] * X[i]; sxy = sxy + X[i] * (Y[i] - sigma_ci ^ 2) end
        if sxx == 0 then raise("material.hoek_brown: needs a point with sigma3 > 0") end
        m = sxy / (sigma_ci * sxx)
    else
        local mx, my = 0, 0
        for i = 1, n do mx = mx + X[i]; my = my + Y[i] end
        mx, my = mx / n, my / n
        local sxx, sxy = 0, 0
        for i = 1, n do sxx = sxx + (X[i] - mx) ^ 2; sxy = sxy + (X[i] - mx) * (Y[i] - my) end
        if n < 2 or sxx == 0 then raise("material.hoek_brown: needs points at two or more confinements") end
        local slope = sxy / sxx
        local icpt = my - slope * mx
        if not (icpt > 0) then raise("material.hoek_brown: the fitted sigma_ci^2 is not positive") end
        sigma_ci = math.sqrt(icpt)
        m = slope / sigma_ci
    end
    local res = 0
    for i = 1, n do
        local q = m * xs[i] / sigma_ci + 1
        local s1 = xs[i] + sigma_ci * math.sqrt(math.max(0, q))
        res = res + (ys[i] - s1) ^ 2
    end
    return { m_i = m, sigma_ci = sigma_ci, rms = math.sqrt(res / n), n = n }
end

--- The crack initiation and crack damage thresholds of a compression test (M.compress's result;
--- Martin & Chandler 1994), as axial stresses:
---   ci: crack initiation, where the crack count first reaches `fraction` (0.05) of its count at
---       the peak (and at least one crack): the onset of steady cracking, not the first stray
---       break. Returns { stress, ratio (to the peak), cracks, strain_axial, row }.
---   ci_strain: the same on the crack volumetric strain, Martin & Chandler's measure: the
---       volumetric strain less its elastic part, eps_v - (sigma_a - sigma_a0) (1 - nu) / E
---       (a 2D disk assembly loaded along one axis, its E and nu those of the test), from where
---       it stays below `fraction` x its value at the peak (it is negative: dilation).
---   cd: crack damage, the reversal of the volumetric strain (statistics.lua, crack_damage),
---       with ratio.
--- opts: fraction (0.05). A field is nil when the test has no such point (no cracks before the
--- peak, no volumetric strain).
function Env.thresholds(res, opts)
    opts = opts or {}
    local f = opts.fraction or 0.05
    local rows, ipeak = res.rows, res.ipeak
    local peak = rows[ipeak].sa
    local out = {}
    local nmax = rows[ipeak].cracks or 0
    if nmax > 0 then
        local need = math.max(1, f * nmax)
        for i = 1, ipeak do
            if (rows[i].cracks or 0) >= need then
                out.ci = { stress = rows[i].sa, ratio = rows[i].sa / peak, cracks = rows[i].cracks,
                           strain_axial = rows[i].ea, row = i }
                break
            end
        end
    end
    if res.E and res.nu and rows[1].strain_volumetric then
        local s0 = rows[1].sa
        local function crack_strain(r) return r.strain_volumetric - (r.sa - s0) * (1 - res.nu) / res.E end
        local vpeak = crack_strain(rows[ipeak])
        if vpeak < 0 then
            -- the row from which it stays below (the lateral strain of a UCS test, read from the
            -- side balls, is noisy early on)
            local first
            for i = ipeak, 1, -1 do
                if crack_strain(rows[i]) > f * vpeak then break end
                first = i
            end
            local r = rows[first]
            out.ci_strain = { stress = r.sa, ratio = r.sa / peak, strain_axial = r.ea, crack_volumetric = crack_strain(r),
                              row = first }
        end
    end
    local cd = res.crack_damage or St.crack_damage(rows, ipeak)
    if cd then
        cd.ratio = cd.stress / peak
        out.cd = cd
    end
    return out
end

-- mean, sd over a list of numbers (nil entries left out)
local function mean_sd(list)
    local n, s = 0, 0
    for _, v in pairs(list) do n = n + 1; s = s + v end
    if n == 0 then return nil, nil, 0 end
    local mean, s2 = s / n, 0
    for _, v in pairs(list) do s2 = s2 + (v - mean) ^ 2 end
    return mean, n > 1 and math.sqrt(s2 / (n - 1)) or 0, n
end
Env.mean_sd_list = mean_sd

--- Fits the envelope of a set of tests: tests = {{seed =, confinement =, peak =}, ...}.
--- Per seed (its tests at two or more confinements): Mohr-Coulomb c, phi and Hoek-Brown m_i with
--- sigma_ci = that seed's uniaxial strength (its test at confinement 0, else the Mohr-Coulomb
--- intercept); then their mean and sd over the seeds, and the fits of all points together
--- (m_i with sigma_ci = the mean uniaxial strength). Returns { seeds = {{seed, c, phi, m_i,
--- sigma_ci, rms}, ...}, c = {mean, sd}, phi = {mean, sd}, m_i = {mean, sd}, pooled = {c, phi,
--- m_i, sigma_ci} }.
function Env.fit(tests)
    local by_seed, order = {}, {}
    for _, t in ipairs(tests) do
        if not by_seed[t.seed] then by_seed[t.seed] = {}; order[#order + 1] = t.seed end
        table.insert(by_seed[t.seed], t)
    end
    table.sort(order)
    local out = { seeds = {} }
    local all, ucs_list = {}, {}
    local cs, phis, ms = {}, {}, {}
    for _, seed in ipairs(order) do
        local pts, ucs, confs = {}, nil, {}
        for _, t in ipairs(by_seed[seed]) do
            pts[#pts + 1] = { t.confinement, t.peak }
            all[#all + 1] = { t.confinement, t.peak }
            confs[t.confinement] = true
            if t.confinement == 0 then ucs = t.peak end
        end
        local nconf = 0
        for _ in pairs(confs) do nconf = nconf + 1 end
        if ucs then ucs_list[#ucs_list + 1] = ucs end
        if nconf >= 2 then
            local mc = Env.mohr_coulomb(pts)
            local sci = ucs or mc.intercept
            local hb = sci > 0 and Env.hoek_brown(pts, sci) or {}
            out.seeds[#out.seeds + 1] = { seed = seed, c = mc.c, phi = mc.phi, m_i = hb.m_i, sigma_ci = sci,
                                          rms = mc.rms, hb_rms = hb.rms, points = #pts }
            cs[#cs + 1], phis[#phis + 1], ms[#ms + 1] = mc.c, mc.phi, hb.m_i
        end
    end
    local function ms_of(list)
        local m, s, n = mean_sd(list)
        return { mean = m, sd = s, n = n }
    end
    out.c, out.phi, out.m_i = ms_of(cs), ms_of(phis), ms_of(ms)
    local confs = {}
    for _, p in ipairs(all) do confs[p[1]] = true end
    local nconf = 0
    for _ in pairs(confs) do nconf = nconf + 1 end
    if nconf >= 2 then
        local mc = Env.mohr_coulomb(all)
        local sci = #ucs_list > 0 and (mean_sd(ucs_list)) or mc.intercept
        local hb = sci > 0 and Env.hoek_brown(all, sci) or {}
        out.pooled = { c = mc.c, phi = mc.phi, intercept = mc.intercept, slope = mc.slope, rms = mc.rms,
                       m_i = hb.m_i, sigma_ci = sci, hb_rms = hb.rms }
    end
    return out
end

local kKnown = U.set_of { "packing", "material", "confinements", "seeds", "test", "jobs", "checkpoint", "key",
    "fraction", "specimen" }

--- Runs the envelope: for every seed of `seeds` and every confinement of `confinements` (Pa; 0 is
--- the UCS test, without side walls), a compression test (M.compress) on a specimen of the
--- seed's packing, all through talus.map (on every core, across MPI ranks; a failed test is
--- recorded and left out). spec:
---   packing(seed) -> a packing (M.genesis ...; made once per seed, in a first talus.map)
---   material(seed) -> M.specimen's material table (a table: used for every seed, with
---     seed = the seed)
---   confinements = {0, 5e6, 10e6, 20e6} (Pa), seeds = {1, 2, 3}
---   test = M.compress's options (default post_peak 0.8), specimen = M.specimen's options
---   jobs, checkpoint, key: talus.map's (the tests' map; with checkpoint, the packings' map
---     uses checkpoint .. "/packings"), fraction: Env.thresholds's.
--- Returns Env.fit's result plus tests = {{seed, confinement, peak, deviator, E, nu, ci, ci_ratio,
--- ci_strain, cd, cd_ratio, cracks, stop, steps, balls, lateral (the side walls' mean stress up
--- to the peak), cpu}, ...} (in seed, then confinement order) and
--- failed (talus.map's list, nil when none).
function Env.run(spec)
    U.check_known(spec, kKnown, "envelope")
    local packing = U.req(spec, "packing", "envelope")
    local material = U.req(spec, "material", "envelope")
    local confs = spec.confinements or { 0, 5e6, 10e6, 20e6 }
    local seeds = spec.seeds or { 1, 2, 3 }
    for i, s3 in ipairs(confs) do
        if type(s3) ~= "number" or not (s3 >= 0) then
            raise(string.format("material.envelope: confinements[%d] must be a stress >= 0 (got %s)", i,
                tostring(s3)))
        end
    end
    local map_opts = function(sub)
        local o = { jobs = spec.jobs }
        if spec.checkpoint then
            o.checkpoint = spec.checkpoint .. sub
            o.key = spec.key or ""
        end
        return o
    end
    local pks = talus.map(#seeds, function(k) return packing(seeds[k]) end, map_opts("/packings"))
    local items = {}
    for k, seed in ipairs(seeds) do
        for _, s3 in ipairs(confs) do items[#items + 1] = { k = k, seed = seed, confinement = s3 } end
    end
    local res = talus.map(#items, function(i)
        local it = items[i]
        local pk = pks[it.k]
        if not pk then error(string.format("the packing of seed %d failed", it.seed)) end
        local t0 = U.clock()
        local mat = type(material) == "function" and material(it.seed) or material
        if type(material) ~= "function" then
            local copy = {}
            for key, v in pairs(mat) do copy[key] = v end
            copy.seed = it.seed
            mat = copy
        end
        local sopts = {}
        for key, v in pairs(spec.specimen or {}) do sopts[key] = v end
        sopts.sides = it.confinement > 0
        local sp = S.specimen(pk, mat, sopts)
        local topts = { post_peak = 0.8 }
        for key, v in pairs(spec.test or {}) do topts[key] = v end
        topts.confinement = it.confinement > 0 and it.confinement or nil
        local r = C.compress(sp, topts)
        local th = Env.thresholds(r, { fraction = spec.fraction })
        -- the side walls' mean stress up to the peak (the confinement the servo held)
        local lat, nlat = 0, 0
        for k = 2, r.ipeak do
            if r.rows[k].sl then lat = lat + r.rows[k].sl; nlat = nlat + 1 end
        end
        return { seed = it.seed, confinement = it.confinement, peak = r.ucs, deviator = r.ucs - it.confinement,
                 E = r.E, nu = r.nu, ci = th.ci and th.ci.stress, ci_ratio = th.ci and th.ci.ratio,
                 ci_strain = th.ci_strain and th.ci_strain.stress, cd = th.cd and th.cd.stress,
                 cd_ratio = th.cd and th.cd.ratio, cracks = #r.cracks, stop = r.stop, steps = r.steps,
                 balls = r.balls, lateral = nlat > 0 and lat / nlat or nil, cpu = U.clock() - t0 }
    end, map_opts(""))
    local tests = {}
    for i = 1, #items do
        if res[i] then tests[#tests + 1] = res[i] end
    end
    local out = Env.fit(tests)
    out.tests = tests
    out.failed = res.failed
    return out
end

return Env
