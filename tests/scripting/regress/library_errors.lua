-- SPDX-License-Identifier: MIT
-- Errors raised inside the shipped libraries name the user's script line and what failed, however
-- deep in the library they were found: an engine function's error inside rockfall.monte_carlo
-- (was "rockfall.lua:1431: map: ..."), a misspelt genesis option (now with did-you-mean), a CSV
-- the disk refused (was "rockfall.lua:1298: No space left on device" without the file, and
-- silence from calibrate.write_csv and the material tests' writer).
local T = require("testlib")
local rockfall = require("rockfall")
local M = require("material")
local C = require("calibrate")
local stats = require("rockfall_stats")
local out = (arg and arg[1] or ".") .. "/library_errors"
os.execute("rm -rf '" .. out .. "'")
talus.mkdir(out)
local script = T.script()

local an = rockfall.analysis{
    profile = { { 0, 5 }, { 5, 0 }, { 20, 0 } },
    materials = { slope = { model = "linear", props = { kn = 1e7, ks = 5e6, fric = 0.5, dp_nratio = 0.3 } } },
    seeders = { { kind = "point", at = { 0.5, 5.6 }, rock = { shape = "ball", radius = 0.2 } } },
    t_max = 0.2, seed = 3,
}

-- An error of talus.map, called inside monte_carlo: the user's line, the entry point, no
-- library file.
local line = T.line() + 1
local err = T.fails(function() rockfall.monte_carlo(an, { n = 1, jobs = 0, quiet = true }) end,
    { script .. ":" .. line .. ": rockfall.monte_carlo: ", "jobs", ">= 1" }, "map's error inside monte_carlo")
T.check(not err:find("scripts/lib", 1, true) and not err:find("monte_carlo.lua", 1, true),
    "no library position in the message: " .. err)

-- A rockfall option error deep inside the analysis: the user's line, did-you-mean.
line = T.line() + 1
T.fails(function() rockfall.run_rock(an, 1, { trajectroy = true }) end,
    { script .. ":" .. line .. ": rockfall.run_rock: unknown option 'trajectroy' in run_rock options; "
        .. "did you mean 'trajectory'?" }, "run_rock option")

-- A material option error: the user's line and did-you-mean (the genesis checks its options
-- three calls down).
line = T.line() + 1
T.fails(function() M.genesis{ width = 0.01, height = 0.02, rmin = 3e-4, rmax = 5e-4, kn = 1e9, porosty = 0.2 } end,
    { script .. ":" .. line .. ": material.genesis: unknown option 'porosty'; did you mean 'porosity'?" },
    "genesis option")
line = T.line() + 1
T.fails(function() M.genesis{ width = 0.01, height = 0.02, rmin = 3e-4, rmax = 5e-4 } end,
    { script .. ":" .. line .. ": material.genesis: option 'kn' is required" }, "genesis required option")

-- The statistics check their records several calls down.
line = T.line() + 1
T.fails(function() stats.endpoints({ { rock = 3 } }) end,
    { script .. ":" .. line .. ": rockfall_stats.endpoints: record 1 (rock 3): end_x must be a number" },
    "rockfall_stats input")
line = T.line() + 1
T.fails(function() stats.write({ { rock = 1, end_x = 1, end_y = 0, stop = "rest" } }, { direction = 3 }, out) end,
    { script .. ":" .. line .. ": rockfall_stats.write: analysis.direction must be 1 or -1" }, "rockfall_stats.write input")

-- Files the disk refuses (/dev/full: every write gets ENOSPC): an error naming the file, at the
-- user's line.
local f = io.open("/dev/full", "w")
if f then
    f:close()
    local rec = rockfall.run_rock(an, 1)
    local dir = out .. "/full"
    talus.mkdir(dir)
    os.execute("ln -sf /dev/full '" .. dir .. "/rock_endpoints.csv'")
    line = T.line() + 1
    T.fails(function() rockfall.write_csv({ rec }, an, dir) end,
        { script .. ":" .. line .. ": rockfall.write_csv: cannot write '" .. dir .. "/rock_endpoints.csv'",
          "No space left on device" }, "rockfall.write_csv on a full disk")
    os.execute("ln -sf /dev/full '" .. dir .. "/endpoints.csv'")
    line = T.line() + 1
    T.fails(function() stats.write({ rec }, rockfall.describe(an), dir) end,
        { script .. ":" .. line .. ": rockfall_stats.write: cannot write '" .. dir .. "/endpoints.csv'",
          "No space left on device" }, "rockfall_stats.write on a full disk")
    line = T.line() + 1
    T.fails(function() C.write_csv("/dev/full", { { v = 1, e = 0.5 } }, { "v", "e" }) end,
        { script .. ":" .. line .. ": calibrate.write_csv: cannot write '/dev/full'", "No space left on device" },
        "calibrate.write_csv on a full disk")
    line = T.line() + 1
    T.fails(function() M.write_csv("/dev/full", { { v = 1 } }, { "v" }) end,
        { script .. ":" .. line .. ": material: cannot write '/dev/full'", "No space left on device" },
        "material.write_csv on a full disk")
    line = T.line() + 1
    T.fails(function() M.save_packing({ balls = { { 0, 0, 1 } } }, "/dev/full") end,
        { script .. ":" .. line .. ": material.save_packing: cannot write '/dev/full'", "No space left on device" },
        "material.save_packing on a full disk")
else
    print("library_errors: /dev/full is missing here; the full-disk checks are skipped")
end
-- a directory that does not exist
line = T.line() + 1
T.fails(function() C.write_csv(out .. "/no/such/dir.csv", { { v = 1 } }, { "v" }) end,
    { script .. ":" .. line .. ": calibrate.write_csv: cannot write '" .. out .. "/no/such/dir.csv'" },
    "a missing directory")

T.done("library_errors")
