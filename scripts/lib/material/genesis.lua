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

local G = {}

--- The genesis of `kind`'s bodies in `vessel`. o: the checked options (genesis_options below)
--- and o.name (the entry point, for messages). Errors name the line that called the entry
--- point (level 3: run, the entry point, its caller).
function G.run(vessel, kind, o)
    local say = o.verbose and function(text) print(o.name .. ": " .. text) end or function() end
    local sigma0, ratio, chunk = o.stress, o.ratio, o.check_every
    local u01 = U.drawer(o.seed)
    local timing = {}
    local t0 = U.clock()

    -- 0. sizes for (1 - n) of the vessel's area; each body placed by random sequential addition
    -- at half size (area fraction (1 - n)/4 < 0.25, far below the jamming limit of random
    -- sequential addition, ~0.55, so placement never stalls). A ball is checked against the
    -- balls of the 3 x 3 grid cells around it (cell = the largest ball diameter at half size).
    kind:draw(u01, vessel.target_area(1 - o.porosity))
    local s = 0.5
    local Wg, Hg = vessel.extent()
    local cell = 2 * o.rmax * s
    local nx, ny = math.max(1, math.floor(Wg / cell)), math.max(1, math.floor(Hg / cell))
    local grid, placed = {}, {}
    local function cell_of(x, y)
        return math.min(nx - 1, math.max(0, math.floor(x / Wg * nx))),
               math.min(ny - 1, math.max(0, math.floor(y / Hg * ny)))
    end
    local function free(p)
        local cx, cy = cell_of(p[1], p[2])
        for gx = math.max(0, cx - 1), math.min(nx - 1, cx + 1) do
            for gy = math.max(0, cy - 1), math.min(ny - 1, cy + 1) do
                for _, j in ipairs(grid[gy * nx + gx] or {}) do
                    local q = placed[j]
                    local dx, dy = q[1] - p[1], q[2] - p[2]
                    local rr = q[3] + p[3]
                    if dx * dx + dy * dy < rr * rr then return false end
                end
            end
        end
        return true
    end
    for i, unit in ipairs(kind.units) do
        local rb = unit.bound * s
        local misfit = vessel.fits(rb)
        if misfit then error(string.format("material.%s: %s %d %s", o.name, kind.noun, i, misfit), 3) end
        local ok = false
        for _ = 1, 10000 do
            local x, y = vessel.sample(rb, u01)
            local pts, angle = kind:pebbles_at(unit, x, y, s, u01)
            ok = vessel.inside(x, y, rb)
            for _, p in ipairs(pts) do
                if not ok then break end
                ok = free(p)
            end
            if ok then
                for _, p in ipairs(pts) do
                    placed[#placed + 1] = p
                    local cx, cy = cell_of(p[1], p[2])
                    local key = cy * nx + cx
                    grid[key] = grid[key] or {}
                    table.insert(grid[key], #placed)
                end
                unit.pos, unit.angle, unit.pebbles = { x, y }, angle, pts
                break
            end
        end
        if not ok then
            error(string.format("material.%s: could not place %s %d without overlap", o.name, kind.noun, i), 3)
        end
    end
    timing.place = U.clock() - t0

    -- 1. the vessel and the bodies, expanded in `stages` to full size with zero friction, each
    -- stage relaxed to a ratio of 1e-2 in at most 2 500 steps: the last stage ends
    -- over-stressed (~200 MPa) and is scaled down at once; its relaxation only has to be good
    -- enough for the first secant of step 2
    t0 = U.clock()
    -- The time scale of the packing's slowest elastic mode: the P-wave crossing time of the
    -- vessel's longer side, c = sqrt(kn / density) (the contact stiffness per unit thickness
    -- as a modulus, as loading.lua's rate). It sets the stall window of every relaxation
    -- (docs/material.md "Genesis").
    local Wv, Hv = vessel.extent()
    local t_cross = math.max(Wv, Hv) / math.sqrt(o.kn / o.density)
    local m = E.new_model(o.damp)
    -- The genesis overlaps its bodies on purpose (the expansion grows them into each other,
    -- the scaling and the floater step resize and move them): the engine's warning about
    -- contacts that start overlapping is for mistakes, so it is off here, and said once.
    m:placement_warning(false)
    say("bodies are grown and moved into each other on purpose: the contacts that start " ..
        "overlapping are booked as placement energy and not reported")
    -- the stall window: 2 crossings, at least 1 000 steps (on a small packing the ratio is
    -- noisy: 20 checks)
    local function window()
        local dt = m:dt()
        if not o.stall or not (dt > 0) then return math.huge end
        return math.max(1000, math.ceil(2 * t_cross / dt))
    end
    local relaxations = {} -- how each relaxation ended (the packing's `relaxations`)
    local function relax(phase, target, cap, hold)
        local n, rr, why = E.solve_ratio(m, target, cap, chunk, window(), hold and window() or nil)
        relaxations[#relaxations + 1] = { phase = phase, steps = n, ratio = rr, stop = why }
        return n, rr, why
    end
    m:contact_model("linear", { kn = o.kn, ks = o.ks, fric = 0 })
    vessel.build(m)
    kind:create(m, o.density, s)
    vessel.start(m)
    local steps0 = m:step()
    for k = 1, o.stages do
        local f = s ^ (1 - k / o.stages) -- size factor of this stage, 1 at the last
        kind:expand(f)
        local n, rr, why = relax("expansion " .. k, 1e-2, 2500)
        say(string.format("expansion stage %d: size factor %.4f, %d steps, ratio %.3g (%s)", k, f, n, rr, why))
    end
    say(string.format("%d %ss expanded in %d steps", kind:count(), kind.noun, m:step() - steps0))
    timing.expand = U.clock() - t0

    -- 2. Scaling to the stress. A jammed frictionless packing in a fixed vessel answers a
    -- uniform size change eps (relative) with a stress change that is linear in eps:
    -- sigma(s) = B (s_J - s), s the accumulated shrink, B a bulk stiffness (measured on 1 250
    -- balls: B = 4.2e10 Pa within 10% from 340 MPa down to 0.14 MPa). B is taken from the
    -- secant of the last two states; the first step, without a secant, uses the kind's affine
    -- estimate (balls: B = sigma / (mean overlap / (R1 + R2)), which overestimates B (7e10
    -- there) and so undershoots). Each step aims at max(sigma0, sigma / 5), never at sigma0
    -- directly from far: s_J - s must be hit to sigma0 / B (2.5e-6 there) and a 10% error of B
    -- on a jump from 340 MPa would unjam the packing. (P&C's proportional rule, eps = mean
    -- overlap x (1 - sigma0/sigma), took 10-12 scalings: it drops the stress by only ~e, the
    -- tail of the overlap distribution keeping the contacts loaded.) It stops once the vessel's
    -- stress is within a factor 2 of sigma0: the servo finishes from there. Near sigma0 the
    -- packing is marginal (overlaps ~1e-6 R) and rearranges with every size change, so its
    -- secant stiffness is no guide: aimed at sigma0 from 0.67 sigma0, two scalings went to 0.54
    -- sigma0 (5 000 balls), each 5 000 steps.
    t0 = U.clock()
    local ss = m:step()
    -- Every relaxation from here on stops at its ratio or when the ratio stalls (E.solve_ratio),
    -- with the step held at the automatic step (E.hold_step, re-held every stall window). The
    -- ratio of the unbonded frictionless packing has a floor: at 5 000 balls it stayed at
    -- 3e-3-1.6e-2 for 5 000 steps after each scaling, in bursts (e.g. 3.8e-3, 1.2e-2, 3.5e-3
    -- 500 steps apart) that are rearrangements of the contact network, not vibrations a damping
    -- can take out: while the ratio stalled, ~1.3 contacts per step were made (of ~9 200 that
    -- carry force: a seventh of the network per 1 000 steps), 99% of the unbalanced force was
    -- on balls with 3 or more contacts (rattlers: none of it), and mass-proportional viscous
    -- damping beside the local damping left the floor where it was (docs/results/material.md).
    -- Once bonded, the same packing relaxes to 1e-4 in a few thousand steps.
    local scale_iter, zero_runs, B_est = 0, 0, nil
    local prev, s_cum = nil, 0
    for _ = 1, 25 do
        local sig = vessel.stress()
        if sig <= 2 * sigma0 and sig >= sigma0 / 2 then break end
        scale_iter = scale_iter + 1
        local eps
        if sig >= 0.2 * sigma0 then
            local Bk, factor
            if prev and s_cum ~= prev.s then Bk = (prev.sig - sig) / (s_cum - prev.s) end
            factor = 1
            if Bk and Bk > 0 then
                B_est = Bk
            elseif B_est then
                Bk = B_est
            else
                Bk, factor = kind:affine_modulus(m, sig)
            end
            if not Bk then break end
            local aim = sig > sigma0 and math.max(sigma0, 0.2 * sig) or math.min(sigma0, 5 * sig)
            eps = (sig - aim) / Bk * factor
            zero_runs = 0
        else
            -- (almost) no stress: the packing came apart (unjammed). Its stress is no guide to
            -- the distance to jamming, so grow by sigma0 / B (the growth that would give sigma0
            -- from exactly jammed; 1e-5 without an estimate of B), doubling while the stress
            -- stays below 0.2 sigma0, at most 2e-3 per scaling (a loose packing rearranges into
            -- its holes).
            zero_runs = zero_runs + 1
            local e0 = B_est and sigma0 / B_est or 1e-5
            eps = -math.min(2e-3, e0 * 2 ^ (zero_runs - 1))
        end
        if sig >= 0.2 * sigma0 then prev = { s = s_cum, sig = sig } else prev = nil end
        s_cum = s_cum + eps
        kind:shrink(1 - eps)
        -- to 3e-3, or until the ratio stalls; at most 5 000 steps (a cap: at 5 000 balls capped
        -- at 3 000 or 2 000 steps the packing was left moving, and the floater step then deleted
        -- 5% of the balls)
        local n, rr, why = relax("scaling " .. scale_iter, 3e-3, 5000, true)
        say(string.format("scaling %d: stress %.4g Pa, size factor %.8f, relaxed in %d steps to ratio %.3g (%s)",
            scale_iter, sig, 1 - eps, n, rr, why))
    end

    -- The servo (the vessel's: PFC's gain, a velocity cap) to `tolerance` and, with need_ratio,
    -- the ratio, or max_steps. It finishes the isotropic stress and re-jams a packing that a
    -- floater deletion made come apart (walls a few 1e-7 m from contact close in tens of steps
    -- at the cap). Size scaling cannot do the latter: near sigma0 the packing rearranges with
    -- every change (scalings went back and forth between 0 and 5 sigma0, measured). The servo
    -- alone cannot do the start either: from the over-stressed expanded packing, walls that
    -- retreated at the gain's mm/s speeds lost contact and needed 1e5+ steps to come back
    -- (measured).
    local rmean = kind:rmean()
    local function servo_to_stress(phase, need_ratio)
        local r
        if vessel.at_stress(sigma0, o.tolerance) then
            r = E.unbalanced_ratio(m)
            if r <= ratio or not need_ratio then return r end
        end
        local s0 = m:step()
        local sv = vessel.servo(m, sigma0, o.kn, rmean)
        local best, best_at, why = math.huge, 0, nil
        local stepper = E.held_stepper(m, window)
        while true do
            stepper.cycle(200)
            sv.update()
            local k = m:step() - s0
            if vessel.at_stress(sigma0, o.tolerance) then
                r = E.unbalanced_ratio(m)
                if r <= ratio or not need_ratio then why = need_ratio and "ratio" or "stress"; break end
                -- at the stress, the ratio stalled (as E.solve_ratio's; the clock runs only at the
                -- stress)
                if r <= E.stall_drop * best then best, best_at = r, k end
                if k - best_at >= window() then why = "stalled"; break end
            else
                best, best_at = math.huge, k
            end
            if k >= o.max_steps + vessel.servo_overrun then
                r = E.unbalanced_ratio(m)
                say(string.format("isotropic stress not reached in %d steps (%s, ratio %.3g)", o.max_steps,
                    vessel.stress_text(), r))
                why = "max_steps"
                break
            end
        end
        sv.stop()
        stepper.release()
        relaxations[#relaxations + 1] = { phase = phase, steps = m:step() - s0, ratio = r, stop = why }
        say(string.format("%s: servo %d steps, %s, ratio %.3g (%s)", phase, m:step() - s0, vessel.stress_text(), r, why))
        return r
    end
    timing.stress = U.clock() - t0

    -- 3. Floaters (P&C step 3). Contacts per body (walls count), the partners of a ball ("b<id>"
    -- or "w<id>") and the sum of its contacts' normal forces over the mean contact force.
    t0 = U.clock()
    local function contact_counts()
        local count, partners, fsum, fmean, nc = {}, {}, {}, 0, 0
        local function add(id, key, f)
            count[id] = (count[id] or 0) + 1
            partners[id] = partners[id] or {}
            partners[id][key] = true
            fsum[id] = (fsum[id] or 0) + f
        end
        for c in m:contacts{} do
            if c.overlap > 0 then
                local f = math.abs(c.normal_force)
                fmean = fmean + f; nc = nc + 1
                local a, b = kind:ends(c)
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

    -- A ball with fewer than min_contacts contacts is moved and resized in its cage to the empty
    -- circle tangent to three of its neighbours (balls or walls) whose radius is the nearest
    -- above its own ("move/grow", floaters.lua), so it joins the force network with overlaps of
    -- 1e-6 R and the packing's stress is not disturbed; then a short relaxation under the
    -- servo, to twice `ratio`, at most 1 500 steps: with the walls held the packing crept as it
    -- settled (5 000 balls: the wall stress fell from 0.91 to 0.74 sigma0 over three passes,
    -- and 15% more balls were deleted in the end). Balls only (a grain cannot be grown alone).
    local floaters, deleted, chain_links = 0, 0, 0
    local function move_grow_pass(pass)
        local balls, radii = kind.balls, kind.radii
        local count, partners = contact_counts()
        local cellf = 4 * o.rmax
        local gnx = math.floor(Wg / cellf) + 3
        local function key(x, y) return (math.floor(y / cellf) + 1) * gnx + math.floor(x / cellf) + 1 end
        local g, all = {}, {}
        for i, bb in ipairs(balls) do
            if bb.alive then
                local p = bb.pos
                local kk = key(p[1], p[2])
                g[kk] = g[kk] or {}
                table.insert(g[kk], i)
                all[i] = { p[1], p[2], bb.radius }
            end
        end
        local n_float, n_pass = 0, 0
        for i, bb in ipairs(balls) do
            if bb.alive and (count[bb.id] or 0) < o.min_contacts then
                n_float = n_float + 1
                local P = all[i]
                local sites = {}
                -- neighbours within 5 x 5 cells (>= 8 rmax): any ball that could touch a
                -- candidate circle (centre within 2 rmax of P, radius <= 2 R)
                local cx, cy = math.floor(P[1] / cellf) + 1, math.floor(P[2] / cellf) + 1
                for gx = cx - 2, cx + 2 do
                    for gy = cy - 2, cy + 2 do
                        for _, j in ipairs(g[gy * gnx + gx] or {}) do
                            if j ~= i then
                                local q = all[j]
                                local x, y = q[1] - P[1], q[2] - P[2]
                                sites[#sites + 1] = { x = x, y = y, r = q[3], key = "b" .. balls[j].id,
                                                      gap = math.sqrt(x * x + y * y) - q[3] }
                            end
                        end
                    end
                end
                vessel.wall_sites(P, sites, o.rmax)
                table.sort(sites, function(a, b) return a.gap < b.gap end)
                -- keep the current partners if possible (a chain link stays in its chain)
                local best = F.floater_circle(sites, P[3], 2 * o.rmax, 8, partners[bb.id])
                    or F.floater_circle(sites, P[3], 2 * o.rmax, 8)
                if best then
                    local x, y, r = P[1] + best[1], P[2] + best[2], best[3] * (1 + 1e-6)
                    bb.pos = { x, y }
                    bb.vel = { 0, 0 }
                    bb.radius = r
                    radii[i] = r
                    all[i][1], all[i][2], all[i][3] = x, y, r
                    n_pass = n_pass + 1
                end
            end
        end
        if n_pass == 0 then return false end
        floaters = floaters + n_pass
        local sg = vessel.stress()
        local sv = vessel.servo(m, sigma0, o.kn, rmean)
        local n, rr, why = relax("floater pass " .. pass, 2 * ratio, 1500, true)
        sv.stop()
        say(string.format("floater pass %d: %d floaters, %d moved/grown; stress %.4g Pa, relaxed %.4g Pa (%d steps, ratio %.3g, %s)",
            pass, n_float, n_pass, sg, vessel.stress(), n, rr, why))
        return true
    end

    -- After the passes (about 1% of the balls left on 1 250) the floaters that carry no force
    -- (0 or 1 contact, or contact forces summing to < 1% of the mean contact force: rattlers)
    -- are deleted, which cannot unjam the packing. A body with two contacts that carry force is
    -- a link of a force chain (a frictionless ball in equilibrium on two contacts has them
    -- opposite): it is kept. Deleting those links too made the packing come apart (1 250
    -- balls: 11 deleted, 8 of them links, took the wall stress from 1e5 to 1.3e3 Pa; re-jamming
    -- it made 49 new floaters, and three such rounds ended 86 balls lighter at 0.4 sigma0);
    -- moving them breaks the chain (they are floaters again after the relaxation: 74 -> 18 ->
    -- 14 -> 11 over three passes).
    local function cleanup(round)
        local count, _, fsum = contact_counts()
        local nd, nf = 0, 0
        chain_links = 0
        for i = 1, kind:count() do
            local n = kind:alive(i) and (count[kind:id(i)] or 0)
            if n and n < o.min_contacts then
                nf = nf + 1
                if n <= 1 or (fsum[kind:id(i)] or 0) < 1e-2 then
                    kind:delete(i); nd = nd + 1
                else
                    chain_links = chain_links + 1
                end
            end
        end
        deleted = deleted + nd
        say(string.format("%s: %d floaters: %d rattlers deleted, %d chain links kept", round, nf, nd, chain_links))
    end

    -- Rounds (`floater_rounds`, 2): the servo to sigma0, the move/grow passes, the rattlers
    -- deleted. The servo's relaxation rearranges the marginal packing and makes a few new
    -- floaters (36, then 20 on 1 250 balls), hence a second round; the final servo makes a few
    -- more (~0.5%), which are rattlers and deleted without a relaxation.
    for round = 1, o.floater_rounds do
        servo_to_stress("servo " .. round)
        if kind.movable then
            for pass = 1, o.floater_passes do
                if not move_grow_pass(pass) then break end
            end
        end
        cleanup("round " .. round)
    end
    timing.floaters = U.clock() - t0

    -- 4. the isotropic stress finished by the servo, the last rattlers deleted (they carry no
    -- force: no relaxation needed)
    t0 = U.clock()
    local ss2 = m:step()
    local r_final = servo_to_stress("final servo", true)
    if o.floater_rounds > 0 then cleanup("final") end
    say(string.format("isotropic stress %.4g Pa after %d scalings, %d steps (final servo %d), ratio %.3g", sigma0,
        scale_iter, m:step() - ss, m:step() - ss2, r_final))
    timing.stress = timing.stress + U.clock() - t0
    vessel.finish(m)

    local pk = {
        floaters = floaters, deleted = deleted, chain_links = chain_links, steps = m:step(),
        density = o.density, rmin = o.rmin, rmax = o.rmax, timing = timing,
        profile = m:profile(), -- the engine's time per cycle phase over the whole genesis
        genesis = { kn = o.kn, ks = o.ks, porosity = o.porosity, stress = sigma0, seed = o.seed },
        ratio = r_final, relaxations = relaxations,
    }
    kind:packing(m, pk, say)
    vessel.describe(pk, m, r_final)
    -- Rigid grains interlock: even without friction the packing can carry a deviatoric stress,
    -- and the servo then only makes it flow at that stress ratio (seen: walls at 0.84 and 1.09
    -- sigma0 after 30 000 steps, their mean at sigma0). Said, not hidden.
    if kind.interlocking then
        pk.isotropic = vessel.at_stress(sigma0, o.tolerance)
        if not pk.isotropic then
            print(string.format("%s: warning: %s, not all within %g of %g Pa (the interlocked grains hold a " ..
                "deviatoric stress; mean %.4g Pa)", o.name, vessel.stress_text(), o.tolerance, sigma0, vessel.stress()))
        end
    end
    say(string.format("%d balls, %d floater moves, %d deleted, porosity %.4f", #pk.balls, floaters, deleted,
        pk.porosity))
    return pk
end

-- ------------------------------------------------------------------ entry points

local kCommon = { "rmin", "rmax", "porosity", "density", "kn", "ks", "seed", "stress", "damp", "ratio",
    "tolerance", "stages", "max_steps", "min_contacts", "verbose", "check_every", "floater_rounds", "stall" }

-- The options every genesis takes, checked and defaulted; `extra` the entry point's own option
-- names. Errors name the line that called the entry point.
local function genesis_options(opts, name, extra)
    local known = U.set_of(kCommon)
    for _, k in ipairs(extra) do known[k] = true end
    U.check_known(opts, known, name, 4)
    local o = {
        name = name,
        rmin = U.req(opts, "rmin", name, 4), rmax = U.req(opts, "rmax", name, 4),
        porosity = opts.porosity or 0.16,
        density = opts.density or 2600,
        kn = U.req(opts, "kn", name, 4),
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
    if not (o.rmin > 0 and o.rmax >= o.rmin) then error("material." .. name .. ": need 0 < rmin <= rmax", 3) end
    if not (o.porosity > 0.08 and o.porosity < 0.5) then
        error(string.format("material.%s: porosity must be in (0.08, 0.5) for a random disk packing (got %s)", name,
            tostring(o.porosity)), 3)
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
            error("material.genesis: 'grains' must be a table {clump_max = k}", 2)
        end
        U.check_known(opts.grains, U.set_of { "clump_max" }, "genesis: grains")
        clump_max = opts.grains.clump_max or 3
        if math.type(clump_max) ~= "integer" or clump_max < 1 then
            error("material.genesis: grains.clump_max must be an integer >= 1 (got " .. tostring(clump_max) .. ")", 2)
        end
    end
    local pk = G.run(V.box(W, H), B.balls(o.rmin, o.rmax, clump_max, o.seed), o)
    return pk -- not a tail call: the errors of run name the caller's line
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
        error(string.format("material.genesis_disk: diameter %g m must exceed 8 rmax (%g m)", D0, 8 * o.rmax), 2)
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
        error("material.genesis_disk: segments must be an integer >= 8 (got " .. tostring(N) .. ")", 2)
    end
    local pk = G.run(V.circle(D0, N), B.balls(o.rmin, o.rmax, nil, o.seed), o)
    return pk -- not a tail call: the errors of run name the caller's line
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
        error("material.clump_genesis: 'shares' must be a list {p1, p2, p3} of the fractions of grains of 1, 2 "
            .. "and 3 balls", 2)
    end
    local psum = 0
    for k, p in ipairs(shares) do
        if type(p) ~= "number" or not (p >= 0) then
            error(string.format("material.clump_genesis: shares[%d] must be a number >= 0 (got %s)", k,
                tostring(p)), 2)
        end
        psum = psum + p
    end
    if not (psum > 0) then error("material.clump_genesis: the shares sum to 0", 2) end
    local pk = G.run(V.box(W, H), B.grains(o.rmin, o.rmax, shares), o)
    return pk -- not a tail call: the errors of run name the caller's line
end

return G
