-- SPDX-License-Identifier: MIT
-- The editor annotations (`talus --lua-annotations FILE`, scripting/lua_annotations.cpp) against
-- the running module: the file parses as Lua; every method, field and option the bindings
-- register is in it, each with its line of documentation; and nothing is in it that the
-- bindings do not have. The registered names are read from the module itself (the model's
-- method table, every userdata's methods and its unknown-field list, every call's
-- unknown-option list), not from the tables that wrote the file.
-- Arguments: the annotation file, an output directory.
local T = require("testlib")
local path, out = arg[1], arg[2]
T.check(path and out, "arguments: the annotation file and an output directory")

-- 1. It parses as Lua (it is never run: it would replace the global talus).
local chunk, perr = loadfile(path)
T.check(chunk ~= nil, "the annotation file parses as Lua: " .. tostring(perr))

-- 2. Its classes, fields and functions, each function with the doc lines above it.
local classes = {} -- name -> {fields = {name = doc}, methods = {name = docs}}
local functions = {} -- "Owner:name" / "talus.name" -> {doc = first line, params = {...}}
local locals = {} -- local variable -> class ("Ball" -> "talus.Ball")
do
    local f = assert(io.open(path))
    local current, block = nil, {}
    for line in f:lines() do
        local cls = line:match("^%-%-%-@class ([%w%._]+)$")
        local fname, ftype, fdoc = line:match("^%-%-%-@field ([%w_]+%??) (%S+) ?(.*)$")
        local loc = line:match("^local (%w+) = {}$")
        local owner, sep, name, args = line:match("^function ([%w_]+)([%.:])([%w_]+)%(([^)]*)%) end$")
        if cls then
            T.check(not classes[cls], "class " .. cls .. " once")
            current = cls
            classes[cls] = { fields = {}, line = line }
        elseif fname then
            T.check(current ~= nil, "a field inside a class: " .. line)
            T.check(fdoc ~= nil and fdoc:find("%w") ~= nil, "field has a doc line: " .. line)
            classes[current].fields[(fname:gsub("%?$", ""))] = { doc = fdoc, optional = fname:sub(-1) == "?" }
        elseif loc then
            T.check(current ~= nil, "a class before local " .. loc)
            locals[loc] = current
        elseif owner then
            local key = owner .. sep .. name
            T.check(not functions[key], key .. " once")
            local doc
            for _, b in ipairs(block) do
                if not b:match("^%-%-%-@") then doc = doc or b:match("^%-%-%-(.*)$") end
            end
            T.check(doc and doc:find("%w"), key .. " has a line of documentation")
            functions[key] = { doc = doc, args = args }
        end
        if line:match("^%-%-%-") then block[#block + 1] = line else block = {} end
        if line == "" then current = nil end
    end
    f:close()
end
T.check(locals.Model == "talus.Model", "the model's class")

local function names_in(err, marker)
    local list = tostring(err):match(marker .. ": (.*)%)$")
    T.check(list ~= nil, "a list of names in: " .. tostring(err))
    local fields, methods = {}, {}
    for n in list:gmatch("[^,; ]+") do
        local m = n:match("^([%w_]+)%(%)$")
        if m then methods[#methods + 1] = m else fields[#fields + 1] = n end
    end
    return fields, methods
end

local function same_set(a, b, what)
    local sa, sb = {}, {}
    for _, x in ipairs(a) do sa[x] = true end
    for _, x in ipairs(b) do sb[x] = true end
    for x in pairs(sa) do T.check(sb[x], what .. ": '" .. x .. "' is registered but not annotated") end
    for x in pairs(sb) do T.check(sa[x], what .. ": '" .. x .. "' is annotated but not registered") end
end

local function keys(t)
    local out = {}
    for k in pairs(t or {}) do out[#out + 1] = k end
    return out
end

local function methods_of(local_name)
    local out = {}
    for key in pairs(functions) do
        local owner, name = key:match("^([%w_]+):([%w_]+)$")
        if owner == local_name then out[#out + 1] = name end
    end
    return out
end

-- 3. The model's methods: its method table.
local m = talus.model{ gravity = { 0, -9.81 } }
same_set(T.sorted_keys(getmetatable(m).__index), methods_of("Model"), "model methods")

-- 4. The module's functions and values.
local mod_functions, mod_values = {}, {}
for k, v in pairs(talus) do
    if type(v) == "function" then mod_functions[#mod_functions + 1] = k else mod_values[#mod_values + 1] = k end
end
local annotated = {}
for key in pairs(functions) do
    local name = key:match("^talus%.([%w_]+)$")
    if name then annotated[#annotated + 1] = name end
end
same_set(mod_functions, annotated, "talus functions")
same_set(mod_values, keys(classes.talus.fields), "talus values")

-- 5. Every userdata type: its methods (the metatable's), its fields (the unknown-field error's
-- list) and, when it has writable ones, the class of b:set{...}.
m:contact_model("linear", { kn = 1e6, ks = 1e6 })
local wall = m:wall{ points = { { -1, 0 }, { 1, 0 } } }
local ball = m:ball{ pos = { 0, 0.099 }, radius = 0.1, density = 1000 }
local clump = m:clump{ pebbles = { { -0.05, 0, 0.05 }, { 0.05, 0, 0.05 } }, pos = { 0, 1 }, density = 1000 }
m:cycle(1)
local contact = m:contacts()()
local history = m:history{ file = out .. "/annotations.csv", columns = { "time" } }
local series = m:vtk{ dir = out .. "/annotations_vtk" }
local tracker = m:track(ball, {})
local objects = { ["talus.Ball"] = ball, ["talus.Wall"] = wall, ["talus.Clump"] = clump,
    ["talus.Contact"] = contact, ["talus.History"] = history, ["talus.Output"] = series,
    ["talus.Tracker"] = tracker }
for cls, obj in pairs(objects) do
    T.check(getmetatable(obj).__name == cls, cls .. " is the metatable's name")
    local local_name = cls:match("^talus%.(%w+)$")
    T.check(locals[local_name] == cls, cls .. " has its class and methods")
    local _, methods = debug.getupvalue(getmetatable(obj).__index, 2)
    same_set(T.sorted_keys(methods), methods_of(local_name), cls .. " methods")
    local ok, err = pcall(function() return obj.zz__unknown end)
    T.check(not ok, cls .. ": an unknown field is an error")
    local fields, listed_methods = names_in(err, "known")
    same_set(fields, keys(classes[cls].fields), cls .. " fields")
    same_set(listed_methods, methods_of(local_name), cls .. " methods in the error's list")
    local wok, werr = pcall(function() obj.zz__unknown = 1 end)
    T.check(not wok, cls .. ": writing an unknown field is an error")
    if tostring(werr):find("(writable: ", 1, true) then
        local writable = names_in(werr:gsub("; model properties.*%)$", ")"), "writable")
        same_set(writable, keys(classes[cls .. "Fields"].fields), cls .. " writable fields")
    else
        T.check(classes[cls .. "Fields"] == nil, cls .. " has no writable fields")
    end
end

-- 6. The option tables: each call's unknown-option list is its class's fields.
local calls = {
    ["talus.ModelDef"] = function(o) return talus.model(o) end,
    ["talus.BallDef"] = function(o) return m:ball(o) end,
    ["talus.WallDef"] = function(o) return m:wall(o) end,
    ["talus.ClumpDef"] = function(o) return m:clump(o) end,
    ["talus.ClumpTemplateDef"] = function(o) return m:clump_template(o) end,
    ["talus.BallsOptions"] = function(o) return m:balls(o) end,
    ["talus.ClumpsOptions"] = function(o) return m:clumps(o) end,
    ["talus.ContactsOptions"] = function(o) return m:contacts(o) end,
    ["talus.ContactCountOptions"] = function(o) return m:contact_count(o) end,
    ["talus.ContactModelOptions"] = function(o) return m:contact_model("linear", {}, o) end,
    ["talus.DampingOptions"] = function(o) return m:damping(o) end,
    ["talus.BroadphaseOptions"] = function(o) return m:broadphase(o) end,
    ["talus.ProfileOptions"] = function(o) return m:profile(o) end,
    ["talus.TimestepOptions"] = function(o) return m:timestep(o) end,
    ["talus.SolveOptions"] = function(o) return m:solve(o) end,
    ["talus.GuardOptions"] = function(o) return m:guard(o) end,
    ["talus.EnergyOptions"] = function(o) return m:energy(o) end,
    ["talus.BondOptions"] = function(o) return m:bond(o) end,
    ["talus.Distribution"] = function(o) return m:bond{ model = "cbond", props = { cb_tenf = o } } end,
    ["talus.UnbondOptions"] = function(o) return m:unbond(o) end,
    ["talus.MeasureOptions"] = function(o) return m:measure(o) end,
    ["talus.CracksOptions"] = function(o) return m:cracks(o) end,
    ["talus.HistoryOptions"] = function(o) return m:history(o) end,
    ["talus.VtkOptions"] = function(o) return m:vtk(o) end,
    ["talus.PictureOptions"] = function(o) return m:picture(o) end,
    ["talus.ServoOptions"] = function(o) return wall:servo(o) end,
    ["talus.ServoSetOptions"] = function(o) return m:servo(o) end,
    ["talus.ServoHoldOptions"] = function(o) return m:servo{ walls = { wall }, rate = 1, gauge = 1, hold = o } end,
    ["talus.TrackOptions"] = function(o) return m:track(clump, o) end,
    ["talus.TrackImpacts"] = function(o) return m:track(clump, { impacts = o }) end,
    ["talus.TrackLine"] = function(o) return m:track(clump, { lines = { o } }) end,
    ["talus.BarrierDef"] = function(o) return m:barrier(o) end,
    ["talus.TrackRest"] = function(o) return m:track(clump, { rest = o }) end,
    ["talus.TrackRegion"] = function(o) return m:track(clump, { region = o }) end,
    ["talus.TrackEnvelope"] = function(o) return m:track(clump, { envelope = o }) end,
    ["talus.RestoreOptions"] = function(o) return talus.restore(out .. "/no_such_save", o) end,
    ["talus.ImpactOptions"] = function(o) return talus.impact(o) end,
    ["talus.DriveOptions"] = function(o) return talus.drive(o) end,
    ["talus.MapOptions"] = function(o) return talus.map(1, function() end, o) end,
}
local options_checked = 0
for cls, call in pairs(calls) do
    T.check(classes[cls] ~= nil, cls .. " is annotated")
    local ok, err = pcall(call, { zz__unknown = 1 })
    T.check(not ok and tostring(err):find("unknown option 'zz__unknown'", 1, true),
        cls .. ": an unknown option is an error: " .. tostring(err))
    same_set((names_in(err, "known")), keys(classes[cls].fields), cls .. " options")
    options_checked = options_checked + 1
end
-- Every option class of the file is one of the calls above (a new table gets its row here).
for cls, c in pairs(classes) do
    if cls:match("Def$") or cls:match("Options$") or cls:match("^talus%.Track%u") or cls == "talus.Distribution" then
        T.check(calls[cls] ~= nil, cls .. " is checked against its call")
    end
end

-- 7. A call completes from its parameters: m:ball's argument is the ball's definition.
T.check(functions["Model:ball"].args == "def", "m:ball(def)")
T.check(classes["talus.BallDef"].fields.pos and not classes["talus.BallDef"].fields.pos.optional,
    "pos is a required field of m:ball{...}")
T.check(classes["talus.BallDef"].fields.density.optional, "density is optional")

print(string.format("annotations: %d classes, %d functions, %d option tables checked", #keys(classes),
    #keys(functions), options_checked))
T.done("annotations")
