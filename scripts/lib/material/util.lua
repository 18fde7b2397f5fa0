-- SPDX-License-Identifier: MIT
-- material/util.lua: what the material parts share, on the common library (talus_util): option
-- checks, the seeded number stream and the CSV writer.
local Err = require("talus_util.errors")
local Opt = require("talus_util.options")
local Rand = require("talus_util.random")
local Csv = require("talus_util.csv")

local U = {}

U.clock = os.clock
U.merged = Opt.merged
U.set_of = Opt.set_of
U.raise = Err.raise

--- opts[key], or an error naming the routine `where`, at the user's line.
function U.req(opts, key, where)
    local v = opts[key]
    if v == nil then Err.raise("material.%s: option '%s' is required", where, key) end
    return v
end

--- An error naming the first key of opts that is not in the set `known` (did you mean ...?).
function U.check_known(opts, known, where)
    Opt.check(opts, known, nil, "material." .. where .. ": ")
end

--- A private number stream for `seed` (xorshift64*, talus_util.random: the generator the
--- packings were always made with, so a seed gives the same specimen): returns u01() (uniform
--- in (0, 1)) and draw(spec), a value drawn from {mean =, sd =, dist = "normal"|"uniform"} or a
--- plain number. Normal: Box-Muller, truncated at zero by redrawing; uniform: mean +- sd sqrt(3)
--- (that interval has standard deviation sd).
function U.drawer(seed)
    local s = (seed or 1) * Rand.GOLDEN ~ 0x2545F4914F6CDD1D
    if s == 0 then s = 1 end
    local gen = Rand.xorshift64star(s)
    local function u01() return gen:uniform_open() end
    local function draw(spec)
        if type(spec) ~= "table" then return spec end
        local mean, sd = spec.mean, spec.sd or 0
        if sd == 0 then return mean end
        if spec.dist == "uniform" then
            return mean + sd * math.sqrt(3) * (2 * u01() - 1)
        end
        for _ = 1, 1000 do
            local v = mean + sd * math.sqrt(-2 * math.log(u01())) * math.cos(2 * math.pi * u01())
            if v > 0 then return v end
        end
        Err.raise("material: cannot draw a positive value from mean %s, sd %s", mean, sd)
    end
    return u01, draw
end

--- Rows (tables with named fields) as CSV with 12 significant digits; an error naming the file
--- when it cannot be written.
function U.write_csv(file, rows, cols)
    local ok, why = Csv.write_records(file, rows, cols, { digits = 12 })
    if not ok then Err.raise("material: " .. why) end
end

return U
