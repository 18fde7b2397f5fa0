-- SPDX-License-Identifier: MIT
-- talus.map (Monte Carlo across cores): results equal the serial loop bit for bit,
-- whatever the number of worker processes; errors name the index and the script line; values
-- that cannot cross are refused with their path; a dead worker is reported with its range.
-- The comparisons are exact (no tolerance): map carries numbers by their bits.
local T = require("testlib")

-- Exact comparison: same Lua type, integers vs floats kept apart, floats by their bits (so
-- -0.0 differs from 0.0 and nan equals nan), tables key by key both ways.
local function same(a, b, path)
    path = path or "value"
    if type(a) ~= type(b) then return false, path .. ": " .. type(a) .. " vs " .. type(b) end
    if type(a) == "number" then
        if math.type(a) ~= math.type(b) then return false, path .. ": integer vs float" end
        if math.type(a) == "float" then
            if string.pack("<d", a) ~= string.pack("<d", b) then
                return false, string.format("%s: %a vs %a", path, a, b)
            end
        elseif a ~= b then
            return false, path .. ": " .. a .. " vs " .. b
        end
        return true
    end
    if type(a) ~= "table" then return a == b, path end
    for k, v in pairs(a) do
        local ok, where = same(v, rawget(b, k), path .. "[" .. tostring(k) .. "]")
        if not ok then return false, where end
    end
    for k in pairs(b) do
        if rawget(a, k) == nil then return false, path .. "[" .. tostring(k) .. "] extra" end
    end
    return true
end

-- One item: every kind of value that must cross exactly, varying with i.
local specials = { -0.0, 1 / 0, -1 / 0, 0 / 0, 1e-310, 5e-324, math.maxinteger, math.mininteger,
    0.1, 1 / 3, 2 ^ 53 + 1.0 }
