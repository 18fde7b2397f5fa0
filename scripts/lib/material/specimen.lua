-- SPDX-License-Identifier: MIT
-- material/specimen.lua: a bonded specimen built from a packing: the balls (its grains made
-- clumps), the loading walls (platens, side walls, or a disk's jaws), the bonds, relaxed.
local U = require("material.util")
local E = require("material.equilibrium")
local Wl = require("material.walls")
local J = require("material.jaws")
local raise = require("talus_util.errors").raise

local S = {}

--- Builds a model from a packing: the balls (group "rock"; the packing's grains made clumps
--- when it has them), platens at the packing's bottom and top (group "platen"), side walls when
--- opts.sides (group "side"), the bond model installed at every contact and near-contact
--- within `gap` between two different bodies (balls or clumps), then relaxed to the ratio.
--- mat = { model = "cbond"|"pbond"|..., kn, ks, fric, density, bond = {props of the bond
---         model, each a number or {mean, sd, dist}}, platen = {kn, ks, fric} (default: kn,
---         ks of the material, fric 0), damp (0.7), gap (default 1e-3 rmin), seed, slit =
---         {fraction, gap} (a flat joint's slit interfaces, S.install_slits) }
--- opts = { sides = false, balls = {indices} (a subset, e.g. a disk), relax_ratio = 1e-4,
---          energy = true, clumps = true (false: the packing's grains stay single balls),
---          jaws = "curved" | "flat" (a disk of M.disk only; default "curved": the Brazilian
---          loading walls, see M.make_jaws), jaw_angle, jaw_segments (M.make_jaws) }
--- sp.balls lists every ball (pebbles too), sp.clumps the clumps, sp.bonds the bonds installed
--- and sp.slits how many of them are slit.
function S.specimen(pk, mat, opts)
    opts = opts or {}
    local t0 = U.clock()
    local m = E.new_model(mat.damp)
    local kn, ks = U.req(mat, "kn", "specimen"), mat.ks or mat.kn
    local fric = mat.fric or 0
    local pl = mat.platen or {}
    local lin = { kn = kn, ks = ks, fric = fric }
    m:contact_model("linear", lin)
    m:contact_model("linear", { kn = pl.kn or kn, ks = pl.ks or ks, fric = pl.fric or 0 },
        { groups = { "platen" } })
    m:contact_model("linear", { kn = pl.kn or kn, ks = pl.ks or ks, fric = pl.fric or 0 },
        { groups = { "side" } })
    local list = pk.balls
    local sub -- packing index -> index in list (a subset)
    if opts.balls then
        list, sub = {}, {}
        for _, i in ipairs(opts.balls) do
            list[#list + 1] = pk.balls[i]; sub[i] = #list
        end
    end
    local xmin, xmax, ymin, ymax = math.huge, -math.huge, math.huge, -math.huge
    for _, p in ipairs(list) do
        xmin = math.min(xmin, p[1] - p[3]); xmax = math.max(xmax, p[1] + p[3])
        ymin = math.min(ymin, p[2] - p[3]); ymax = math.max(ymax, p[2] + p[3])
    end
    local yb, yt = ymin, ymax
    local xl, xr = xmin, xmax
    if not opts.balls then -- the vessel's final walls (the balls press into them under sigma0)
        xl, yb, xr, yt = pk.box[1], pk.box[2], pk.box[3], pk.box[4]
    end
    local W, H = xr - xl, yt - yb
    local ext = 0.25 * math.max(W, H)
    local sp = { model = m, packing = pk, mat = mat, timing = {} }
    local rho = mat.density or pk.density or 2600
    sp.balls = {} -- every ball of the specimen, pebbles included (m:balls() skips pebbles)
    for _, p in ipairs(list) do
        sp.balls[#sp.balls + 1] = m:ball{ pos = { p[1], p[2] }, radius = p[3], density = rho, group = "rock" }
    end
    -- grains (genesis option `grains`): the packing's groups of touching balls become rigid
    -- clumps before any contact exists, so pebbles of one clump never get a contact (nor a
    -- bond). Mass mode "sum" (PFC 3.x's rule): the clump's mass is the sum of its
    -- disks' (the lens overlaps of ~1e-6 R are counted twice: up to 2e-8 relative above the
    -- union's, measured). A subset (a disk) keeps the members it has; a grain cut to one ball is a ball.
    sp.clumps = {}
    if pk.clumps and opts.clumps ~= false then
        for _, g in ipairs(pk.clumps) do
            local members = {}
            for _, i in ipairs(g) do
                local k = sub and sub[i] or (not sub and i)
                if k then members[#members + 1] = sp.balls[k] end
            end
            if #members > 1 then
                sp.clumps[#sp.clumps + 1] = m:clump{ balls = members, mass_mode = "sum", density = rho }
            end
        end
    end
    -- a disk cut by M.disk gets the Brazilian loading walls (opts.jaws, default curved jaws)
    local jaws = opts.jaws
    if jaws ~= nil and not (opts.balls and opts.balls.cut) then
        raise("material.specimen: option 'jaws' is for a disk (balls = M.disk(pk, D))")
    end
    if opts.balls and opts.balls.cut then jaws = jaws or "curved" end
    if jaws ~= nil and jaws ~= "curved" and jaws ~= "flat" then
        raise(string.format("material.specimen: jaws = '%s' (known: 'curved', 'flat')", tostring(jaws)))
    end
    if jaws == "curved" then
        sp.jaws = "curved"
        J.make_jaws(sp, list, opts.balls.center, opts.jaw_angle, opts.jaw_segments)
    else
        sp.jaws = jaws -- nil for a block, "flat" for a disk between flat platens
        if jaws then
            -- flat platens touch the highest and the lowest ball first
            local it, ib, yt1, yb1 = 1, 1, -math.huge, math.huge
            for i, p in ipairs(list) do
                if p[2] + p[3] > yt1 then yt1, it = p[2] + p[3], i end
                if p[2] - p[3] < yb1 then yb1, ib = p[2] - p[3], i end
            end
            local c = opts.balls.center
            sp.disk = { center = c, first_contact = J.contact_angles(list, c[1], c[2], it, ib) }
        end
        sp.bottom = Wl.make(m, { xl - ext, yb }, { xr + ext, yb }, { 0, 1 }, "platen")
        sp.top = Wl.make(m, { xl - ext, yt }, { xr + ext, yt }, { 0, -1 }, "platen")
    end
    if opts.sides then
        sp.left = Wl.make(m, { xl, yb - ext }, { xl, yt + ext }, { 1, 0 }, "side")
        sp.right = Wl.make(m, { xr, yb - ext }, { xr, yt + ext }, { -1, 0 }, "side")
    end
    sp.width, sp.height = xmax - xmin, yt - yb
    sp.extent = { xmin, ymin, xmax, ymax }
    if opts.energy ~= false then m:energy{ on = true } end
    -- make the contacts of the packing: it was made at its stress, so they start overlapping,
    -- on purpose (not reported; booked as placement energy when tracing)
    local placement = m:placement_warning(false)
    m:cycle(1)
    m:placement_warning(placement)
    local gap = mat.gap or 1e-3 * (pk.rmin or 1e-3)
    sp.bonds, sp.slits = S.install_bonds(m, mat, gap)
    sp.timing.bond = U.clock() - t0
    t0 = U.clock()
    -- the ratio judged every 50 steps, the step held (E.hold_step, re-held every 1 000 steps)
    local steps, r = E.solve_ratio(m, opts.relax_ratio or 1e-4, opts.relax_steps or 50000, 50, nil, 1000)
    sp.relax_steps, sp.relax_ratio = steps, r
    sp.timing.relax = U.clock() - t0
    return sp
end

--- Installs the bond model `mat.model` (default "cbond") with the properties mat.bond (each a
--- number or {mean, sd, dist}, drawn per bond with mat.seed) at the ball-ball contacts of group
--- "rock" and the near-contacts within `gap` (m:bond, reset = true: a stress-free start, PFC
--- practice; mat.reset = false keeps the forces). The material's kn, ks and fric go to the bond
--- model only if it has them (the linear part of cbond and pbond; a flat joint has its own).
--- With mat.slit (a flat joint), a fraction of them are then made slit (S.install_slits).
--- Returns the number of bonds (slit ones included) and of slit interfaces.
function S.install_bonds(m, mat, gap)
    local model = mat.model or "cbond"
    local has = {}
    for _, p in ipairs(talus.contact_model_info(model).properties) do has[p.name] = true end
    local props = {}
    if has.kn then props.kn = mat.kn end
    if has.ks then props.ks = mat.ks or mat.kn end
    if has.fric then props.fric = mat.fric or 0 end
    for k, v in pairs(mat.bond or {}) do props[k] = v end
    local n = m:bond{ model = model, props = props, group = "rock", gap = gap, seed = mat.seed or 1,
                      reset = mat.reset ~= false }
    local slits = mat.slit and S.install_slits(m, mat, has) or 0
    return n, slits
end

--- A flat-jointed material's slit interfaces (Potyondy 2012: a share of the interfaces installed
--- unbonded, optionally open by a gap, lowers the tensile strength far more than the compressive
--- one): mat.slit = { fraction = f, gap = g (m, default 0) } reinstalls a fraction f of the
--- bonded interfaces, drawn with mat.seed in the order of their balls' ids, as slit (fj_mtype 2,
--- fj_gap0 = g: unbonded, force-free, open by g). Right after m:bond with reset the interfaces
--- hold no force, so nothing is released. Returns the number of slit interfaces.
function S.install_slits(m, mat, has)
    local model = mat.model or "cbond"
    local sl = mat.slit
    if not has.fj_mtype then
        raise(string.format("material.specimen: mat.slit is for a flat joint (a model with fj_mtype), not '%s'", model))
    end
    local f, g = sl.fraction, sl.gap or 0
    if type(f) ~= "number" or not (f >= 0 and f <= 1) then
        raise("material.specimen: mat.slit.fraction must be in [0, 1] (got " .. tostring(f) .. ")")
    end
    if type(g) ~= "number" or not (g >= 0) then
        raise("material.specimen: mat.slit.gap must be >= 0 (got " .. tostring(g) .. ")")
    end
    local list = {}
    for c in m:contacts{ model = model } do
        if c:prop("bonded") == 1 and c.ball2 then list[#list + 1] = { c = c, a = c.ball1.id, b = c.ball2.id } end
    end
    table.sort(list, function(x, y) return x.a < y.a or (x.a == y.a and x.b < y.b) end)
    -- a stream of its own (the genesis and m:bond draw from theirs)
    local u01 = U.drawer(0x5117 + 7919 * (mat.seed or 1))
    local n = 0
    for _, e in ipairs(list) do
        if u01() < f then
            e.c:set_prop("fj_mtype", 2)
            e.c:set_prop("fj_gap0", g)
            e.c:set_prop("bonded", 1)
            n = n + 1
        end
    end
    return n
end

return S
