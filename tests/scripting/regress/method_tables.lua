-- SPDX-License-Identifier: MIT
-- One list of method tables (scripting/lua_bindings.hpp): every method the model has is in the
-- list the unknown-method error gives, and every name in that list is a method. The list used
-- to be partly typed by hand and left out `save`. Likewise every `talus` function is callable.
local T = require("testlib")

local m = talus.model{}
local methods = getmetatable(m).__index -- the model's method table
local names = T.sorted_keys(methods)
T.check(#names > 40, "the model has its methods (" .. #names .. ")")

local ok, err = pcall(function() return m:no_such_method() end)
T.check(not ok, "an unknown method is an error")
local known = err:match("%(known: (.*)%)$")
T.check(known ~= nil, "the error lists the known names: " .. tostring(err))
local listed = {}
for name in known:gmatch("[^, ]+") do listed[#listed + 1] = name end

-- the list is every method, each once, sorted
local in_list = {}
for i, name in ipairs(listed) do
    T.check(not in_list[name], "'" .. name .. "' listed once")
    in_list[name] = true
    if i > 1 then T.check(listed[i - 1] < name, "sorted at '" .. name .. "'") end
    T.check(type(rawget(methods, name)) == "function", "listed '" .. name .. "' is a method")
end
for _, name in ipairs(names) do
    T.check(in_list[name], "method '" .. name .. "' is in the unknown-method list")
end
T.check(#listed == #names, string.format("%d listed, %d methods", #listed, #names))
-- the ones registered by the other files' own functions before
for _, name in ipairs { "save", "history", "close_history", "vtk", "picture", "cycle", "ball", "bond" } do
    T.check(in_list[name], "'" .. name .. "' is listed")
end

-- the module: every function of each table is there
for _, name in ipairs { "model", "load_plugin", "models", "contact_model_info", "mkdir", "impact", "drive",
    "map", "rank", "ranks", "restore" } do
    T.check(type(talus[name]) == "function", "talus." .. name .. " is a function")
end

T.done("method_tables")
