-- SPDX-License-Identifier: MIT
-- talus.map after the force loop ran on threads (m:threads): the workers are forks of a process
-- whose libgomp thread pool exists, which a fork does not carry over, so a worker keeps its
-- models on one thread (docs/lua-api.md, "Threads and fork"). The map must finish (a worker
-- waiting for threads it does not have would hang until ctest's timeout) and give, for each
-- item, the bits the caller computes itself on two threads (the result does not depend on the
-- thread count: docs/architecture.md, "Threads").
local T = require("testlib")

local function run(seed)
    local m = talus.model{ gravity = {0, -9.81} }
    m:threads(2, 1)
    m:contact_model("linear", { kn = 1e6, ks = 5e5, fric = 0.5, dp_nratio = 0.1 })
    m:wall{ points = {{0, 1}, {0, 0}, {1, 0}, {1, 1}} }
    local rnd = T.lcg(seed)
    for j = 0, 5 do
        for i = 0, 9 do
            m:ball{ pos = {0.05 + 0.09 * i, 0.05 + 0.09 * j + 0.01 * rnd()}, radius = 0.04,
                    density = 2600, vel = {rnd() - 0.5, 0} }
        end
    end
    m:cycle(400)
    local out = {}
    for b in m:balls() do out[#out + 1] = T.hex(b.pos[1]) .. T.hex(b.pos[2]) end
    return table.concat(out, " "), tonumber(m:profile():match("threaded steps (%d+)"))
end

-- The caller: on threads (in a build with OpenMP), which starts libgomp's pool.
local mine, mine_threaded = {}, 0
for i = 1, 3 do
    local d, threaded = run(i)
    mine[i] = d
    mine_threaded = mine_threaded + threaded
end
T.check((mine_threaded > 0) == talus.openmp, "the caller's runs used threads: " .. mine_threaded)
local res = talus.map(3, function(i)
    local d, threaded = run(i)
    return { d = d, threaded = threaded }
end, { jobs = 2 })
for i = 1, 3 do
    T.check(res[i].d == mine[i], "item " .. i .. ": the worker's state equals the caller's")
end
T.done("map_after_threads")
