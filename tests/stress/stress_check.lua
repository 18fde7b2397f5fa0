-- SPDX-License-Identifier: MIT
-- Runs one stress scene and checks it (docs/stress.md):
--   nonfinite    every ball position, velocity and spin, every energy item, the time and the
--                step are finite after every chunk, unless the run stopped with an error;
--   error        an error that stops a run starts with "file:line:" of the m:cycle call and
--                names what failed (a ball, contact, wall or model);
--   energy       |balance_error| <= 1% of the throughput, max(energy put in, peak mechanical
--                energy), at every chunk, unless a warning was delivered (m:on_warning) or the
--                run stopped with an error;
--   contract     a shipped model's output broke the plugin ABI's contract (the engine's check);
--   runaway      the simulated time stays finite and the step below check.max_dt;
--   determinism  the scene run twice in this process ends in the same state bit for bit
--                (%a of every ball's position, velocity and spin, of the time and energies).
local gen = require("stress_gen")

local check = {}

-- The energy tolerance (docs/stress.md "The 1% criterion"): the guard's own per-contact
-- tolerance (docs/physics/guard.md), the run-level criterion. A resolved impact
-- errs by ~1e-4 of its energy (docs/models/*.md tables, default step), so an error above 1% of
-- everything that went through the model is a booking defect, not integration error.
check.energy_tolerance = 0.01
-- Partition sums: each group item is booked as a share of the same increments as the whole
-- model's, so over a partition the group sums differ from the whole only by the order of the
-- additions: ~1e-16 relative per booking, accumulating over at most 1e4 steps to ~1e-12 of the
-- throughput (measured 3e-15 over 3000 steps, docs/physics/energy.md). 1e-9 leaves three decades
-- for unlucky cancellation; a booking defect (a share lost, counted twice) is of the order of a
-- contact's energy, far above it.
check.group_sum_tolerance = 1e-9
--- The per-group balance tolerance [J]. A group's residual is the second-order error of its own
--- contacts and of those across its border; a small group crossed by a large impact carries a
--- residual large against its own throughput (the "left column" of docs/physics/energy.md:
--- 1.2% of its own, 5.5e-4 of the model's). So the bound is the whole model's tolerance in
--- joules: energy_tolerance x the model's throughput (x the resolution factor).
function check.groupTolerance(scale, group_throughput, model_throughput)
    return check.energy_tolerance * scale * model_throughput
end
-- CPU seconds one run of a scene may take before the watchdog stops it (a hang is a defect).
check.watchdog_seconds = 20
-- The largest sane step [s] (see the runaway check in check.scene).
check.max_dt = 1e3

local WATCHDOG = "stress watchdog: "
local input_items = { initial_kinetic = true, body = true, boundary = true }
local stored_items = { kinetic = true, strain = true, bond = true }
-- Sinks, and the engine's own sums: `input` is the sum of the input items above (counting it
-- too would double the throughput and the tolerance with it), `deleted` leaves the model.
local known_items = { slip = true, dashpot = true, plastic = true, damping = true, released = true,
                      deleted = true, balance_error = true, input = true, exchanged = true }

local function finite(x) return type(x) == "number" and x == x and x ~= math.huge and x ~= -math.huge end

--- The state of every live ball as text (%a is exact), in handle order.
local function stateText(m)
    local parts = { string.format("step %d t %a", m:step(), m:time()) }
    for b in m:balls() do
        local p, v = b.pos, b.vel
        parts[#parts + 1] = string.format("%d %a %a %a %a %a", b.id, p[1], p[2], v[1], v[2], b.spin)
    end
    -- Clumps (none in a scene without clumps: its text, and the digest, are what they were).
    for c in m:clumps() do
        local p, v = c.pos, c.vel
        parts[#parts + 1] = string.format("clump %d %a %a %a %a %a %a", c.id, p[1], p[2], v[1], v[2], c.spin, c.angle)
    end
    local ok, e = pcall(m.energies, m)
    if ok then
        local keys = {}
        for k in pairs(e) do keys[#keys + 1] = k end
        table.sort(keys)
        for _, k in ipairs(keys) do parts[#parts + 1] = k .. " " .. string.format("%a", e[k]) end
    end
    return table.concat(parts, "\n")
end

--- The first non-finite value of the model's state, described; nil when all are finite.
local function firstNonFinite(m)
    if not finite(m:time()) then return "time = " .. tostring(m:time()) end
    local dt = m:dt()
    if not finite(dt) then return "dt = " .. tostring(dt) end
    for b in m:balls() do
        local p, v = b.pos, b.vel
        if not (finite(p[1]) and finite(p[2]) and finite(v[1]) and finite(v[2]) and finite(b.spin)) then
            return string.format("ball %d: pos (%g, %g) vel (%g, %g) spin %g", b.id, p[1], p[2], v[1], v[2], b.spin)
        end
    end
    for c in m:clumps() do
        local p, v = c.pos, c.vel
        if not (finite(p[1]) and finite(p[2]) and finite(v[1]) and finite(v[2]) and finite(c.spin) and finite(c.angle)) then
            return string.format("clump %d: pos (%g, %g) vel (%g, %g) spin %g angle %g", c.id, p[1], p[2], v[1], v[2], c.spin, c.angle)
        end
    end
    local ok, e = pcall(m.energies, m)
    if ok then
        for k, x in pairs(e) do if not finite(x) then return "energy item " .. k .. " = " .. tostring(x) end end
    end
    return nil
end

--- Throughput and balance of one sample of m:energies(): energy put in (initial kinetic plus
--- the magnitudes of the work items, and of any input item the engine may add later: items not
--- known as stored or dissipated count as input) and the mechanical energy stored.
local function sample(e)
    local input, stored = 0, 0
    for k, x in pairs(e) do
        if input_items[k] then
            input = input + math.abs(x)
        elseif stored_items[k] then
            stored = stored + x
        elseif not known_items[k] then
            input = input + math.abs(x)
        end
    end
    return input, stored, e.balance_error
end

--- True when every live body (ball, clump, wall) is in exactly one of `names`: the group books
--- must then sum to the whole model's (docs/physics/energy.md "Energy per group").
local function isPartition(m, names)
    local set = {}
    for _, g in ipairs(names) do set[g] = true end
    local function one(body)
        local n = 0
        for _, g in ipairs(body.groups) do if set[g] then n = n + 1 end end
        return n == 1
    end
    for b in m:balls() do if not one(b) then return false end end
    for c in m:clumps() do if not one(c) then return false end end
    for w in m:walls() do if not one(w) then return false end end
    return true
end

--- The group books after a chunk: per group its balance error and throughput (as for the whole
--- model), and over a partition the largest |sum over the groups - whole| of any additive item.
local function sampleGroups(m, G, e, res)
    local part = res.partition and isPartition(m, G.names)
    res.partition = part
    local sums = {}
    local text = {}
    for _, g in ipairs(G.names) do
        local f = m:energies(g)
        local input, stored, bal = sample(f)
        -- `exchanged` is the group's work with its neighbours: an input of the group.
        input = input + math.abs(f.exchanged or 0)
        local r = res.groups[g] or { throughput = 0, worst = 0, worst_step = 0 }
        res.groups[g] = r
        r.throughput = math.max(r.throughput, input, stored)
        if not finite(bal) or math.abs(bal) > math.abs(r.worst) then r.worst, r.worst_step = bal, m:step() end
        local keys = {}
        for k, x in pairs(f) do
            keys[#keys + 1] = k
            if not finite(x) then res.group_nonfinite = res.group_nonfinite or string.format("group %s item %s = %s after step %d", g, k, tostring(x), m:step()) end
            sums[k] = (sums[k] or 0) + x
        end
        table.sort(keys)
        for _, k in ipairs(keys) do text[#text + 1] = string.format("%s %s %a", g, k, f[k]) end
    end
    res.gstate = table.concat(text, "\n")
    if part then
        -- `input` adds positive parts (of body, boundary, exchanged) group by group: not additive.
        for k, x in pairs(e) do
            if k ~= "input" then
                local d = math.abs((sums[k] or 0) - x)
                if not (d <= res.sum_worst) then res.sum_worst, res.sum_item, res.sum_step = d, k, m:step() end
            end
        end
        if math.abs(sums.exchanged or 0) > res.sum_worst then
            res.sum_worst, res.sum_item, res.sum_step = math.abs(sums.exchanged or 0), "exchanged (sum)", m:step()
        end
    end
end

local SRC = debug.getinfo(1, "S").short_src
-- Step rules that follow the bodies' motion: their steps are long when the motion is slow.
local motion_rules = { kinematic = true, approach = true, growth = true }

--- Runs scene S once. Returns a record: state (text), err (message or nil), err_line (the line of
--- the m:cycle call), warnings (list), nonfinite (text or nil, found with no error), worst
--- (largest |balance_error|, signed), throughput, chunks run.
function check.runOnce(S)
    local res = { warnings = {}, throughput = 0, worst = 0, worst_step = 0, max_dt = 0, max_dt_step = 0 }
    local ok, m = pcall(gen.build, S)
    if not ok then
        res.err, res.build_error = tostring(m), true
        return res
    end
    m:on_warning(function(text) res.warnings[#res.warnings + 1] = text end)
    if S.groups then
        res.groups, res.sum_worst = {}, 0
        res.partition = isPartition(m, S.groups.names)
        res.partition_at_start = res.partition
    end
    if S.hook then S.hook(m) end -- the self-test's deliberate faults (stress.lua selftest)
    local deadline = os.clock() + check.watchdog_seconds
    m:on_cycle(function()
        if os.clock() > deadline then error(WATCHDOG .. "no end after " .. check.watchdog_seconds .. " s CPU", 0) end
    end, 50)
    for i, k in ipairs(gen.plan(S)) do
        local okc, err = pcall(m.cycle, m, k); local line = debug.getinfo(1, "l").currentline
        if not okc then
            res.err, res.err_line = tostring(err), line
            break
        end
        gen.afterChunk(S, m, i)
        local bad = firstNonFinite(m)
        if bad then
            res.nonfinite = string.format("after step %d: %s", m:step(), bad)
            break
        end
        local dt, rule = m:dt()
        if dt > res.max_dt and not motion_rules[rule] then res.max_dt, res.max_dt_step, res.max_dt_rule = dt, m:step(), rule end
        local e = m:energies()
        if S.groups then sampleGroups(m, S.groups, e, res) end
        local input, stored, bal = sample(e)
        res.throughput = math.max(res.throughput, input, stored)
        if math.abs(bal) > math.abs(res.worst) then res.worst, res.worst_step = bal, m:step() end
        res.chunks = i
    end
    res.state = stateText(m)
    res.steps = m:step()
    res.time = m:time()
    local dt, rule = m:dt()
    if finite(dt) and dt > res.max_dt and not motion_rules[rule] then
        res.max_dt, res.max_dt_step, res.max_dt_rule = dt, m:step(), rule
    end
    return res
end

--- Runs and checks scene S (twice, for determinism). Returns the list of defects (strings) and
--- the first run's record.
function check.scene(S)
    local defects = {}
    local a = check.runOnce(S)
    local function defect(what, text) defects[#defects + 1] = what .. ": " .. text end
    if a.build_error then
        defect("build", "a valid scene was refused: " .. a.err)
        return defects, a
    end
    if a.err then
        if a.err:sub(1, #WATCHDOG) == WATCHDOG then
            defect("hang", a.err)
        else
            local prefix = string.format("%s:%d: ", SRC, a.err_line)
            if a.err:sub(1, #prefix) ~= prefix then
                defect("error", "message does not start with '" .. prefix .. "': " .. a.err)
            elseif a.err:find("contact model '[%w_]+' at step %d+ on ") then
                -- The engine's check of a plugin's output against the ABI:
                -- a shipped model breaking its contract in a valid scene is a defect of the
                -- model (or of the check), not an answer to the scene.
                defect("contract", "a shipped model broke the plugin ABI's contract: " .. a.err:sub(#prefix + 1))
            elseif not a.err:lower():find("ball") and not a.err:lower():find("contact")
                and not a.err:lower():find("wall") and not a.err:lower():find("model") then
                defect("error", "message names no ball, contact, wall or model: " .. a.err)
            end
        end
    end
    -- The step is the engine's choice: simulated time running away is a defect
    -- even when it ends in a clear error (a step growing without bound reaches t = inf within
    -- 1100 steps). A step above 1e3 s is one too, unless a rule that follows the motion set it
    -- (kinematic, approach, or growth from those): a ball creeping at 1e-7 m/s (a slow draw, or
    -- one slowed by inelastic impacts with no gravity) may move its margin or half its gap in
    -- that time, and free flight is exact. The other rules answer to contacts, damping or the
    -- idle bound, all far below 1e3 s in these scenes.
    if not finite(a.time) or (a.err and a.err:find("t = inf", 1, true)) then
        defect("runaway", "simulated time became infinite: " .. (a.err or tostring(a.time)))
    elseif a.max_dt > check.max_dt then
        defect("runaway", string.format("the step grew to %.3g s (> %g s, rule %s) by step %d", a.max_dt,
            check.max_dt, tostring(a.max_dt_rule), a.max_dt_step))
    end
    if a.nonfinite then defect("nonfinite", "no error: " .. a.nonfinite) end
    if not a.err and not a.nonfinite and #a.warnings == 0 then
        -- A scene that lowers the resolution rule below its default of 30 steps per contact
        -- asks for a coarser integration: leapfrog's energy error is second order in the step
        -- (seed 91, hertz at resolution 10 / 20 / 40: -4.6e-3 / -6.3e-4 / -1.4e-4 J), so the
        -- tolerance grows as (30 / resolution)^2. A booking defect does not shrink with the step
        -- and the other 80% of the scenes keep the default.
        local res = S.timestep and S.timestep.resolution or 30
        local tol = check.energy_tolerance * math.max(1, (30 / res) ^ 2) * a.throughput
        if math.abs(a.worst) > tol or a.worst ~= a.worst then
            defect("energy", string.format("balance_error %.4g J = %.3g%% of throughput %.4g J (%s) at step %d, no warning",
                a.worst, 100 * a.worst / a.throughput, a.throughput, a.worst < 0 and "created" or "lost", a.worst_step))
        end
    end
    if S.groups and not a.nonfinite then
        if a.group_nonfinite then defect("group-energy", "non-finite group item, no error: " .. a.group_nonfinite) end
        -- Over a partition every additive item summed over the groups is the whole model's, to
        -- round-off (check.group_sum_tolerance). Checked even in scenes that warned or stopped:
        -- the samples are of completed chunks, and books are books.
        if a.partition and a.sum_worst > check.group_sum_tolerance * a.throughput then
            defect("groups", string.format("over the partition %s the groups' %s differ from the whole model's by %.4g J = %.3g of throughput %.4g J at step %d",
                table.concat(S.groups.names, ","), a.sum_item, a.sum_worst, a.sum_worst / a.throughput, a.throughput, a.sum_step))
        end
        if not a.err and #a.warnings == 0 then
            -- Every group's balance closes (exchanged work on its input side), with the same
            -- discretisation error as the whole model's: the tolerance is the whole model's, in
            -- joules (check.groupTolerance).
            local res = S.timestep and S.timestep.resolution or 30
            local scale = math.max(1, (30 / res) ^ 2)
            for _, g in ipairs(S.groups.names) do
                local r = a.groups[g]
                local tol = check.groupTolerance(scale, r.throughput, a.throughput)
                if r and (math.abs(r.worst) > tol or r.worst ~= r.worst) then
                    defect("group-energy", string.format("group %s: balance_error %.4g J at step %d > %.3g J (group throughput %.4g J, model %.4g J), no warning",
                        g, r.worst, r.worst_step, tol, r.throughput, a.throughput))
                end
            end
        end
    end
    local b = check.runOnce(S)
    if a.gstate ~= b.gstate then defect("determinism", "group energy books differ between two runs in one process") end
    if a.state ~= b.state or tostring(a.err) ~= tostring(b.err) or #a.warnings ~= #b.warnings then
        local why = a.state ~= b.state and "final state differs" or
            (tostring(a.err) ~= tostring(b.err) and "error differs" or "warning count differs")
        defect("determinism", why .. " between two runs in one process")
    end
    return defects, a
end

--- One line naming a scene: seed, kind, model(s), ball count and the features that matter most
--- when reading a defect (born overlapped, idle start, soft contacts, moving walls, damping,
--- fixities, applied loads).
function check.describe(S)
    local f = {}
    if S.overlap then f[#f + 1] = "overlap" end
    if S.idle then f[#f + 1] = "idle" end
    if S.soft then f[#f + 1] = "soft" end
    for _, wl in ipairs(S.walls) do if wl.vel or wl.spin then f[#f + 1] = "moving-wall" break end end
    for _, ev in ipairs(S.events or {}) do
        f[#f + 1] = ({ delete = "delete", wallvel = "wall-kick", cdelete = "clump-delete", release = "release" })[ev.kind]
    end
    if S.clumps then
        local n = 0
        for _ in pairs(S.clumps) do n = n + 1 end
        f[#f + 1] = string.format("clumps=%d%s%s", n + #S.fromballs, S.template and ",template" or "", #S.fromballs > 0 and ",from-balls" or "")
    end
    if S.groups then f[#f + 1] = "groups=" .. #S.groups.names .. (S.groups.partition and ",partition" or "") end
    if S.damping then f[#f + 1] = "damping" end
    if S.guard and S.guard.balance == "off" then f[#f + 1] = "balance-off" end
    if S.gravity[1] ~= 0 or S.gravity[2] ~= 0 then f[#f + 1] = "gravity" end
    for _, b in ipairs(S.balls) do if b.fix then f[#f + 1] = "fix" break end end
    for _, b in ipairs(S.balls) do if b.fapp or b.mapp then f[#f + 1] = "load" break end end
    return string.format("seed=%d scene=%s model=%s%s balls=%d [%s]", S.seed, S.kind, S.model,
        S.rule and ("+" .. S.rule.model) or "", #S.balls, table.concat(f, ","))
end

check.firstNonFinite = firstNonFinite

return check
