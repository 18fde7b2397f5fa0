-- SPDX-License-Identifier: MIT
-- material/genesis.lua: the genesis of Potyondy & Cundall (2004), written once for every vessel
-- (vessels.lua: box, circle) and kind of body (bodies.lua: balls, rigid grains), and its three
-- entry points M.genesis (balls in a box), M.genesis_disk (balls in a circle) and
-- M.clump_genesis (grains in a box). The steps (docs/material.md "Genesis"):
--   0. sizes drawn until the bodies' area is (1 - porosity) of the vessel's, placed without
--      overlap at half size (random sequential addition);
--   1. expanded to full size in stages, frictionless;
--   2. brought near the isotropic stress by scaling every body alike;
--   3. floaters: balls with too few contacts moved and grown in their cage, rattlers deleted;
--   4. the isotropic stress finished by the vessel's servo.
-- A genesis returns a packing: a plain table (balls {x, y, r}, the vessel's outline, stress,
-- porosity, ...), the specimen without a model.
local U = require("material.util")
local E = require("material.equilibrium")
local F = require("material.floaters")
local V = require("material.vessels")
local B = require("material.bodies")
local raise = require("talus_util.errors").raise

local G = {}

-- The genesis is a sequence of named steps over one state table `st`: the vessel, the kind of
-- body, the checked options `o`, the model `m` (from step 1 on), the number stream, the log of
-- relaxations, the floater counts and the CPU time of each step. The measurements behind each
-- rule below are in docs/results/material.md ("Genesis: the measurements behind the steps").

