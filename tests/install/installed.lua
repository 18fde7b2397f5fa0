-- SPDX-License-Identifier: MIT
-- Run by an installed talus moved away from where it was installed (relocated.cmake), with
-- TALUS_PLUGIN_PATH and TALUS_LUA_PATH unset: its contact models and Lua libraries must come
-- from the moved tree, never from the build or the source tree.
--   talus run installed.lua <prefix> <source dir> <build dir> <shipped models, "a, b, ...">
--                           <module>...
local prefix, source_dir, build_dir, shipped = arg[1], arg[2], arg[3], arg[4]
local modules = { table.unpack(arg, 5) }
local failures = {}
local function check(ok, what)
    if not ok then failures[#failures + 1] = what end
end
local function inside(path, dir)
    return path ~= nil and path:sub(1, #dir + 1) == dir .. "/"
end

-- 1. No search path leads into the trees the install was made from.
for entry in package.path:gmatch("[^;]+") do
    check(not inside(entry, source_dir) and not inside(entry, build_dir),
          "package.path leads into the source or build tree: " .. entry)
end

-- 2. Every installed library module is found in the moved tree and loads.
check(#modules > 0, "no Lua library modules were installed")
for _, name in ipairs(modules) do
    local file = package.searchpath(name, package.path)
    if not inside(file, prefix .. "/share/talus/scripts/lib") then
        check(false, "require('" .. name .. "') would load " .. tostring(file) .. ", not the moved install's")
    else
        local ok, err = pcall(require, name)
        check(ok, "require('" .. name .. "') failed: " .. tostring(err))
    end
end

-- 3. A shipped model, loaded by name from the moved tree, holds a ball at rest on a wall: the
--    wall carries the ball's weight and the overlap is weight / kn (linear spring).
local g, kn = 9.81, 1e6
local m = talus.model{ gravity = {0, -g} }
m:contact_model("linear", { kn = kn, ks = kn, fric = 0.5, dp_nratio = 0.5 })
local w = m:wall{ points = { {-1, 0}, {1, 0} } }
local b = m:ball{ pos = {0, 0.05}, radius = 0.05, density = 2600 }
m:damping{ damp = 0.7 }
m:solve{ time = 2.0 }
local weight = b.mass * g
check(math.abs(-w.force[2] - weight) <= 1e-6 * weight,
      string.format("wall force %.9g N, weight %.9g N", -w.force[2], weight))
check(math.abs((0.05 - b.pos[2]) - weight / kn) <= 1e-6 * weight / kn,
      string.format("overlap %.9g m, expected %.9g m", 0.05 - b.pos[2], weight / kn))
local library = talus.contact_model_info("linear").library
check(inside(library, prefix), "linear was loaded from " .. tostring(library))

-- 4. The models a user is offered are the shipped ones, from the moved tree only.
local ok, err = pcall(m.contact_model, m, "zz_not_a_model", {})
err = tostring(err)
check(not ok and err:find("(models that can be loaded: " .. shipped .. ";", 1, true),
      "the models offered are not the shipped ones (" .. shipped .. "): " .. err)
check(not err:find(build_dir, 1, true) and not err:find(source_dir, 1, true),
      "plugins were searched in the build or source tree: " .. err)

if #failures > 0 then error(#failures .. " failed:\n  " .. table.concat(failures, "\n  "), 0) end
print(string.format("installed talus in %s: %d Lua modules, linear holds %.6g N", prefix,
                    #modules, -w.force[2]))
