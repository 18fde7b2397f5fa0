-- SPDX-License-Identifier: MIT
-- The bad-input matrix of the stress suite (docs/stress.md): every option of every Lua call
-- that configures a model, with NaN, inf, -inf, 1e300, 1e-320, -1, 0 and values of the wrong
-- type (a string, a table, a boolean); vector options also with one bad component.
--
-- The option names are not listed here: they are read from the bindings' own "unknown option
-- ... (known: ...)" and "writable: ..." messages and from talus.contact_model_info, so that an
-- option added later is covered without editing this file.
--
-- Each case runs in a fresh small scene (a ball dropping 1 mm onto a floor, a second ball in free
-- fall, energy tracing on) and is classified:
--   refused      the call raised an error that starts with "file:line:" of the call and names
--                the option                                                      (correct)
--   accepted     the call was accepted and 0.3 s of simulated time (at most 3000 steps) ran with
--                every value finite and the dropped ball above the floor         (correct)
--   warned       accepted, and a warning was delivered (m:on_warning)            (correct)
--   deferred     accepted, then the run stopped with a clear error ("file:line:" of the cycle
--                call); listed, not a defect (the brief: a clear error is an answer)
-- and the defects:
--   no-line      an error without the "file:line:" of the script line
--   no-name      an error that does not name the option (nor, for strings, the value)
--   nan-accepted NaN accepted at the call: NaN is never a valid value
--   silent-nan   accepted, then a non-finite position, velocity, energy or time, no error
--   passthrough  accepted, then the dropped ball went through the floor, no warning, no error
--   hang         accepted, then the run did not end within the watchdog (CPU seconds)
--   contract     accepted, then a shipped model broke the plugin ABI's contract (as in scenes)
--   data-lost    a history reported rows that are not in its file, and raised nothing
local B = {}

local SRC = debug.getinfo(1, "S").short_src
local WATCHDOG = "stress watchdog: "
local watchdog_seconds = 3

local function finite(x) return type(x) == "number" and x == x and x ~= math.huge and x ~= -math.huge end

--- Calls f(...) protected; returns ok, error, and the line the error must name (this line).
local function attempt(f, ...)
    local ok, err = pcall(f, ...); local line = debug.getinfo(1, "l").currentline
    return ok, err, line
end
-- Field writes (b.radius = v) raise from the function doing the write: its line is named.
local SET_LINE = debug.getinfo(1, "l").currentline + 1
local function setField(o, k, v) o[k] = v end
local function setProp(c, k, v) return c:set_prop(k, v) end; local PROP_LINE = debug.getinfo(1, "l").currentline

