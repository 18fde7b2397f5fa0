-- SPDX-License-Identifier: MIT
-- The material module is a folder of parts (scripts/lib/material/, docs/material.md):
-- require("material") finds its init.lua, every part is a module of its own, and the module's
-- functions are the parts' (one genesis for the three vessels and bodies, not three). The Lua
-- stand-ins for engine features the build always has are gone: a script that still asks for
-- the Lua servo is told so instead of running something else.
local T = require("testlib")
local M = require("material")

local parts = {}
for _, name in ipairs { "util", "equilibrium", "walls", "floaters", "bodies", "vessels", "genesis", "packing",
    "specimen", "jaws", "loading", "compress", "brazilian", "statistics", "ldb" } do
    local ok, part = pcall(require, "material." .. name)
    T.check(ok and type(part) == "table", "material." .. name .. " is a module: " .. tostring(part))
    parts[name] = ok and part or {}
end
T.check(package.loaded["material"] == M, "require('material') is the folder's init.lua")

-- the three geneses are one routine over a vessel and a kind of body
local G = parts.genesis
T.check(M.genesis == G.box and M.genesis_disk == G.disk and M.clump_genesis == G.clumps,
    "M.genesis, M.genesis_disk, M.clump_genesis are the genesis part's entry points")
T.check(type(G.run) == "function", "one genesis routine (genesis.run)")
local V, B = parts.vessels, parts.bodies
for _, v in ipairs { V.box and V.box(0.01, 0.02), V.circle and V.circle(0.02, 16) } do
    for _, f in ipairs { "target_area", "extent", "sample", "inside", "fits", "build", "start", "finish", "stress",
        "at_stress", "stress_text", "servo", "wall_sites", "describe" } do
        T.check(type(v[f]) == "function", v.name .. " vessel: " .. f)
    end
end
for _, k in ipairs { B.balls and B.balls(1e-3, 2e-3, nil, 1), B.grains and B.grains(1e-3, 2e-3, { 1 }) } do
    for _, f in ipairs { "draw", "pebbles_at", "create", "expand", "shrink", "affine_modulus", "rmean", "ends", "count",
        "alive", "id", "delete", "packing" } do
        T.check(type(k[f]) == "function", k.noun .. " bodies: " .. f)
    end
end
-- the vessels' areas, the box's and the inscribed polygon's (N a^2 tan(pi/N), a = R cos(pi/N))
if V.box then
    T.near(V.box(0.01, 0.02).target_area(0.84), 0.84 * 0.01 * 0.02, 1e-18, "box area")
    local N, R = 16, 0.01
    local a = R * math.cos(math.pi / N)
    T.near(V.circle(2 * R, N).target_area(1), N * a * a * math.tan(math.pi / N), 1e-18, "polygon area")
end

-- the stand-ins are gone
T.check(M.feature == nil, "no feature probe")
T.fails(function() M.genesis{ width = 0.01, height = 0.02, rmin = 1e-3, rmax = 1e-3, kn = 1, lua_servo = true } end,
    { "material.genesis: unknown option 'lua_servo'" }, "genesis: no Lua servo")
T.fails(function() M.clump_genesis{ width = 0.01, height = 0.02, rmin = 1e-3, rmax = 1e-3, kn = 1, lua_servo = true } end,
    { "material.clump_genesis: unknown option 'lua_servo'" }, "clump_genesis: no Lua servo")
-- the option errors name the caller's line
local l = T.line(); local ok, err = pcall(function() local pk = M.genesis_disk{ diameter = 0.02, rmin = 1e-3, rmax = 1e-3 }; return pk end)
T.check(not ok and err:find(T.script() .. ":" .. l .. ": material.genesis_disk: option 'kn' is required", 1, true),
    "missing option names the line: " .. tostring(err))
l = T.line() + 1; ok, err = pcall(function()
    local pk = M.clump_genesis{ width = 0.01, height = 0.02, rmin = 1e-3, rmax = 1e-3, kn = 1, spam = 1 }; return pk end)
T.check(not ok and err:find(T.script() .. ":" .. l .. ": material.clump_genesis: unknown option 'spam'", 1, true),
    "unknown option names the line: " .. tostring(err))
-- a body that cannot fit the vessel: named, at the caller's line (run's own errors)
l = T.line() + 1; ok, err = pcall(function()
    local pk = M.genesis{ width = 1e-3, height = 0.02, rmin = 1e-3, rmax = 1e-3, kn = 1 }; return pk end)
T.check(not ok and err:find(T.script() .. ":" .. l .. ": material.genesis: ball 1 (bounding radius", 1, true)
    and err:find("does not fit the 0.001 x 0.02 m box", 1, true), "a ball too large for the box: " .. tostring(err))
T.done("material_parts")