local function item(i)
    if i % 13 == 0 then return nil end
    if i % 17 == 0 then return i % 2 == 0 end
    if i % 19 == 0 then return i / 7 end
    return {
        i = i,
        x = i / 7,
        special = specials[i % #specials + 1],
        text = "item\0" .. i .. "\0\255",
        list = { i, i + 0.5, "s" .. i, false, nil, { deep = { deeper = { -i } } } },
        [1.5] = "float key",
        [true] = i,
        [-i] = "negative key",
        ["two words"] = { [""] = 0.0 },
    }
end

local function serial(n, fn)
    local r = {}
    for i = 1, n do r[i] = fn(i) end
    return r
end

local function checkSame(got, want, n, what)
    local ok, where = same(got, want)
    T.check(ok, what .. ": " .. tostring(where))
    local count = 0
    for _ in pairs(got) do count = count + 1 end
    T.check(count <= n, what .. ": no entries beyond n")
end

for _, n in ipairs({ 0, 1, 7, 1000 }) do
    local want = serial(n, item)
    for _, jobs in ipairs({ 1, 2, 3 }) do
        checkSame(talus.map(n, item, { jobs = jobs }), want, n,
            string.format("n = %d, jobs = %d", n, jobs))
    end
end
-- The default number of jobs (the usable cores, or TALUS_JOBS).
checkSame(talus.map(50, item), serial(50, item), 50, "default jobs")

-- Big values (each larger than a pipe's 64 kB buffer many times over): the caller must read all
-- pipes as they fill, or workers and caller wait on each other forever.
local function big(i) return { s = string.rep(string.char(i % 256, 0), 700 * 1024 + i), i = i } end
local big_want = serial(5, big)
for _, jobs in ipairs({ 1, 2, 3 }) do
    checkSame(talus.map(5, big, { jobs = jobs }), big_want, 5, "1.4 MB strings, jobs = " .. jobs)
end

-- With on_error = "raise", a Lua error in fn(5) stops the map: the message has the index and
-- fn's own line. With two failing items, the lowest index is reported whatever the jobs (as
-- the serial loop would). (The default, "record", is tested in map_failures.lua.)
local boom_line = T.line() + 2
local function boom(i)
    if i == 5 or i == 9 then error("boom " .. i) end
    return i
end
for _, jobs in ipairs({ 1, 2, 3 }) do
    T.fails(function() talus.map(12, boom, { jobs = jobs, on_error = "raise" }) end,
        { "map: fn(5) failed: ", T.script() .. ":" .. boom_line .. ": boom 5" },
        "error in fn(5), jobs = " .. jobs)
end

-- Values that cannot cross, refused with the index and where in the value.
for _, jobs in ipairs({ 1, 2 }) do
    T.fails(function()
        talus.map(6, function(i) return { a = { i, { f = i == 3 and print or 0 } } } end,
            { jobs = jobs, on_error = "raise" })
    end, { "map: fn(3) returned a value that talus.map cannot pass back: a function at "
        .. "result.a[2].f" }, "a function in the result, jobs = " .. jobs)
end
T.fails(function() talus.map(2, function() return print end, { on_error = "raise" }) end,
    { "fn(1) returned", "a function at result (only nil, booleans" }, "a function as the result")
T.fails(function()
    talus.map(3, function(i)
        local t = { i }
        if i == 2 then t.self = { up = t } end
        return t
    end, { jobs = 2, on_error = "raise" })
end, { "fn(2) returned", "a cycle (a table that contains itself) at result.self.up" }, "a cycle")
T.fails(function() talus.map(1, function() return { [{}] = 1 } end, { on_error = "raise" }) end,
    { "a table used as a table key at result" }, "a table key")
T.fails(function() talus.map(1, function() return { m = talus.model{} } end, { on_error = "raise" }) end,
    { "a userdata at result.m" }, "a userdata")
T.fails(function()
    talus.map(2, function() return coroutine.create(print) end, { jobs = 2, on_error = "raise" })
end,
    { "fn(1) returned", "a thread at result" }, "a coroutine")
-- A table reached twice (no cycle) arrives as two equal copies.
local shared = talus.map(1, function()
    local s = { 1, 2 }
    return { a = s, b = s }
end, { jobs = 1 })[1]
T.check(shared.a ~= shared.b and shared.a[2] == 2 and shared.b[2] == 2, "shared table copied")

-- A worker that dies (killed by a signal) or leaves (os.exit) is reported with its range and
-- the item it was running.
T.fails(function()
    talus.map(6, function(i)
        if i == 4 then os.execute("kill -KILL $PPID") end -- the shell's parent is the worker
        return i
    end, { jobs = 2, on_error = "raise" })
end, { "map: worker 2 of 2", "indices 4..6) was killed by signal 9", "while running fn(4)" },
    "a killed worker")
T.fails(function()
    talus.map(6, function(i)
        if i == 2 then os.exit(3) end
        return i
    end, { jobs = 3, on_error = "raise" })
end, { "map: worker 1 of 3", "indices 1..2) exited with status 3 while running fn(2)" },
    "os.exit in a worker")

-- Side effects happen in the workers, not in the caller.
counter = 0
talus.map(4, function(i) counter = counter + i end, { jobs = 2 })
T.check(counter == 0, "a global set by fn in a worker is not seen by the caller")
-- A map inside fn runs in place (no workers of workers) and gives the same values.
local nested = talus.map(3, function(i)
    return talus.map(i, function(j) return i * 10 + j end, { jobs = 2 })
end, { jobs = 2 })
T.check(same(nested, { { 11 }, { 21, 22 }, { 31, 32, 33 } }), "nested map")

-- Bad arguments.
T.fails(function() talus.map(-1, item) end, { "map: n must be >= 0 (got -1)" }, "n < 0")
T.fails(function() talus.map(1.5, item) end, { "map: n (the number of items) must be an integer" },
    "n = 1.5")
T.fails(function() talus.map(3, "item") end, { "map: fn must be a function (got string)" }, "fn")
T.fails(function() talus.map(3, item, { jobs = 0 }) end, { "map: 'jobs' must be >= 1 (got 0)" },
    "jobs = 0")
T.fails(function() talus.map(3, item, { job = 2 }) end, { "map: unknown option 'job'" }, "typo")

-- Without mpirun (or under it), the rank is in [0, ranks).
T.check(math.type(talus.rank()) == "integer" and talus.rank() >= 0, "rank")
T.check(talus.rank() < talus.ranks(), "rank < ranks")
T.done("map")