--- Option names from an "unknown option 'x' (known: a, b)" or "(writable: a, b)" message.
local function namesFrom(err, marker)
    local list = tostring(err):match(marker .. ": ([^)]*)%)")
    local out = {}
    if list then
        for n in list:gmatch("[^,; ]+") do
            if not n:find("%(") then out[#out + 1] = n end
        end
    end
    return out
end

local models = {
    linear = { kn = 1e6, ks = 1e6, fric = 0.5 },
    hertz = { hz_shear = 1e8, hz_poiss = 0.3, fric = 0.5 },
    hysdamp = { kn_m = 1e6, d = 0.5, ks = 1e6, fric = 0.5 },
    power = { kn = 1e6, ks = 1e6, fric = 0.5, exponent = 2 },
    cbond = { kn = 1e6, ks = 1e6, fric = 0.5 },
    ng = { ng_shear = 1e8, ng_poiss = 0.3, fric = 0.5 },
    -- Bonded at touch (the bond contract's rule form), so the bond's properties are exercised.
    pbond = { kn = 1e6, ks = 1e6, fric = 0.5, pb_kn = 1e8, pb_ks = 1e8, pb_ten = 1e5, pb_coh = 1e5,
              bonded = 1 },
}
local model_names = { "linear", "hertz", "hysdamp", "power", "cbond", "ng", "pbond" }

local function copy(t)
    local o = {}
    for k, v in pairs(t) do o[k] = v end
    return o
end

--- The scene every case starts from; `over` replaces parts of it (model options, contact model).
local function scene(over)
    over = over or {}
    local env = { warnings = {} }
    local m = talus.model(over.model or { gravity = { 0, -9.81 } })
    env.m = m
    m:on_warning(function(t) env.warnings[#env.warnings + 1] = t end)
    local deadline = os.clock() + watchdog_seconds
    m:on_cycle(function()
        if os.clock() > deadline then error(WATCHDOG .. "no end after " .. watchdog_seconds .. " s CPU", 0) end
    end, 20)
    if not over.no_contact_model then m:contact_model("linear", models.linear) end
    env.w = m:wall{ points = { { -1, 0 }, { 1, 0 } } }
    env.b = m:ball{ pos = { 0, 0.101 }, radius = 0.1, density = 1000, vel = { 0, -1 } }
    env.b2 = m:ball{ pos = { 0.5, 0.5 }, radius = 0.05, density = 2000, vel = { -0.5, 0 } }
    m:energy{ on = true }
    return env
end

-- Bad values: NaN, inf, -inf, huge, subnormal, negative, zero, and three wrong types.
local scalars = {
    { "nan", 0 / 0 }, { "inf", math.huge }, { "-inf", -math.huge }, { "1e300", 1e300 },
    { "1e-320", 1e-320 }, { "-1", -1 }, { "0", 0 }, { "string", "abc" }, { "table", {} },
    { "boolean", true },
}
local function vectorValues()
    local out = {}
    for _, s in ipairs(scalars) do
        if type(s[2]) == "number" then out[#out + 1] = { "{" .. s[1] .. ", 0}", { s[2], 0 } } end
    end
    out[#out + 1] = { "{1}", { 1 } }
    out[#out + 1] = { "string", "abc" }
    out[#out + 1] = { "boolean", true }
    out[#out + 1] = { "nan", 0 / 0 }
    return out
end
local vector_options = { pos = true, vel = true, gravity = true, center = true, fapp = true, centroid = true }

--- Builds the list of cases: {what, option, label, value, run(env, v) -> ok, err, line}.
local function cases(out_dir)
    local list = {}
    local function add(what, opt, run, values)
        for _, v in ipairs(values or (vector_options[opt] and vectorValues() or scalars)) do
            list[#list + 1] = { what = what, opt = opt, label = v[1], value = v[2], run = run }
        end
    end
    local probe = talus.model{}
    local function known(fn, ...)
        local _, err = pcall(probe[fn], probe, ...)
        return namesFrom(err, "known")
    end

    -- talus.model{...}: the case builds its own scene with the option.
    local _, err = pcall(talus.model, { zz__stress = 1 })
    for _, opt in ipairs(namesFrom(err, "known")) do
        add("model", opt, function(_, v)
            local ok, e, line = attempt(talus.model, { [opt] = v })
            return ok, e, line, ok and { model = { [opt] = v } }
        end)
    end

    -- m:ball{...} and m:wall{...}: a valid definition with one option replaced.
    for _, opt in ipairs(known("ball", { zz__stress = 1 })) do
        add("ball", opt, function(env, v)
            local d = { pos = { -0.5, 0.5 }, radius = 0.05, density = 1000 }
            if opt == "mass" then d.density = nil end
            if opt == "groups" then d.group = nil end
            d[opt] = v
            return attempt(env.m.ball, env.m, d)
        end)
    end
    for _, opt in ipairs(known("wall", { zz__stress = 1 })) do
        local values = nil
        if opt == "points" then
            values = {}
            for _, v in ipairs(vectorValues()) do
                values[#values + 1] = { "{" .. v[1] .. ", {1, -0.5}}", { v[2], { 1, -0.5 } } }
            end
            for _, s in ipairs(scalars) do values[#values + 1] = s end
            values[#values + 1] = { "one point", { { 0, -0.5 } } }
            values[#values + 1] = { "repeated point", { { 0, -0.5 }, { 0, -0.5 } } }
            values[#values + 1] = { "{{-1e200, -0.5}, {1e200, -0.5}}", { { -1e200, -0.5 }, { 1e200, -0.5 } } }
        end
        add("wall", opt, function(env, v)
            local d = { points = { { -1, -0.5 }, { 1, -0.5 } } }
            d[opt] = v
            return attempt(env.m.wall, env.m, d)
        end, values)
    end

    -- Settings: m:timestep, m:guard, m:damping, m:broadphase, m:energy, m:solve.
    for _, fn in ipairs({ "timestep", "guard", "damping", "broadphase", "energy", "solve" }) do
        for _, opt in ipairs(known(fn, { zz__stress = 1 })) do
            add(fn, opt, function(env, v) return attempt(env.m[fn], env.m, { [opt] = v }) end)
        end
    end

    -- m:history{...}: file names go to the scratch directory; a full disk must be reported.
    for _, opt in ipairs(known("history", { zz__stress = 1 })) do
        local values = scalars
        if opt == "file" then
            values = { { "nan", 0 / 0 }, { "inf", math.huge }, { "table", {} }, { "boolean", true },
                       { "/dev/full", "/dev/full" }, { "missing directory", out_dir .. "/no/such/dir/h.csv" } }
        end
        add("history", opt, function(env, v)
            local d = { file = out_dir .. "/stress_history.csv", columns = { "time", "kinetic" } }
            -- A fresh file for each case: `append = true` (a valid value) would otherwise add
            -- to the rows of an earlier case or run, and the row count would not match.
            os.remove(d.file)
            d[opt] = v
            local ok, e, line = attempt(env.m.history, env.m, d)
            if ok then env.history = e end
            return ok, e, line
        end, values)
    end

    -- m:contact_model(name, props): every writable property of every shipped model.
    for _, name in ipairs(model_names) do
        local info = talus.contact_model_info(name)
        for _, p in ipairs(info.properties) do
            if not p.read_only then
                add("contact_model " .. name, p.name, function(env, v)
                    local props = copy(models[name])
                    props[p.name] = v
                    return attempt(env.m.contact_model, env.m, name, props)
                end)
            end
        end
        -- Without properties (linear's kn = 0 lets bodies pass through).
        list[#list + 1] = { what = "contact_model " .. name, opt = "(no properties)", label = "nil",
            run = function(_, _)
                return true, nil, 0, { no_contact_model = true, after = function(env) env.m:contact_model(name) end }
            end }
    end

    -- m:gravity(v), m:cycle(n), m:on_cycle(fn, every).
    add("gravity", "gravity", function(env, v) return attempt(env.m.gravity, env.m, v) end)
    local nvals = { { "nan", 0 / 0 }, { "inf", math.huge }, { "-1", -1 }, { "1.5", 1.5 }, { "1e300", 1e300 },
                    { "string", "abc" }, { "table", {} }, { "boolean", true } }
    add("cycle", "cycle", function(env, v) return attempt(env.m.cycle, env.m, v) end, nvals)
    add("on_cycle", "every", function(env, v) return attempt(env.m.on_cycle, env.m, function() end, v) end, nvals)

    -- Ball and wall fields: every writable one (named by the error for an unknown field), by
    -- assignment to the scene's object `key` (env.b or env.w).
    local function addFields(what, probe_object, key)
        local _, unknown = pcall(setField, probe_object, "zz__stress", 1)
        for _, f in ipairs(namesFrom(unknown, "writable")) do
            add(what, f, function(env, v)
                local ok, e = pcall(setField, env[key], f, v)
                return ok, e, SET_LINE
            end)
        end
    end
    addFields("ball field", probe:ball{ pos = { 0, 0 }, radius = 1, density = 1 }, "b")
    -- Writing the dropped ball's position moves it off its drop (onto or into the floor).
    for _, c in ipairs(list) do if c.what == "ball field" and c.opt == "pos" then c.moves_ball = true end end
    addFields("wall field", probe:wall{ points = { { 0, 0 }, { 1, 0 } } }, "w")

    -- m:clump{...}: a valid two-pebble clump (left of the dropped ball, above the floor) with one
    -- option replaced; the direct-mode options (mass, inertia, centroid) in a direct definition.
    local function clumpDef(opt)
        local d = { pebbles = { { -0.04, 0, 0.05 }, { 0.04, 0, 0.04 } }, pos = { -0.5, 0.5 }, density = 1000 }
        if opt == "mass" or opt == "inertia" or opt == "centroid" then
            d.density, d.mass_mode, d.mass, d.inertia = nil, "direct", 10, 0.01
        end
        if opt == "groups" then d.group = nil end
        if opt == "template" or opt == "balls" then d.pebbles, d.pos = nil, nil end
        if opt == "balls" then d.density = nil end
        return d
    end
    local function pebbleValues()
        local out = {}
        for _, v in ipairs(vectorValues()) do
            if type(v[2]) == "table" and #v[2] == 2 then
                out[#out + 1] = { "{{" .. v[1]:sub(2, -2) .. ", 0.05}}", { { v[2][1], 0, 0.05 } } }
                out[#out + 1] = { "{{0, 0, " .. v[1]:sub(2, -5) .. "}}", { { 0, 0, v[2][1] } } }
            end
        end
        for _, sc in ipairs(scalars) do out[#out + 1] = sc end
        out[#out + 1] = { "empty", {} }
        out[#out + 1] = { "{{0, 0}}", { { 0, 0 } } }
        out[#out + 1] = { "{{0, 0, 0.05}, 'x'}", { { 0, 0, 0.05 }, "x" } }
        out[#out + 1] = { "{{0, 0, 0.05}, {0, 0, 0.05}}", { { 0, 0, 0.05 }, { 0, 0, 0.05 } } }
        return out
    end
    for _, opt in ipairs(known("clump", { zz__stress = 1 })) do
        local values = nil
        if opt == "pebbles" then values = pebbleValues() end
        if opt == "balls" then
            values = {}
            for _, sc in ipairs(scalars) do values[#values + 1] = sc end
            values[#values + 1] = { "empty", {} }
            values[#values + 1] = { "{number}", { 1 } }
            values[#values + 1] = { "{stale ball}", "stale" }
            values[#values + 1] = { "{pebble}", "pebble" }
            values[#values + 1] = { "{ball, ball}", "twice" }
        end
        if opt == "template" then
            values = {}
            for _, sc in ipairs(scalars) do values[#values + 1] = sc end
            values[#values + 1] = { "{id = 99}", { id = 99 } }
            values[#values + 1] = { "{id = nan}", { id = 0 / 0 } }
        end
        add("clump", opt, function(env, v)
            local d = clumpDef(opt)
            if opt == "balls" and type(v) == "string" and v ~= "abc" then
                local b = env.m:ball{ pos = { -0.5, 0.5 }, radius = 0.05, density = 1000 }
                if v == "stale" then b:delete() v = { b }
                elseif v == "twice" then v = { b, b }
                else
                    env.m:clump{ balls = { b, env.m:ball{ pos = { -0.4, 0.5 }, radius = 0.05, density = 1000 } } }
                    v = { b }
                end
            end
            d[opt] = v
            return attempt(env.m.clump, env.m, d)
        end, values)
    end
    for _, opt in ipairs(known("clump_template", { zz__stress = 1 })) do
        add("clump_template", opt, function(env, v)
            local d = { pebbles = { { -0.04, 0, 0.05 }, { 0.04, 0, 0.04 } } }
            d[opt] = v
            return attempt(env.m.clump_template, env.m, d)
        end, opt == "pebbles" and pebbleValues() or nil)
    end
    -- Clump fields: every writable one, on a clump created by the case.
    do
        local _, unknown = pcall(setField, probe:clump{ pebbles = { { 0, 0, 1 } }, pos = { 0, 5 }, density = 1 }, "zz__stress", 1)
        for _, f in ipairs(namesFrom(unknown, "writable")) do
            add("clump field", f, function(env, v)
                env.c = env.c or env.m:clump(clumpDef(""))
                local ok, e = pcall(setField, env.c, f, v)
                return ok, e, SET_LINE
            end)
        end
    end
    -- A deleted or released clump: every field read and write, and its methods, must be refused
    -- ("clump N was deleted (stale id)"), never crash.
    for _, how in ipairs({ "delete", "release" }) do
        for _, f in ipairs({ "pos", "vel", "spin", "angle", "fapp", "mapp", "fix", "kn", "mass", "groups" }) do
            list[#list + 1] = { what = how .. "d clump", opt = "clump", label = f, value = f, run = function(env, _)
                local c = env.m:clump(clumpDef(""))
                c[how](c)
                local ok, e = pcall(setField, c, f, f == "fix" and { "x" } or (f == "kn" and 1e6 or ((f == "pos" or f == "vel" or f == "fapp") and { 0, 0 } or 1)))
                return ok, e, SET_LINE
            end }
        end
        for _, meth in ipairs({ "delete", "release", "pebbles", "add_group", "set" }) do
            list[#list + 1] = { what = how .. "d clump", opt = "clump", label = meth .. "()", value = meth, run = function(env, _)
                local c = env.m:clump(clumpDef(""))
                c[how](c)
                return attempt(c[meth], c, meth == "add_group" and "g" or (meth == "set" and { spin = 1 } or nil))
            end }
        end
    end
    -- m:energies(group) with a group that does not exist, and values of the wrong type.
    for _, v in ipairs({ { "unknown", "nosuch" }, { "nan", 0 / 0 }, { "1", 1 }, { "table", {} }, { "boolean", true },
                         { "empty", "" } }) do
        list[#list + 1] = { what = "energies", opt = "group", label = v[1], value = v[2], run = function(env, val)
            env.b:add_group("rock")
            return attempt(env.m.energies, env.m, val)
        end }
    end
    -- History columns of a group that does not exist (or an empty group name).
    for _, v in ipairs({ { "kinetic@nosuch", { "kinetic@nosuch" } }, { "{kinetic, nosuch}", { { "kinetic", "nosuch" } } },
                         { "map kinetic@nosuch", { ke = "kinetic@nosuch" } }, { "kinetic@", { "kinetic@" } },
                         { "nosuch@rock", { "nosuch@rock" } }, { "{kinetic, nan}", { { "kinetic", 0 / 0 } } } }) do
        list[#list + 1] = { what = "history group column", opt = "column", label = v[1], value = v[2], run = function(env, val)
            env.b:add_group("rock")
            local ok, e, line = attempt(env.m.history, env.m, { file = out_dir .. "/stress_history_g.csv", columns = val })
            if ok then env.history = e end
            return ok, e, line
        end }
    end

    -- Contact writes: c.normal_force, c.shear_force, c:set_prop(name, v) on the floor contact.
    local function floorContact(env)
        for _ = 1, 500 do
            local c = env.m:contacts{}()
            if c then return c end
            env.m:cycle(1)
        end
    end
    for _, f in ipairs({ "normal_force", "shear_force" }) do
        add("contact field", f, function(env, v)
            local c = floorContact(env)
            if not c then return false, "no contact to write", -1 end
            local ok, e = pcall(setField, c, f, v)
            return ok, e, SET_LINE
        end)
    end
    for _, p in ipairs(talus.contact_model_info("linear").properties) do
        if not p.read_only then
            add("contact set_prop", p.name, function(env, v)
                local c = floorContact(env)
                if not c then return false, "no contact to write", -1 end
                local ok, e = pcall(setProp, c, p.name, v)
                return ok, e, PROP_LINE
            end)
        end
    end
    return list
end

--- The state after acceptance: nil when everything is finite, else a description.
local nonFinite = require("stress_check").firstNonFinite

--- Runs 0.3 s of simulated time (at most 3000 steps, in chunks of 100).
local function runOn(env)
    local m = env.m
    for _ = 1, 30 do
        local ok, err, line = attempt(m.cycle, m, 100)
        if not ok then return false, err, line end
        if nonFinite(m) or m:time() >= 0.3 then break end
    end
    if env.history then
        local h = env.history
        local ok, err, line = attempt(h.close, h)
        if not ok then return false, err, line end
        -- Every row reported written must be in the file (a full disk).
        if h.file == "/dev/full" then
            env.lost = string.format("%d rows reported written to /dev/full, no error", h.rows)
        else
            local n, f = 0, io.open(h.file, "r")
            if f then
                for _ in f:lines() do n = n + 1 end
                f:close()
            end
            if n ~= h.rows + 1 then
                env.lost = string.format("%d rows reported written to %s, %d lines in the file", h.rows, h.file, n)
            end
        end
    end
    return true
end

local function namesOption(err, case)
    local text = tostring(err):lower()
    local opt = case.opt:lower()
    if opt:sub(1, 1) == "(" then return true end
    if text:find(opt, 1, true) then return true end
    -- "points" is named per entry ("wall: point 2 ...").
    if opt:sub(-1) == "s" and text:find(opt:sub(1, -2) .. " ", 1, true) then return true end
    if type(case.value) == "string" and text:find(case.value:lower(), 1, true) then return true end
    return false
end

local function hasLine(err, line)
    local prefix = string.format("%s:%d: ", SRC, line)
    return tostring(err):sub(1, #prefix) == prefix
end

--- Runs the matrix. Returns the number of cases, of defects, and the classes as text.
function B.run(opts)
    local out_dir = opts.out or os.getenv("TMPDIR") or "/tmp"
    local list = cases(out_dir)
    local classes, ndef = {}, 0
    local order = {}
    local function classify(case, class, defect, text)
        if not classes[class] then
            classes[class] = 0
            order[#order + 1] = class
        end
        classes[class] = classes[class] + 1
        local head = string.format("%s %s = %s", case.what, case.opt, case.label)
        if defect then
            ndef = ndef + 1
            print(string.format("DEFECT badinput %s: %s: %s", head, class, text or ""))
        elseif class == "deferred" or opts.verbose then
            print(string.format("NOTE badinput %s: %s%s", head, class, text and (": " .. text) or ""))
        end
    end
    -- The base scene alone must run clean, or every class below would be noise.
    do
        local env = scene()
        local okr, errr = runOn(env)
        local bad = nonFinite(env.m)
        if not okr or bad or #env.warnings > 0 or env.b.pos[2] < 0 then
            ndef = ndef + 1
            print("DEFECT badinput base scene: not clean: " .. tostring(errr or bad or env.warnings[1] or
                string.format("ball at y = %g", env.b.pos[2])))
        end
    end
    -- Each model's base properties alone: a model whose base scene already fails is reported
    -- once here, and the same failure in its cases below is not counted again.
    local model_broken = {}
    for _, name in ipairs(model_names) do
        local env = scene({ no_contact_model = true })
        env.m:contact_model(name, models[name])
        local okr, errr = runOn(env)
        if not okr then
            model_broken[name] = true
            ndef = ndef + 1
            print(string.format("DEFECT badinput base scene with %s %s: %s", name,
                (function() local t = {} for k, v in pairs(models[name]) do t[#t + 1] = k .. " = " .. v end
                    table.sort(t) return "{" .. table.concat(t, ", ") .. "}" end)(), tostring(errr)))
        end
    end
    for _, case in ipairs(list) do
        local env = scene()
        local ok, err, line, rebuild = case.run(env, case.value)
        if ok and rebuild then
            -- The case's option is part of the scene itself: build it with the option.
            local okb, e2 = pcall(scene, rebuild)
            if not okb then
                ok, err, line = false, e2, -1
            else
                env = e2
                if rebuild.after then rebuild.after(env) end
            end
        end
        if not ok then
            if tostring(err):sub(1, #WATCHDOG) == WATCHDOG then
                classify(case, "hang", true, tostring(err))
            elseif line == -1 then
                classify(case, "no-line", true, "error raised outside the call: " .. tostring(err))
            elseif not hasLine(err, line) then
                classify(case, "no-line", true, tostring(err))
            elseif not namesOption(err, case) then
                classify(case, "no-name", true, tostring(err))
            else
                classify(case, "refused", false)
            end
        elseif case.label == "nan" or (type(case.value) == "table" and case.value[1] ~= case.value[1]) then
            classify(case, "nan-accepted", true, "NaN accepted at the call")
        else
            local okr, errr, liner = runOn(env)
            local bad = nonFinite(env.m)
            if not okr then
                local e = tostring(errr)
                if e:sub(1, #WATCHDOG) == WATCHDOG then
                    classify(case, "hang", true, e)
                elseif e:find("contact model '[%w_]+' at step %d+ on ") and
                    model_broken[case.what:match("^contact_model (%w+)") or ""] then
                    classify(case, "deferred", false, "(as its base scene) " .. e)
                elseif e:find("contact model '[%w_]+' at step %d+ on ") then
                    classify(case, "contract", true, "a shipped model broke the plugin ABI's contract: " ..
                        e:gsub("^[^:]*:%d+: ", ""))
                elseif not hasLine(e, liner) then
                    classify(case, "no-line", true, "accepted, then: " .. e)
                else
                    classify(case, "deferred", false, e)
                end
            elseif bad and #env.warnings == 0 then
                classify(case, "silent-nan", true, bad)
            elseif #env.warnings > 0 then
                classify(case, "warned", false, env.warnings[1])
            elseif env.lost then
                classify(case, "data-lost", true, env.lost)
            elseif env.b.alive and env.b.pos[2] < 0 and not case.moves_ball then
                classify(case, "passthrough", true, string.format(
                    "the ball dropped on the floor is at y = %.4g m (radius 0.1, floor y = 0), no warning", env.b.pos[2]))
            else
                classify(case, "accepted", false)
            end
        end
    end
    local parts = {}
    for _, c in ipairs(order) do parts[#parts + 1] = c .. " " .. classes[c] end
    return #list, ndef, table.concat(parts, ", ")
end

return B
