-- SPDX-License-Identifier: MIT
-- material/util.lua: what the material parts share: option checks, the seeded number stream
-- and the CSV writer.
local U = {}

U.clock = os.clock

--- opts[key], or an error naming the routine `where` and the line `level` levels up (default
--- 3: the line that called the routine that called req).
function U.req(opts, key, where, level)
    local v = opts[key]
    if v == nil then error(string.format("material.%s: option '%s' is required", where, key), level or 3) end
    return v
end

--- An error naming the first key of opts that is not in the set `known` (`level` as for req).
function U.check_known(opts, known, where, level)
    for k in pairs(opts) do
        if not known[k] then
            local names = {}
            for n in pairs(known) do names[#names + 1] = n end
            table.sort(names)
            error(string.format("material.%s: unknown option '%s' (known: %s)", where, tostring(k),
                table.concat(names, ", ")), level or 3)
        end
    end
end

--- A new table with the entries of each argument in turn (later ones win; nil arguments are
--- skipped): a copy with some entries changed, the tables given left as they are.
function U.merged(...)
    local o = {}
    for i = 1, select("#", ...) do
        for k, v in pairs(select(i, ...) or {}) do o[k] = v end
    end
    return o
end

function U.set_of(list)
    local s = {}
    for _, v in ipairs(list) do s[v] = true end
    return s
end

--- A private number stream for `seed` (xorshift64*, the same on every platform, independent of
--- other users of math.random): returns u01() (uniform in (0, 1)) and draw(spec), a value drawn
--- from {mean =, sd =, dist = "normal"|"uniform"} or a plain number. Normal: Box-Muller,
--- truncated at zero by redrawing; uniform: mean +- sd sqrt(3) (that interval has standard
--- deviation sd).
function U.drawer(seed)
    local s = (seed or 1) * 0x9E3779B97F4A7C15 ~ 0x2545F4914F6CDD1D
    if s == 0 then s = 1 end
    local function u01()
        s = s ~ (s >> 12); s = s ~ (s << 25); s = s ~ (s >> 27)
        local x = (s * 0x2545F4914F6CDD1D) >> 11
        return (x + 0.5) / 9007199254740992.0
    end
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
        error("material: cannot draw a positive value from mean " .. mean .. ", sd " .. sd)
    end
    return u01, draw
end

--- CSV with 12 significant digits (calibrate.lua's writer).
function U.write_csv(file, rows, cols)
    return require("calibrate").write_csv(file, rows, cols, "%.12g")
end

return U