--- The state of one genesis.
local function new_state(vessel, kind, o)
    return {
        vessel = vessel, kind = kind, o = o,
        say = o.verbose and function(text) print(o.name .. ": " .. text) end or function() end,
        sigma0 = o.stress, ratio = o.ratio, chunk = o.check_every,
        u01 = U.drawer(o.seed),
        timing = {}, relaxations = {}, -- how each relaxation ended (the packing's `relaxations`)
        floaters = 0, deleted = 0, chain_links = 0, scale_iter = 0,
    }
end

-- ------------------------------------------------------------------ 0. placement

--- Random sequential addition at half size: each body is checked against the pebbles placed in
--- the 3 x 3 grid cells around it (cell = the largest ball diameter at half size). The area
--- fraction at half size, (1 - n)/4 < 0.25, is far below the jamming limit of random sequential
--- addition (~0.55), so placement never stalls.
local function placement_grid(st, s)
    local Wg, Hg = st.vessel.extent()
    st.Wg = Wg -- the floater step's grid spans the vessel as placed
    local cell = 2 * st.o.rmax * s
    local nx, ny = math.max(1, math.floor(Wg / cell)), math.max(1, math.floor(Hg / cell))
    local grid = { cells = {}, placed = {} }
    function grid.cell_of(x, y)
        return math.min(nx - 1, math.max(0, math.floor(x / Wg * nx))),
               math.min(ny - 1, math.max(0, math.floor(y / Hg * ny)))
    end
    function grid.free(p)
        local cx, cy = grid.cell_of(p[1], p[2])
        for gx = math.max(0, cx - 1), math.min(nx - 1, cx + 1) do
            for gy = math.max(0, cy - 1), math.min(ny - 1, cy + 1) do
                for _, j in ipairs(grid.cells[gy * nx + gx] or {}) do
                    local q = grid.placed[j]
                    local dx, dy = q[1] - p[1], q[2] - p[2]
                    local rr = q[3] + p[3]
                    if dx * dx + dy * dy < rr * rr then return false end
                end
            end
        end
        return true
    end
    function grid.add(p)
        grid.placed[#grid.placed + 1] = p
        local cx, cy = grid.cell_of(p[1], p[2])
        local key = cy * nx + cx
        grid.cells[key] = grid.cells[key] or {}
        table.insert(grid.cells[key], #grid.placed)
    end
    return grid
end

--- Step 0: sizes drawn for (1 - n) of the vessel's area, each body placed without overlap at
--- half size (st.s).
local function place(st)
    local t0 = U.clock()
    local o, kind, vessel, u01 = st.o, st.kind, st.vessel, st.u01
    kind:draw(u01, vessel.target_area(1 - o.porosity))
    st.s = 0.5
    local s = st.s
    local grid = placement_grid(st, s)
    for i, unit in ipairs(kind.units) do
        local rb = unit.bound * s
        local misfit = vessel.fits(rb)
        if misfit then raise("material.%s: %s %d %s", o.name, kind.noun, i, misfit) end
        local ok = false
        for _ = 1, 10000 do
            local x, y = vessel.sample(rb, u01)
            local pts, angle = kind:pebbles_at(unit, x, y, s, u01)
            ok = vessel.inside(x, y, rb)
            for _, p in ipairs(pts) do
                if not ok then break end
                ok = grid.free(p)
            end
            if ok then
                for _, p in ipairs(pts) do grid.add(p) end
                unit.pos, unit.angle, unit.pebbles = { x, y }, angle, pts
                break
            end
        end
        if not ok then raise("material.%s: could not place %s %d without overlap", o.name, kind.noun, i) end
    end
    st.timing.place = U.clock() - t0
end

-- ------------------------------------------------------------------ relaxations

--- The stall window of every relaxation: 2 crossings of the vessel's longer side by a P-wave
--- (c = sqrt(kn / density), the contact stiffness per unit thickness as a modulus, as
--- loading.lua's rate), at least 1 000 steps (on a small packing the ratio is noisy: 20
--- checks); unbounded with stall = false.
local function window(st)
    local dt = st.m:dt()
    if not st.o.stall or not (dt > 0) then return math.huge end
    return math.max(1000, math.ceil(2 * st.t_cross / dt))
end

--- Relaxes to the unbalanced-force ratio `target` or until the ratio stalls, at most `cap`
--- steps (with `hold`, the step held at the automatic step, E.solve_ratio); logged.
local function relax(st, phase, target, cap, hold)
    local w = window(st)
    local n, rr, why = E.solve_ratio(st.m, target, cap, st.chunk, w, hold and window(st) or nil)
    st.relaxations[#st.relaxations + 1] = { phase = phase, steps = n, ratio = rr, stop = why }
    return n, rr, why
end

-- ------------------------------------------------------------------ 1. expansion

--- Step 1: the model, the vessel and the bodies, expanded in `stages` to full size with zero
--- friction, each stage relaxed to a ratio of 1e-2 in at most 2 500 steps. The last stage ends
--- over-stressed and is scaled down at once by step 2, so its relaxation only has to be good
--- enough for step 2's first secant.
local function expand(st)
    local t0 = U.clock()
    local o, kind, vessel = st.o, st.kind, st.vessel
    local Wv, Hv = vessel.extent()
    st.t_cross = math.max(Wv, Hv) / math.sqrt(o.kn / o.density)
    st.m = E.new_model(o.damp)
    local m = st.m
    -- The genesis overlaps its bodies on purpose (the expansion grows them into each other, the
    -- scaling and the floater step resize and move them): the engine's warning about contacts
    -- that start overlapping is for mistakes, so it is off here, and said once.
    m:placement_warning(false)
    st.say("bodies are grown and moved into each other on purpose: the contacts that start " ..
        "overlapping are booked as placement energy and not reported")
    m:contact_model("linear", { kn = o.kn, ks = o.ks, fric = 0 })
    vessel.build(m)
    kind:create(m, o.density, st.s)
    vessel.start(m)
    local steps0 = m:step()
    for k = 1, o.stages do
        local f = st.s ^ (1 - k / o.stages) -- size factor of this stage, 1 at the last
        kind:expand(f)
        local n, rr, why = relax(st, "expansion " .. k, 1e-2, 2500)
        st.say(string.format("expansion stage %d: size factor %.4f, %d steps, ratio %.3g (%s)", k, f, n, rr, why))
    end
    st.say(string.format("%d %ss expanded in %d steps", kind:count(), kind.noun, m:step() - steps0))
    st.timing.expand = U.clock() - t0
end

-- ------------------------------------------------------------------ 2. scaling to the stress

--- The relative size change of one scaling at vessel stress `sig`. A jammed frictionless
--- packing in a fixed vessel answers a uniform size change with a stress change linear in it:
--- sigma(s) = B (s_J - s), s the accumulated shrink, B a bulk stiffness, taken from the secant
--- of the last two states (st.prev); the first step, without a secant, uses the kind's affine
--- estimate, which overestimates B and so undershoots. Each step aims at max(sigma0, sigma/5),
--- never at sigma0 directly from far (s_J - s must be hit to sigma0 / B, and a 10% error of B
--- on a jump from hundreds of MPa would unjam the packing). Below 0.2 sigma0 the packing came
--- apart: its stress says nothing about the distance to jamming, so it grows by sigma0 / B
--- (1e-5 without an estimate of B), doubling while the stress stays low, at most 2e-3 per
--- scaling (a loose packing rearranges into its holes). nil when no stiffness is known.
local function scaling_strain(st, sig)
    local sigma0 = st.sigma0
    if sig < 0.2 * sigma0 then
        st.zero_runs = st.zero_runs + 1
        local e0 = st.B_est and sigma0 / st.B_est or 1e-5
        return -math.min(2e-3, e0 * 2 ^ (st.zero_runs - 1))
    end
    local Bk, factor
    local prev = st.prev
    if prev and st.s_cum ~= prev.s then Bk = (prev.sig - sig) / (st.s_cum - prev.s) end
    factor = 1
    if Bk and Bk > 0 then
        st.B_est = Bk
    elseif st.B_est then
        Bk = st.B_est
    else
        Bk, factor = st.kind:affine_modulus(st.m, sig)
    end
    if not Bk then return nil end
    local aim = sig > sigma0 and math.max(sigma0, 0.2 * sig) or math.min(sigma0, 5 * sig)
    st.zero_runs = 0
    return (sig - aim) / Bk * factor
end

--- Step 2: every body scaled alike until the vessel's stress is within a factor 2 of sigma0
--- (the servo finishes from there: near sigma0 the packing is marginal and rearranges with
--- every size change, so its secant stiffness is no guide), at most 25 scalings. Each scaling
--- is relaxed to 3e-3, or until the ratio stalls (the unbonded frictionless packing's ratio has
--- a floor: rearrangements of the contact network, not vibrations a damping can take out), at
--- most 5 000 steps.
local function scale_to_stress(st)
    local t0 = U.clock()
    local sigma0, vessel = st.sigma0, st.vessel
    st.ss = st.m:step()
    st.zero_runs, st.B_est, st.prev, st.s_cum = 0, nil, nil, 0
    for _ = 1, 25 do
        local sig = vessel.stress()
        if sig <= 2 * sigma0 and sig >= sigma0 / 2 then break end
        st.scale_iter = st.scale_iter + 1
        local eps = scaling_strain(st, sig)
        if not eps then break end
        if sig >= 0.2 * sigma0 then st.prev = { s = st.s_cum, sig = sig } else st.prev = nil end
        st.s_cum = st.s_cum + eps
        st.kind:shrink(1 - eps)
        local n, rr, why = relax(st, "scaling " .. st.scale_iter, 3e-3, 5000, true)
        st.say(string.format("scaling %d: stress %.4g Pa, size factor %.8f, relaxed in %d steps to ratio %.3g (%s)",
            st.scale_iter, sig, 1 - eps, n, rr, why))
    end
    st.rmean = st.kind:rmean()
    st.timing.stress = U.clock() - t0
end

-- ------------------------------------------------------------------ the servo

--- Whether the servo loop is done at step k (of this servo): at the stress with the ratio (or
--- without need_ratio), or at the stress with the ratio stalled (as E.solve_ratio's; the clock
--- runs only at the stress). Returns the reason, or nil to go on.
local function servo_done(st, sv_state, k, need_ratio)
    local o = st.o
    if st.vessel.at_stress(st.sigma0, o.tolerance) then
        sv_state.r = E.unbalanced_ratio(st.m)
        if sv_state.r <= st.ratio or not need_ratio then return need_ratio and "ratio" or "stress" end
        if sv_state.r <= E.stall_drop * sv_state.best then sv_state.best, sv_state.best_at = sv_state.r, k end
        if k - sv_state.best_at >= window(st) then return "stalled" end
    else
        sv_state.best, sv_state.best_at = math.huge, k
    end
    if k >= o.max_steps + st.vessel.servo_overrun then
        sv_state.r = E.unbalanced_ratio(st.m)
        st.say(string.format("isotropic stress not reached in %d steps (%s, ratio %.3g)", o.max_steps,
            st.vessel.stress_text(), sv_state.r))
        return "max_steps"
    end
    return nil
end

--- The vessel's servo (PFC's gain, a velocity cap) to `tolerance` and, with need_ratio, the
--- ratio, or max_steps. It finishes the isotropic stress and re-jams a packing that a floater
--- deletion made come apart (walls close in tens of steps at the cap). Size scaling cannot do
--- the latter (near sigma0 scalings go back and forth), and the servo alone cannot do the start
--- (from the over-stressed expanded packing, walls retreating at the gain's speeds lose contact
--- for 1e5+ steps). Returns the final ratio.
local function servo_to_stress(st, phase, need_ratio)
    local m, vessel = st.m, st.vessel
    if vessel.at_stress(st.sigma0, st.o.tolerance) then
        local r = E.unbalanced_ratio(m)
        if r <= st.ratio or not need_ratio then return r end
    end
    local s0 = m:step()
    local sv = vessel.servo(m, st.sigma0, st.o.kn, st.rmean)
    local state = { best = math.huge, best_at = 0 }
    local stepper = E.held_stepper(m, function() return window(st) end)
    local why
    repeat
        stepper.cycle(200)
        sv.update()
        why = servo_done(st, state, m:step() - s0, need_ratio)
    until why
    sv.stop()
    stepper.release()
    st.relaxations[#st.relaxations + 1] = { phase = phase, steps = m:step() - s0, ratio = state.r, stop = why }
    st.say(string.format("%s: servo %d steps, %s, ratio %.3g (%s)", phase, m:step() - s0, vessel.stress_text(),
        state.r, why))
    return state.r
end

-- ------------------------------------------------------------------ 3. floaters

--- Contacts per body (walls count), the partners of a body ("b<id>" or "w<id>") and the sum of
--- its contacts' normal forces over the mean contact force.
local function contact_counts(st)
    local count, partners, fsum, fmean, nc = {}, {}, {}, 0, 0
    local function add(id, key, f)
        count[id] = (count[id] or 0) + 1
        partners[id] = partners[id] or {}
        partners[id][key] = true
        fsum[id] = (fsum[id] or 0) + f
    end
    for c in st.m:contacts{} do
        if c.overlap > 0 then
            local f = math.abs(c.normal_force)
            fmean = fmean + f; nc = nc + 1
            local a, b = st.kind:ends(c)
            if b then
                add(a, "b" .. b, f); add(b, "b" .. a, f)
            else
                add(a, "w" .. c.wall.id, f)
            end
        end
    end
    fmean = nc > 0 and fmean / nc or 1
    for id, v in pairs(fsum) do fsum[id] = v / fmean end
    return count, partners, fsum
end

--- The balls alive, in a grid of cells of 4 rmax: {cells, all = {i = {x, y, r}}, cell size, width}.
local function ball_grid(st)
    local cellf = 4 * st.o.rmax
    local gnx = math.floor(st.Wg / cellf) + 3
    local g, all = {}, {}
    for i, bb in ipairs(st.kind.balls) do
        if bb.alive then
            local p = bb.pos
            local kk = (math.floor(p[2] / cellf) + 1) * gnx + math.floor(p[1] / cellf) + 1
            g[kk] = g[kk] or {}
            table.insert(g[kk], i)
            all[i] = { p[1], p[2], bb.radius }
        end
    end
    return { cells = g, all = all, cellf = cellf, gnx = gnx }
end

--- The neighbours of ball i that could touch a candidate circle (centre within 2 rmax of it,
--- radius <= 2 R): the balls of the 5 x 5 cells (>= 8 rmax) around it and the vessel's walls,
--- nearest first, relative to the ball's centre.
local function floater_sites(st, bg, i)
    local P, balls = bg.all[i], st.kind.balls
    local sites = {}
    local cx, cy = math.floor(P[1] / bg.cellf) + 1, math.floor(P[2] / bg.cellf) + 1
    for gx = cx - 2, cx + 2 do
        for gy = cy - 2, cy + 2 do
            for _, j in ipairs(bg.cells[gy * bg.gnx + gx] or {}) do
                if j ~= i then
                    local q = bg.all[j]
                    local x, y = q[1] - P[1], q[2] - P[2]
                    sites[#sites + 1] = { x = x, y = y, r = q[3], key = "b" .. balls[j].id,
                                          gap = math.sqrt(x * x + y * y) - q[3] }
                end
            end
        end
    end
    st.vessel.wall_sites(P, sites, st.o.rmax)
    table.sort(sites, function(a, b) return a.gap < b.gap end)
    return sites
end

--- One move/grow pass: each ball with fewer than min_contacts contacts is moved and resized in
--- its cage to the empty circle tangent to three of its neighbours (balls or walls) whose
--- radius is the nearest above its own (floaters.lua), keeping its partners where it can (a
--- chain link stays in its chain), so it joins the force network with overlaps of 1e-6 R and
--- the packing's stress is not disturbed; then a short relaxation under the servo (with the
--- walls held the packing crept as it settled), to twice `ratio`, at most 1 500 steps. Balls
--- only (a grain cannot be grown alone). Returns whether any ball moved.
local function move_grow_pass(st, pass)
    local o, kind = st.o, st.kind
    local balls, radii = kind.balls, kind.radii
    local count, partners = contact_counts(st)
    local bg = ball_grid(st)
    local n_float, n_pass = 0, 0
    for i, bb in ipairs(balls) do
        if bb.alive and (count[bb.id] or 0) < o.min_contacts then
            n_float = n_float + 1
            local P = bg.all[i]
            local sites = floater_sites(st, bg, i)
            local best = F.floater_circle(sites, P[3], 2 * o.rmax, 8, partners[bb.id])
                or F.floater_circle(sites, P[3], 2 * o.rmax, 8)
            if best then
                local x, y, r = P[1] + best[1], P[2] + best[2], best[3] * (1 + 1e-6)
                bb.pos = { x, y }
                bb.vel = { 0, 0 }
                bb.radius = r
                radii[i] = r
                P[1], P[2], P[3] = x, y, r
                n_pass = n_pass + 1
            end
        end
    end
    if n_pass == 0 then return false end
    st.floaters = st.floaters + n_pass
    local sg = st.vessel.stress()
    local sv = st.vessel.servo(st.m, st.sigma0, o.kn, st.rmean)
    local n, rr, why = relax(st, "floater pass " .. pass, 2 * st.ratio, 1500, true)
    sv.stop()
    st.say(string.format("floater pass %d: %d floaters, %d moved/grown; stress %.4g Pa, relaxed %.4g Pa (%d steps, ratio %.3g, %s)",
        pass, n_float, n_pass, sg, st.vessel.stress(), n, rr, why))
    return true
end

--- The floaters that carry no force (0 or 1 contact, or contact forces summing to < 1% of the
--- mean contact force: rattlers) deleted, which cannot unjam the packing. A body with two
--- contacts that carry force is a link of a force chain (a frictionless ball in equilibrium on
--- two contacts has them opposite): kept, since deleting links made the packing come apart and
--- moving them breaks the chain.
local function cleanup(st, round)
    local kind, o = st.kind, st.o
    local count, _, fsum = contact_counts(st)
    local nd, nf = 0, 0
    st.chain_links = 0
    for i = 1, kind:count() do
        local n = kind:alive(i) and (count[kind:id(i)] or 0)
        if n and n < o.min_contacts then
            nf = nf + 1
            if n <= 1 or (fsum[kind:id(i)] or 0) < 1e-2 then
                kind:delete(i); nd = nd + 1
            else
                st.chain_links = st.chain_links + 1
            end
        end
    end
    st.deleted = st.deleted + nd
    st.say(string.format("%s: %d floaters: %d rattlers deleted, %d chain links kept", round, nf, nd, st.chain_links))
end

--- Step 3 (P&C's step 3), in `floater_rounds` rounds: the servo to sigma0, the move/grow
--- passes, the rattlers deleted. The servo's relaxation rearranges the marginal packing and
--- makes a few new floaters, hence a second round.
local function floater_rounds(st)
    local t0 = U.clock()
    for round = 1, st.o.floater_rounds do
        servo_to_stress(st, "servo " .. round)
        if st.kind.movable then
            for pass = 1, st.o.floater_passes do
                if not move_grow_pass(st, pass) then break end
            end
        end
        cleanup(st, "round " .. round)
    end
    st.timing.floaters = U.clock() - t0
end

-- ------------------------------------------------------------------ 4. the final stress

--- Step 4: the isotropic stress finished by the servo; the last rattlers (the final servo
--- makes a few) deleted without a relaxation (they carry no force).
local function finish_stress(st)
    local t0 = U.clock()
    local m = st.m
    local ss2 = m:step()
    st.r_final = servo_to_stress(st, "final servo", true)
    if st.o.floater_rounds > 0 then cleanup(st, "final") end
    st.say(string.format("isotropic stress %.4g Pa after %d scalings, %d steps (final servo %d), ratio %.3g",
        st.sigma0, st.scale_iter, m:step() - st.ss, m:step() - ss2, st.r_final))
    st.timing.stress = st.timing.stress + U.clock() - t0
    st.vessel.finish(m)
end

--- The packing: a plain table of what the genesis made.
local function packing(st)
    local o, m, kind, vessel = st.o, st.m, st.kind, st.vessel
    local pk = {
        floaters = st.floaters, deleted = st.deleted, chain_links = st.chain_links, steps = m:step(),
        density = o.density, rmin = o.rmin, rmax = o.rmax, timing = st.timing,
        profile = m:profile(), -- the engine's time per cycle phase over the whole genesis
        genesis = { kn = o.kn, ks = o.ks, porosity = o.porosity, stress = st.sigma0, seed = o.seed },
        ratio = st.r_final, relaxations = st.relaxations,
    }
    kind:packing(m, pk, st.say)
    vessel.describe(pk, m, st.r_final)
    -- Rigid grains interlock: even without friction the packing can carry a deviatoric stress,
    -- and the servo then only makes it flow at that stress ratio. Said, not hidden.
    if kind.interlocking then
        pk.isotropic = vessel.at_stress(st.sigma0, o.tolerance)
        if not pk.isotropic then
            print(string.format("%s: warning: %s, not all within %g of %g Pa (the interlocked grains hold a " ..
                "deviatoric stress; mean %.4g Pa)", o.name, vessel.stress_text(), o.tolerance, st.sigma0, vessel.stress()))
        end
    end
    st.say(string.format("%d balls, %d floater moves, %d deleted, porosity %.4f", #pk.balls, st.floaters, st.deleted,
        pk.porosity))
    return pk
end

--- The genesis of `kind`'s bodies in `vessel`: its steps in order. o: the checked options
--- (genesis_options below) and o.name (the entry point, for messages).
function G.run(vessel, kind, o)
    local st = new_state(vessel, kind, o)
    place(st)
    expand(st)
    scale_to_stress(st)
    floater_rounds(st)
    finish_stress(st)
    return packing(st)
end

-- ------------------------------------------------------------------ entry points

local kCommon = { "rmin", "rmax", "porosity", "density", "kn", "ks", "seed", "stress", "damp", "ratio",
    "tolerance", "stages", "max_steps", "min_contacts", "verbose", "check_every", "floater_rounds", "stall" }

-- The options every genesis takes, checked and defaulted; `extra` the entry point's own option
-- names. Errors name the line that called the entry point.
local function genesis_options(opts, name, extra)
    local known = U.set_of(kCommon)
    for _, k in ipairs(extra) do known[k] = true end
    U.check_known(opts, known, name)
    local o = {
        name = name,
        rmin = U.req(opts, "rmin", name), rmax = U.req(opts, "rmax", name),
        porosity = opts.porosity or 0.16,
        density = opts.density or 2600,
        kn = U.req(opts, "kn", name),
        stress = opts.stress or 1e5, -- P&C: isotropic stress ~0.1 MPa
        ratio = opts.ratio or 1e-3,
        tolerance = opts.tolerance or 0.1,
        stages = opts.stages or 8,
        max_steps = opts.max_steps or 3000,
        min_contacts = opts.min_contacts or 3,
        check_every = opts.check_every or 50,
        floater_passes = opts.floater_passes or 3,
        floater_rounds = opts.floater_rounds or 2,
        seed = opts.seed or 1,
        damp = opts.damp,
        stall = opts.stall ~= false,
        verbose = opts.verbose,
    }
    o.ks = opts.ks or o.kn
    if not (o.rmin > 0 and o.rmax >= o.rmin) then raise("material." .. name .. ": need 0 < rmin <= rmax") end
    if not (o.porosity > 0.08 and o.porosity < 0.5) then
        raise(string.format("material.%s: porosity must be in (0.08, 0.5) for a random disk packing (got %s)", name,
            tostring(o.porosity)))
    end
    return o
end

--- Balls with radii uniform in [rmin, rmax] in a box of width x height (four frictionless
--- walls; each servoed on its own). Options: width, height, rmin, rmax, kn (required); ks (kn),
--- porosity (0.16), density (2600), seed (1), stress (isotropic stress, 1e5 Pa), damp (0.7),
--- ratio (1e-3), tolerance (0.1 per wall), stages (8), max_steps (3000 per servo), min_contacts
--- (3), floater_passes (3), floater_rounds (2), check_every (50), verbose, grains =
--- {clump_max = k} (touching balls grouped into rigid grains of up to k afterwards). Returns a
--- packing: { balls = {{x, y, r}, ...}, box = {xmin, ymin, xmax, ymax} (the walls' final
--- positions), porosity, stress = {left, right, bottom, top} (Pa), floaters (moves), deleted,
--- chain_links, steps, timing = {place, expand, stress, floaters} (CPU s), profile, genesis =
--- {the options}, clumps, grain_counts }.
function G.box(opts)
    local o = genesis_options(opts, "genesis", { "width", "height", "floater_passes", "grains" })
    local W, H = U.req(opts, "width", "genesis"), U.req(opts, "height", "genesis")
    local clump_max = 1
    if opts.grains ~= nil then
        if type(opts.grains) ~= "table" then
            raise("material.genesis: 'grains' must be a table {clump_max = k}")
        end
        U.check_known(opts.grains, U.set_of { "clump_max" }, "genesis: grains")
        clump_max = opts.grains.clump_max or 3
        if math.type(clump_max) ~= "integer" or clump_max < 1 then
            raise("material.genesis: grains.clump_max must be an integer >= 1 (got " .. tostring(clump_max) .. ")")
        end
    end
    return G.run(V.box(W, H), B.balls(o.rmin, o.rmax, clump_max, o.seed), o)
end

--- A disk specimen made in a circular vessel, whose outer balls touch its circle (a cut disk's
--- rim is rough by up to a ball diameter): balls in a regular polygon of `segments` walls
--- inscribed in the circle of diameter `diameter`, shrunk by one radial servo. Options as
--- G.box's but diameter for width and height, and no grains; segments (default: the polygon
--- is a circle to within `roughness` x rmin, roughness 0.01). Returns a packing like G.box's
--- with box = the circle's bounding box, porosity over the polygon, vessel = {center, diameter
--- (final circumcircle), apothem, segments}, stress = {vessel = pressure, measured = mean
--- stress of the whole disk by m:measure, inner = over the circle of 0.8 R}, porosity_inner
--- (m:measure over that circle), ratio (the final unbalanced-force ratio). M.disk(pk) returns
--- all its balls as the disk.
function G.disk(opts)
    local o = genesis_options(opts, "genesis_disk", { "diameter", "floater_passes", "segments", "roughness" })
    local D0 = U.req(opts, "diameter", "genesis_disk")
    if not (D0 > 8 * o.rmax) then
        raise(string.format("material.genesis_disk: diameter %g m must exceed 8 rmax (%g m)", D0, 8 * o.rmax))
    end
    -- Segment count. A ball wedged in a corner of the polygon (touching two flats) has its
    -- centre (a - r) / cos(pi/N) from the centre, a = the apothem, beyond the circle of radius
    -- a - r by (a - r)(1/cos(pi/N) - 1) ~ a pi^2 / (2 N^2); the flats lie inside the
    -- circumcircle by at most R (1 - cos(pi/N)), the same to leading order. So the polygon is a
    -- circle to within e rmin (e = `roughness`, 0.01) when N >= pi sqrt(R / (2 e rmin)): 119.1
    -- at the half-size LdB disk (R = 7.77 mm, rmin = 0.27 mm), 168.5 at full size; rounded up
    -- to a multiple of 4 (a flat centred on each axis): 120 and 172.
    local e_rough = opts.roughness or 0.01
    local N = opts.segments or 4 * math.ceil(math.pi * math.sqrt(0.5 * D0 / (2 * e_rough * o.rmin)) / 4)
    if math.type(N) ~= "integer" or N < 8 then
        raise("material.genesis_disk: segments must be an integer >= 8 (got " .. tostring(N) .. ")")
    end
    return G.run(V.circle(D0, N), B.balls(o.rmin, o.rmax, nil, o.seed), o)
end

--- Grains made as clumps from the start (Potyondy & Cundall's "randomly placed clumps of up to
--- 3 balls" read literally): rigid templates of 1, 2 or 3 touching balls with radii uniform in
--- [rmin, rmax], drawn with the grain shares `shares` = {p1, p2, p3} (fractions of the grains;
--- default 1/3 each), in a box as G.box. Rattler grains (fewer than min_contacts contacts,
--- carrying no force) are deleted. Options as G.box's but shares for grains and no
--- floater_passes. Returns a packing as G.box's (balls = the pebbles, clumps = lists of ball
--- indices of the grains of 2 or 3, grain_counts[k] = grains of k balls, rmin/rmax scaled,
--- scale, isotropic = whether every wall ended within the tolerance).
function G.clumps(opts)
    local o = genesis_options(opts, "clump_genesis", { "width", "height", "shares" })
    local W, H = U.req(opts, "width", "clump_genesis"), U.req(opts, "height", "clump_genesis")
    local shares = opts.shares or { 1 / 3, 1 / 3, 1 / 3 }
    if type(shares) ~= "table" or #shares < 1 or #shares > 3 then
        raise("material.clump_genesis: 'shares' must be a list {p1, p2, p3} of the fractions of grains of 1, 2 "
            .. "and 3 balls")
    end
    local psum = 0
    for k, p in ipairs(shares) do
        if type(p) ~= "number" or not (p >= 0) then
            raise(string.format("material.clump_genesis: shares[%d] must be a number >= 0 (got %s)", k,
                tostring(p)))
        end
        psum = psum + p
    end
    if not (psum > 0) then raise("material.clump_genesis: the shares sum to 0") end
    return G.run(V.box(W, H), B.grains(o.rmin, o.rmax, shares), o)
end

return G
