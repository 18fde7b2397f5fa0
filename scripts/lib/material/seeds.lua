-- SPDX-License-Identifier: MIT
-- material/seeds.lua: a material's laboratory table over seeds: per seed a UCS test, a Brazilian
-- test and, when asked, biaxial tests for the friction angle; their means and scatter.
local U = require("material.util")
local S = require("material.specimen")
local C = require("material.compress")
local Br = require("material.brazilian")
local Env = require("material.envelope")
local L = require("material.loading")

local Sd = {}

local kKnown = U.set_of { "material", "genesis", "disk", "seeds", "scale", "width", "height", "diameter",
    "confinements", "platen_fric", "jobs", "checkpoint", "key", "outdir", "name", "strain_per_crossing", "rate",
    "max_steps", "hold" }

--- Runs the table. spec:
---   material = M.specimen's material table (each seed gets mat.seed = its seed)
---   genesis(width, height, seed), disk(diameter, seed): the packings (M.lac_du_bonnet's)
---   seeds = {1, ..., 5}; scale (1): the specimen's size factor; width (0.0317 m), height
---   (0.0634 m), diameter (0.98 width) at scale 1; the disk's genesis seed is 100 + seed
---   confinements = {} (Pa): biaxial tests on the UCS specimen's packing; with one or more, phi,
---   c (Mohr-Coulomb) and m_i (Hoek-Brown) per seed from those and the UCS test
---   platen_fric = the Brazilian jaws' friction (0.5); jobs, checkpoint, key: talus.map's
---   outdir, name: when given, histories and crack lists are written there as
---   NAME_ucs_<seed>.csv, NAME_brazilian_<seed>.csv, NAME_biaxial_<sigma3 MPa>_<seed>.csv
---   strain_per_crossing or rate (1/s), max_steps, hold: every test's loading (M.compress's; the
---   default rate, its step cap and the platens' equilibrium hold when not given)
--- Returns { rows = {{seed, balls, porosity, ucs, E, nu, tensile (only from a disk that split),
--- tensile_peak (the Brazilian test's peak, whatever it measured), valid, reason, ratio (UCS over
--- a valid tensile strength), phi, c, m_i, peaks = {[sigma3] = sigma1}, steps, stop, ci_ratio,
--- cd_ratio, qs_difference, qs_kinetic (how far from quasi-static the UCS test ran at its peak:
--- the platen stress difference, the kinetic over the stored energy, the mechanical ratio),
--- held, holds (the UCS test's steps with the platens held, and its holds), cpu, cpu_ucs,
--- cpu_brazilian, cpu_biaxial (s)}, ...}, failed
--- (talus.map's), cpu (tests and packings, s), cpu_packings }. Statistics: Sd.stat.
function Sd.run(spec)
    U.check_known(spec, kKnown, "run_seeds")
    local mat = U.req(spec, "material", "run_seeds")
    local genesis = U.req(spec, "genesis", "run_seeds")
    local disk = U.req(spec, "disk", "run_seeds")
    local seeds = spec.seeds or { 1, 2, 3, 4, 5 }
    local scale = spec.scale or 1
    local W, H = (spec.width or 0.0317) * scale, (spec.height or 0.0634) * scale
    local D = (spec.diameter or 0.98 * (spec.width or 0.0317)) * scale
    local confs = spec.confinements or {}
    -- the packings' checkpoint is keyed by `key`; the tests' also by their loading (a rerun at
    -- another rate makes its tests again on the same packings)
    local function map_opts(sub, extra)
        local o = { jobs = spec.jobs }
        if spec.checkpoint then o.checkpoint, o.key = spec.checkpoint .. "/" .. sub, (spec.key or "") .. (extra or "") end
        return o
    end
    local pitems = {}
    for k, seed in ipairs(seeds) do
        pitems[#pitems + 1] = { k = k, seed = seed, kind = "block" }
        pitems[#pitems + 1] = { k = k, seed = seed, kind = "disk" }
    end
    local pks = talus.map(#pitems, function(i)
        local it = pitems[i]
        local c0 = U.clock()
        local pk = it.kind == "block" and genesis(W, H, it.seed) or disk(D, 100 + it.seed)
        pk.cpu_genesis = U.clock() - c0
        return pk
    end, map_opts("packings"))
    local blocks, disks, cpu_pk = {}, {}, 0
    for i, it in ipairs(pitems) do
        local pk = pks[i]
        if pk then
            cpu_pk = cpu_pk + pk.cpu_genesis
            if it.kind == "block" then blocks[it.k] = pk else disks[it.k] = pk end
        end
    end
    local items = {}
    for k, seed in ipairs(seeds) do
        items[#items + 1] = { k = k, seed = seed, kind = "ucs" }
        items[#items + 1] = { k = k, seed = seed, kind = "brazilian" }
        for _, s3 in ipairs(confs) do items[#items + 1] = { k = k, seed = seed, kind = "biaxial", confinement = s3 } end
    end
    local function file(kind, it)
        if not spec.outdir then return nil end
        local tag = kind == "biaxial" and string.format("biaxial_%g", it.confinement / 1e6) or kind
        return string.format("%s/%s_%s_%d.csv", spec.outdir, spec.name or "ldb", tag, it.seed)
    end
    local loading = { strain_per_crossing = spec.strain_per_crossing, rate = spec.rate, max_steps = spec.max_steps,
                      hold = spec.hold }
    local res = talus.map(#items, function(i)
        local it = items[i]
        local c0 = U.clock()
        local m = U.merged(mat, { seed = it.seed })
        if it.kind == "brazilian" then
            local pd = disks[it.k]
            if not pd then error("the disk packing of seed " .. it.seed .. " failed") end
            m = Br.with_jaw_friction(m, spec.platen_fric or 0.5)
            local b = Br.brazilian(S.specimen(pd, m, { balls = Br.disk(pd) }),
                U.merged(loading, { csv = file("brazilian", it) }))
            return { kind = it.kind, seed = it.seed, tensile = b.tensile, peak = b.peak, valid = b.valid, reason = b.reason,
                     stop = b.stop, steps = b.steps, balls = b.balls, cpu = U.clock() - c0 }
        end
        local pk = blocks[it.k]
        if not pk then error("the block packing of seed " .. it.seed .. " failed") end
        local r = C.compress(S.specimen(pk, m, { sides = it.kind == "biaxial" }),
            U.merged(loading, { post_peak = 0.8, confinement = it.confinement, csv = file(it.kind, it) }))
        local th = Env.thresholds(r)
        local q = r.quasi_static
        return { kind = it.kind, seed = it.seed, confinement = it.confinement or 0, peak = r.ucs, E = r.E, nu = r.nu,
                 E_elastic = r.E_elastic, nu_elastic = r.nu_elastic, stop = r.stop, steps = r.steps, balls = r.balls,
                 porosity = pk.porosity, ci_ratio = th.ci and th.ci.ratio, cd_ratio = th.cd and th.cd.ratio,
                 qs_difference = q.difference_peak, qs_kinetic = q.kinetic_peak, qs_ratio = q.ratio_peak, held = r.held,
                 holds = r.holds, cpu = U.clock() - c0 }
    end, map_opts("tests", string.format(" rate %s %s max_steps %s hold %s", tostring(spec.strain_per_crossing),
        tostring(spec.rate), tostring(spec.max_steps), L.hold_key(spec.hold))))
    local rows, by_seed, cpu = {}, {}, cpu_pk
    for k, seed in ipairs(seeds) do
        rows[k] = { seed = seed, peaks = {}, cpu = 0 }
        by_seed[seed] = rows[k]
    end
    for i, it in ipairs(items) do
        local r = res[i]
        local row = by_seed[it.seed]
        if r then
            cpu = cpu + r.cpu
            row.cpu = row.cpu + r.cpu
            row["cpu_" .. r.kind] = (row["cpu_" .. r.kind] or 0) + r.cpu
            if r.kind == "ucs" then
                row.ucs, row.E, row.nu, row.balls, row.porosity = r.peak, r.E, r.nu, r.balls, r.porosity
                row.E_elastic, row.nu_elastic = r.E_elastic, r.nu_elastic
                row.stop, row.steps, row.ci_ratio, row.cd_ratio = r.stop, r.steps, r.ci_ratio, r.cd_ratio
                row.qs_difference, row.qs_kinetic, row.qs_ratio = r.qs_difference, r.qs_kinetic, r.qs_ratio
                row.held, row.holds = r.held, r.holds
            elseif r.kind == "brazilian" then
                row.tensile, row.tensile_peak, row.valid, row.reason = r.tensile, r.peak, r.valid == true, r.reason
                row.stop_brazilian, row.steps_brazilian = r.stop, r.steps
            else
                row.peaks[r.confinement] = r.peak
            end
        end
    end
    for _, row in ipairs(rows) do
        -- a ratio only over a tensile strength (tensile is nil for a disk that did not split)
        if row.ucs and row.tensile and row.valid then row.ratio = row.ucs / row.tensile end
        if row.ucs and next(row.peaks) then
            local pts = { { 0, row.ucs } }
            for s3, s1 in pairs(row.peaks) do pts[#pts + 1] = { s3, s1 } end
            table.sort(pts, function(a, b) return a[1] < b[1] end)
            local mc = Env.mohr_coulomb(pts)
            row.phi, row.c = mc.phi, mc.c
            row.m_i = Env.hoek_brown(pts, row.ucs).m_i
        end
    end
    return { rows = rows, failed = res.failed, cpu = cpu, cpu_packings = cpu_pk, confinements = confs }
end

--- Mean, sd and count of `key` over the rows that have it (tensile and ratio: the Brazilian tests
--- that split, M.brazilian's `valid`).
function Sd.stat(rows, key)
    local list = {}
    for _, r in ipairs(rows) do
        local v = r[key]
        if v and ((key ~= "tensile" and key ~= "ratio") or r.valid) then list[#list + 1] = v end
    end
    return Env.mean_sd_list(list)
end

--- Prints the table of Sd.run's result and its means; returns the summary { ucs = {mean, sd,
--- n}, E, nu, E_elastic, nu_elastic, tensile, ratio, phi, c, m_i }.
function Sd.print(res, title)
    if title then print(title) end
    print("seed balls porosity UCS[MPa] E[GPa]  nu     E_el   nu_el  sigma_t[MPa]  UCS/sigma_t phi[deg] CI/UCS CD/UCS "
        .. "stop(UCS) steps   held   dF/F   Ek/Es  ratio")
    for _, r in ipairs(res.rows) do
        -- a disk that did not split: no tensile strength; its peak in brackets, marked *
        local ten = r.tensile and string.format("%.2f", r.tensile / 1e6)
            or (r.tensile_peak and string.format("(%.2f)*", r.tensile_peak / 1e6)) or "-"
        print(string.format("%4d %5s  %5s  %8s %6s  %5s  %5s  %5s  %11s  %8s   %6s    %4s   %4s   %-9s %6s %6s  %.1e %.1e %.1e",
            r.seed, r.balls or "-", r.porosity and string.format("%.3f", r.porosity) or "-",
            r.ucs and string.format("%.1f", r.ucs / 1e6) or "-", r.E and string.format("%.1f", r.E / 1e9) or "-",
            r.nu and string.format("%.3f", r.nu) or "-", r.E_elastic and string.format("%.1f", r.E_elastic / 1e9) or "-",
            r.nu_elastic and string.format("%.3f", r.nu_elastic) or "-", ten,
            r.ratio and string.format("%.1f", r.ratio) or "-", r.phi and string.format("%.1f", r.phi) or "-",
            r.ci_ratio and string.format("%.2f", r.ci_ratio) or "-", r.cd_ratio and string.format("%.2f", r.cd_ratio) or "-",
            r.stop or "-", r.steps or "-", r.held or "-", r.qs_difference or 0 / 0, r.qs_kinetic or 0 / 0,
            r.qs_ratio or 0 / 0))
    end
    local sum = {}
    local parts = {}
    for _, k in ipairs({ "ucs", "E", "nu", "E_elastic", "nu_elastic", "tensile", "ratio", "phi", "c", "m_i" }) do
        local m, s, n = Sd.stat(res.rows, k)
        sum[k] = { mean = m, sd = s, n = n }
        if m then
            local scale, unit, f = 1, "", "%.3f"
            if k == "ucs" or k == "tensile" or k == "c" then scale, unit, f = 1e-6, " MPa", "%.2f" end
            if k == "E" or k == "E_elastic" then scale, unit, f = 1e-9, " GPa", "%.1f" end
            if k == "ratio" or k == "phi" or k == "m_i" then f = "%.1f" end
            if k == "phi" then unit = " deg" end
            parts[#parts + 1] = string.format("%s " .. f .. " +- " .. f .. "%s (%d)", k == "ucs" and "UCS" or
                (k == "tensile" and "sigma_t" or (k == "ratio" and "UCS/sigma_t" or k)), m * scale, s * scale, unit, n)
        end
    end
    print("mean +- sd (n): " .. table.concat(parts, ", "))
    for _, r in ipairs(res.rows) do
        if r.tensile_peak and not r.valid then
            print(string.format("* seed %d: the disk gave no tensile strength (left out of sigma_t and UCS/sigma_t): %s",
                r.seed, r.reason))
        end
    end
    print("dF/F: the platen stress difference over its mean at the UCS peak; Ek/Es: kinetic over stored energy there")
    if res.failed then
        for _, f in ipairs(res.failed) do print("failed: " .. f.message) end
    end
    return sum
end

return Sd
