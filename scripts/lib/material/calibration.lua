-- SPDX-License-Identifier: MIT
-- material/calibration.lua: a bonded material's micro-parameters fitted to several laboratory
-- targets at once (E, nu, UCS, tensile strength, friction angle), by calibrate.fit_targets over
-- UCS, Brazilian and biaxial tests on packings made once per seed; every test through talus.map
-- (all cores, MPI ranks), resumable from its checkpoints (docs/material.md, "Calibration against
-- several targets").
local U = require("material.util")
local S = require("material.specimen")
local C = require("material.compress")
local Br = require("material.brazilian")
local Env = require("material.envelope")
local RS = require("talus_util.response_surface")
local raise = require("talus_util.errors").raise

local M = {}

-- The outputs a calibration can aim at, from the tests of one point.
M.outputs = { "E", "nu", "ucs", "tensile", "ratio", "phi", "E_elastic", "nu_elastic" }
local kOutput = U.set_of(M.outputs)

-- A short key for a long description (talus.map's checkpoint key): FNV-1a, 64 bits.
local hash = require("talus_util.random").fnv1a
M.hash = hash

local kKnown = U.set_of { "material", "packing", "disk", "params", "fixed", "targets", "seeds", "confinement", "budget",
    "jobs", "checkpoint", "key", "csv", "tests", "radius", "min_radius", "design", "quiet", "report_phi" }

-- M.calibrate's steps, over one state table `cs`.

--- The checked spec: the tests a point needs (`kinds`), the seeds, how progress is said.
local function calibration_state(spec)
    U.check_known(spec, kKnown, "calibrate")
    local cs = {
        spec = spec,
        material = U.req(spec, "material", "calibrate"),
        packing = U.req(spec, "packing", "calibrate"),
        targets = U.req(spec, "targets", "calibrate"),
        params = U.req(spec, "params", "calibrate"),
        seeds = spec.seeds or { 1, 2 },
        confinement = spec.confinement or 10e6,
        tests = spec.tests or {},
        fixed = spec.fixed or {},
        need = {},
    }
    for i, t in ipairs(cs.targets) do
        if not kOutput[t.name] then
            raise("material.calibrate: targets[%d] is '%s' (known: %s)", i, tostring(t.name), table.concat(M.outputs, ", "))
        end
        cs.need[t.name] = true
    end
    cs.kinds = { "ucs" }
    if cs.need.tensile or cs.need.ratio then
        if not spec.disk then raise("material.calibrate: a tensile or ratio target needs 'disk'") end
        cs.kinds[#cs.kinds + 1] = "brazilian"
    end
    if cs.need.phi or spec.report_phi then cs.kinds[#cs.kinds + 1] = "biaxial" end
    cs.say = spec.quiet and function() end or function(text)
        if talus.rank() == 0 then print(text); io.stdout:flush() end
    end
    return cs
end

--- talus.map's options for a sub-directory of the checkpoint.
local function map_opts(cs, sub, key)
    local o = { jobs = cs.spec.jobs }
    if cs.spec.checkpoint then o.checkpoint, o.key = cs.spec.checkpoint .. "/" .. sub, key end
    return o
end

--- The packings, once per seed (and a disk per seed when a test needs one): cs.blocks,
--- cs.disks, cs.cpu_pk.
local function make_packings(cs)
    local spec, seeds = cs.spec, cs.seeds
    local pk_items = {}
    for k, seed in ipairs(seeds) do
        pk_items[#pk_items + 1] = { k = k, seed = seed, kind = "block" }
        if spec.disk and (cs.need.tensile or cs.need.ratio) then
            pk_items[#pk_items + 1] = { k = k, seed = seed, kind = "disk" }
        end
    end
    local pk_list = talus.map(#pk_items, function(i)
        local it = pk_items[i]
        local c0 = U.clock()
        local pk = it.kind == "block" and cs.packing(it.seed) or spec.disk(it.seed)
        pk.cpu_genesis = U.clock() - c0
        return pk
    end, map_opts(cs, "packings", hash("packings " .. table.concat(seeds, ",") .. " " .. (spec.key or ""))))
    cs.blocks, cs.disks, cs.cpu_pk = {}, {}, 0
    for i, it in ipairs(pk_items) do
        local pk = pk_list[i]
        if not pk then
            raise("material.calibrate: the %s packing of seed %d failed: %s", it.kind, it.seed,
                pk_list.failed and pk_list.failed[1].message or "?")
        end
        cs.cpu_pk = cs.cpu_pk + (pk.cpu_genesis or 0)
        if it.kind == "block" then cs.blocks[it.k] = pk else cs.disks[it.k] = pk end
    end
    cs.say(string.format("calibrate: %d packings made (%.0f s CPU)", #pk_items, cs.cpu_pk))
end

--- One test: `kind` on seed k at point p.
local function run_test(cs, p, k, kind)
    local c0 = U.clock()
    local seed, tests = cs.seeds[k], cs.tests
    local mat = cs.material(p, seed)
    if kind == "brazilian" then
        local md = Br.with_jaw_friction(mat, tests.platen_fric or 0.5)
        local so = U.merged({ balls = Br.disk(cs.disks[k]) }, tests.disk)
        local b = Br.brazilian(S.specimen(cs.disks[k], md, so), U.merged(tests.brazilian))
        return { seed = seed, kind = kind, tensile = b.tensile, valid = b.valid, steps = b.steps, stop = b.stop,
                 cpu = U.clock() - c0 }
    end
    local o = U.merged({ post_peak = 0.8 }, tests.ucs)
    if kind == "biaxial" then o.confinement = cs.confinement end
    local r = C.compress(S.specimen(cs.blocks[k], mat, { sides = kind == "biaxial" }), o)
    return { seed = seed, kind = kind, peak = r.ucs, E = r.E, nu = r.nu, E_elastic = r.E_elastic,
             nu_elastic = r.nu_elastic, steps = r.steps, stop = r.stop, cpu = U.clock() - c0 }
end

local function mean_sd(list)
    local m, s = Env.mean_sd_list(list)
    return m, s
end

--- The outputs of a point from its tests.
local function outputs(cs, res)
    local ucs, E, nu, ten_valid, ten_all, biax, cpu = {}, {}, {}, {}, {}, {}, 0
    local E_el, nu_el = {}, {}
    for _, r in ipairs(res) do
        cpu = cpu + r.cpu
        if r.kind == "ucs" then
            ucs[r.seed], E[#E + 1], nu[#nu + 1] = r.peak, r.E, r.nu
            E_el[#E_el + 1], nu_el[#nu_el + 1] = r.E_elastic, r.nu_elastic
        elseif r.kind == "biaxial" then
            biax[r.seed] = r.peak
        else
            ten_all[#ten_all + 1] = r.tensile
            if r.valid then ten_valid[#ten_valid + 1] = r.tensile end
        end
    end
    local o = { tests = res, cpu = cpu }
    local u = {}
    for _, v in pairs(ucs) do u[#u + 1] = v end
    o.ucs, o.ucs_sd = mean_sd(u)
    o.E, o.E_sd = mean_sd(E)
    o.nu, o.nu_sd = mean_sd(nu)
    o.E_elastic, o.E_elastic_sd = mean_sd(E_el)
    o.nu_elastic, o.nu_elastic_sd = mean_sd(nu_el)
    if #ten_all > 0 then
        -- the tests that split; all of them when none did (said by tensile_valid = 0)
        o.tensile, o.tensile_sd = mean_sd(#ten_valid > 0 and ten_valid or ten_all)
        o.tensile_valid = #ten_valid
        if o.ucs and o.tensile then o.ratio = o.ucs / o.tensile end
    end
    local phis = {}
    for seed, s1 in pairs(biax) do
        if ucs[seed] then
            local mc = Env.mohr_coulomb({ { 0, ucs[seed] }, { cs.confinement, s1 } })
            phis[#phis + 1] = mc.phi
        end
    end
    o.phi, o.phi_sd = mean_sd(phis)
    return o
end

--- fit_targets' evaluate: every test of every point of a batch through talus.map (one
--- checkpoint directory per batch, keyed by the points, seeds, tests and key).
local function evaluate(cs, points, batch)
    local spec, seeds, kinds = cs.spec, cs.seeds, cs.kinds
    local items, desc = {}, {}
    for i, x in ipairs(points) do
        local p = U.merged(cs.fixed, x)
        local names = {}
        for name in pairs(p) do names[#names + 1] = name end
        table.sort(names)
        local d = {}
        for _, name in ipairs(names) do d[#d + 1] = name .. "=" .. string.format("%a", p[name]) end
        desc[i] = table.concat(d, ",")
        for k = 1, #seeds do
            for _, kind in ipairs(kinds) do items[#items + 1] = { i = i, k = k, kind = kind, p = p } end
        end
    end
    local key = hash(table.concat(desc, ";") .. "|" .. table.concat(seeds, ",") .. "|" .. table.concat(kinds, ",")
        .. "|" .. cs.confinement .. "|" .. (spec.key or ""))
    local res = talus.map(#items, function(j)
        local it = items[j]
        return run_test(cs, it.p, it.k, it.kind)
    end, map_opts(cs, string.format("batch_%03d", batch), key))
    local per = {}
    for i = 1, #points do per[i] = {} end
    for j, it in ipairs(items) do
        if res[j] then table.insert(per[it.i], res[j]) end
    end
    local outs = {}
    for i = 1, #points do
        outs[i] = outputs(cs, per[i])
        cs.total_cpu = cs.total_cpu + outs[i].cpu
    end
    return outs
end

--- A progress line for one evaluated point.
local function fmt_row(cs, row)
    local parts = {}
    for _, d in ipairs(cs.params) do parts[#parts + 1] = string.format("%s %.4g", d.name, row.params[d.name]) end
    local o = row.out or {}
    local outs = {}
    for _, n in ipairs(M.outputs) do
        if o[n] then
            local scale = (n == "E") and 1e-9 or ((n == "ucs" or n == "tensile") and 1e-6 or 1)
            outs[#outs + 1] = string.format("%s %.4g", n, o[n] * scale)
        end
    end
    return string.format("point %d (%s): %s -> %s; misfit %.4g%s", row.index, row.phase, table.concat(parts, ", "),
        table.concat(outs, ", "), row.misfit, row.met and " (targets met)" or "")
end

--- Runs a calibration. spec:
---   material(p, seed) -> M.specimen's material table, p = the point's parameters (name = value:
---       the searched ones over `fixed`)
---   packing(seed) -> the packing of the UCS and biaxial specimens (made once per seed)
---   disk(seed) -> the Brazilian disk's packing (M.genesis_disk; made once per seed), needed
---       when a target is tensile or ratio
---   params = {{name =, lo =, hi =, start =, spread =}, ...} (calibrate.fit_targets), fixed = {}
---   targets = {{name =, value =, weight = 1, tol = 0.05}, ...}, names among E, nu (at 50% of
---       the peak), E_elastic, nu_elastic (over 10-30% of it, M.compress), ucs, tensile, ratio
---       (ucs / tensile) and phi (Mohr-Coulomb, from the UCS test and one biaxial test at
---       `confinement` per seed)
---   seeds = {1, 2}: every point is tested on the same packings (common random numbers: the
---       differences between points are not blurred by the packings' scatter)
---   confinement = 10e6 (Pa), report_phi (run the biaxial test without a phi target)
---   budget = points at most (calibrate.fit_targets), radius, min_radius, design
---   tests = { ucs = M.compress's options (post_peak 0.8), brazilian = M.brazilian's (its
---       defaults), disk = M.specimen's options for the disk, platen_fric = the Brazilian jaws'
---       friction (0.5) }
---   jobs = talus.map's; checkpoint = a directory: every test is kept there as it finishes
---       (talus.map's checkpoint, one directory per batch of points, keyed by the points, the
---       seeds and `key`), so a calibration run again after an interruption takes what was done
---       and continues; key = a string naming the material (change it when material() changes)
---   csv = a file: one row per point (parameters, outputs with their sd over seeds, misfit)
---   quiet: no progress lines
--- Returns calibrate.fit_targets's result; each row's out also has E_sd, nu_sd, ucs_sd,
--- tensile_sd, phi_sd, tensile_valid (the Brazilian tests that split), tests (per test: seed,
--- kind, values, cpu) and cpu (the CPU seconds of its tests); plus cpu = the calibration's CPU
--- seconds (tests and packings), packings = the packings' CPU seconds.
function M.calibrate(spec)
    local cs = calibration_state(spec)
    make_packings(cs)
    cs.total_cpu = cs.cpu_pk
    local result = RS.fit_targets{
        params = cs.params, targets = cs.targets, budget = spec.budget, radius = spec.radius,
        min_radius = spec.min_radius, design = spec.design,
        evaluate = function(points, batch) return evaluate(cs, points, batch) end,
        on_point = function(row) cs.say("calibrate: " .. fmt_row(cs, row)) end,
    }
    result.cpu, result.packings = cs.total_cpu, cs.cpu_pk
    result.tests_per_point = #cs.seeds * #cs.kinds
    if spec.csv and talus.rank() == 0 then M.write_csv(spec.csv, result, cs.params, cs.targets) end
    return result
end

--- The rows of a calibration as CSV: index, batch, phase, the parameters, every output with its
--- sd over seeds, tensile_valid, misfit, met, cpu; and beside it NAME_targets.csv (name, value,
--- tol, weight) for scripts/plot_calibration.py.
function M.write_csv(file, result, params, targets)
    local cols = { "index", "batch", "phase" }
    for _, d in ipairs(params) do cols[#cols + 1] = d.name end
    for _, n in ipairs(M.outputs) do cols[#cols + 1] = n; cols[#cols + 1] = n .. "_sd" end
    for _, n in ipairs({ "tensile_valid", "misfit", "met", "best", "cpu" }) do cols[#cols + 1] = n end
    local rows = {}
    for i, r in ipairs(result.rows) do
        local row = { index = r.index, batch = r.batch, phase = r.phase, misfit = r.misfit < math.huge and r.misfit or nil,
                      met = r.met and 1 or 0, best = r == result.best and 1 or 0 }
        for k, v in pairs(r.params) do row[k] = v end
        for k, v in pairs(r.out or {}) do
            if type(v) == "number" then row[k] = v end
        end
        rows[i] = row
    end
    U.write_csv(file, rows, cols)
    local trows = {}
    for i, t in ipairs(targets) do trows[i] = { name = t.name, value = t.value, tol = t.tol or 0.05, weight = t.weight or 1 } end
    U.write_csv((file:gsub("%.csv$", "")) .. "_targets.csv", trows, { "name", "value", "tol", "weight" })
end

return M
