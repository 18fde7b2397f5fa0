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

-- The page's parallel-bond and flat-joint materials are the library's calibrated Lac du Bonnet
-- (M.lac_du_bonnet with M.ldb_calibrated: every property the page gives, to its rounding of 3-4
-- digits), and they make specimens: on a small packing the page's code installs bonds that carry
-- the moduli the page put in `bond`.
local block
for code in page:gmatch("```lua\n(.-)```") do
    if code:find('model = "pbond"', 1, true) and code:find('model = "fjoint"', 1, true) then block = code end
end
T.check(block ~= nil, "the page defines a parallel-bond and a flat-joint material in one Lua block")
if block then
    local pk = M.genesis{ width = 0.006, height = 0.012, rmin = 0.5e-3, rmax = 0.83e-3, kn = 6.4e10, ks = 2.56e10,
                          seed = 2 }
    local env = setmetatable({ M = M, pk = pk }, { __index = _G })
    local chunk = assert(load(block .. "\nreturn pbond, fjoint, sp", "=docs/material.md", "t", env))
    local page_mat = { pbond = nil, fjoint = nil }
    local sp
    page_mat.pbond, page_mat.fjoint, sp = chunk()
    -- every number of the page's table against the library's, recursively ({mean, sd} included)
    local function compare(kind, a, b, path)
        for k, v in pairs(a) do
            local where = kind .. "." .. path .. k
            if type(v) == "table" then
                T.check(type(b[k]) == "table", where .. " is a table in the library's material")
                if type(b[k]) == "table" then compare(kind, v, b[k], path .. k .. ".") end
            elseif type(v) == "number" then
                T.check(type(b[k]) == "number" and math.abs(v - b[k]) <= 2e-3 * math.abs(b[k]),
                    string.format("%s: page %.6g, library %s", where, v, tostring(b[k])))
            else
                T.check(v == b[k], string.format("%s: page %s, library %s", where, tostring(v), tostring(b[k])))
            end
        end
    end
    for _, kind in ipairs { "pbond", "fjoint" } do
        local lib = M.lac_du_bonnet(kind, M.ldb_calibrated[kind])
        compare(kind, page_mat[kind], lib, "")
    end
    -- the flat-jointed specimen's interfaces carry the page's fj_emod and its elements
    local bonded, right = 0, 0
    for c in sp.model:contacts{ model = "fjoint" } do
        if c:prop("fj_nbond") == 2 then
            bonded = bonded + 1
            if c:prop("fj_emod") == 107e9 and c:prop("fj_kratio") == 2 then right = right + 1 end
        end
    end
    T.check(bonded > 10 and right == bonded,
        string.format("the page's flat joints: %d of %d bonded interfaces with fj_emod 107 GPa, fj_kratio 2", right, bonded))
end
T.done("material_docs")
