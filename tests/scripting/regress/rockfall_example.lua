-- SPDX-License-Identifier: MIT
-- scripts/examples/rockfall_analysis.lua runs end to end (a few rocks, then a small mass
-- release) and writes its per-rock CSVs: one endpoints row per rock, a trajectory file.
local T = require("testlib")
local here = debug.getinfo(1, "S").source:gsub("^@", "")
local root = here:match("^(.*)/tests/scripting/regress/[^/]*$") or "."
local example = root .. "/scripts/examples/rockfall_analysis.lua"
local out = os.tmpname()
os.remove(out)

local function rows(file)
    local n = 0
    for _ in io.lines(file) do n = n + 1 end
    return n - 1 -- header
end

arg = { [0] = example, out, "--n=4", "--paths=2", "--impacts", "--seed=7" }
dofile(example)
T.check(rows(out .. "/rock_endpoints.csv") == 4, "one endpoint row per rock")
T.check(rows(out .. "/rock_paths.csv") > 2, "trajectories of the first rocks")
T.check(rows(out .. "/rock_profile.csv") == 7, "the nominal profile (zone boundaries at its vertices)")
local f = io.open(out .. "/rock_impacts.csv")
T.check(f ~= nil, "rock_impacts.csv written with --impacts")
if f then f:close() end

arg = { [0] = example, out .. "/mass", "--mass-release=3", "--seed=7" }
dofile(example)
T.check(rows(out .. "/mass/rock_endpoints.csv") == 3, "mass release: one row per rock")
os.execute("rm -rf '" .. out .. "'")
T.done("rockfall_example")
