-- SPDX-License-Identifier: MIT
-- The bonded-rock user page (docs/material.md) speaks to users: every function of the module it
-- names exists, it links to its measurement logs (docs/results/material.md), and neither page
-- nor the module's scripts use words from our workshop (issue numbers, names of our notes, "seed
-- digest", the reference notes' file names, branch names) instead of citing sources.
local T = require("testlib")
local M = require("material")
-- the source tree: this script is tests/scripting/regress/ in it
local root = (T.script():match("^(.*)tests/scripting/regress/[^/]*$") or "../../../"):gsub("/$", "")
if root == "" then root = "." end

local function read(path)
    local f = assert(io.open(root .. "/" .. path), "cannot open " .. path)
    local s = f:read("a")
    f:close()
    return s
end
local page = read("docs/material.md")
local results = read("docs/results/material.md")

-- every M.<name> the page uses is the module's
local named = 0
for name in page:gmatch("M%.([%a_][%w_]*)") do
    named = named + 1
    T.check(M[name] ~= nil, "docs/material.md names M." .. name .. ", which the module has")
end
T.check(named >= 10, "the page shows the module's functions (" .. named .. ")")
T.check(page:find("(results/material.md)", 1, true) ~= nil, "the user page links to its measurement logs")
local lines = select(2, page:gsub("\n", "\n"))
-- (brief: genesis, specimens, the three tests, cracks, the envelope, the granite and the
-- calibrations on one page of under 300 lines)
T.check(lines < 300, "the user page is brief (" .. lines .. " lines)")

-- no workshop words
local files = { "docs/material.md", "docs/results/material.md" }
for _, part in ipairs { "init", "util", "equilibrium", "walls", "floaters", "bodies", "vessels", "genesis", "packing",
    "specimen", "jaws", "loading", "cracks", "compress", "brazilian", "statistics", "ldb", "envelope", "calibration",
    "seeds" } do
    files[#files + 1] = "scripts/lib/material/" .. part .. ".lua"
end
for _, ex in ipairs { "ucs", "brazilian", "berea_ucs", "calibrate_ucs", "calibrated_seeds", "ldb_pbond", "ldb_brazilian",
    "ldb_flatjoint", "calibrate_granite" } do
    files[#files + 1] = "scripts/examples/" .. ex .. ".lua"
end
local words = { "[Tt]hesis A", "[Tt]hesis B", "[Ss]eed digest", "digest section", "bodies%-bonds%-rockfall",
    "rockfall%-inputs", "[Ii]ssue %d", "branch `", "REMEMBERED" }
for _, file in ipairs(files) do
    local text = file == "docs/material.md" and page or file == "docs/results/material.md" and results or read(file)
    for _, w in ipairs(words) do
        local at = text:find(w)
        T.check(not at, string.format("%s: workshop word '%s' (%s)", file, w,
            at and text:sub(math.max(1, at - 30), at + 40):gsub("\n", " ") or ""))
    end
end
T.done("material_docs")
