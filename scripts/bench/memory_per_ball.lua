-- SPDX-License-Identifier: MIT
-- The memory a model takes per ball and per contact pair (docs/results/memory.md), measured as the
-- growth of the process's resident set: after creating N disks on a hexagonal grid (the ball
-- arrays), and after the first cycle (the broadphase, the pairs, their model objects, the force
-- loop's scratch). The grid's spacing sets what the pairs are: touching contacts (gap < 0), pairs
-- apart within the broadphase margin, or none.
--   talus run scripts/bench/memory_per_ball.lua [N=200000] [model=linear] [gap=-1e-4]
local function rss()
    collectgarbage()
    collectgarbage()
    local f = io.open("/proc/self/status")
    local t = f:read("a")
    f:close()
    return tonumber(t:match("VmRSS:%s+(%d+)")) * 1024
end
local N = tonumber(arg[1]) or 200000
local model = arg[2] or "linear"
local gap = tonumber(arg[3]) or -1e-4
local m = talus.model{ gravity = { 0, 0 } }
m:placement_warning(false)
local props = { kn = 1e6, ks = 1e6 }
if model == "pbond" then
    props.bonded, props.pb_kn, props.pb_ks, props.pb_ten, props.pb_coh = 1, 1e6, 1e6, 1e9, 1e9
end
m:contact_model(model, props)
local r0 = rss()
local side = math.floor(math.sqrt(N))
local R = 0.01
local d = 2 * R + gap
for i = 0, N - 1 do
    local ix, iy = i % side, i // side
    m:ball{ pos = { ix * d + (iy % 2) * d / 2, iy * d * math.sqrt(3) / 2 }, radius = R, density = 1000 }
end
local r1 = rss()
m:timestep{ fixed = 1e-7 }
m:cycle(1)
local r2 = rss()
local npairs, contacts = m:contact_count{ active = false }, m:contact_count{}
print(string.format("%s N %d gap %g: balls %.1f B/ball; after the first cycle %.1f B/ball in all; "
    .. "pairs %d (%.2f per ball), touching %d; the cycle added %.1f B per ball, %.1f B per pair",
    model, N, gap, (r1 - r0) / N, (r2 - r0) / N, npairs, npairs / N, contacts, (r2 - r1) / N,
    npairs > 0 and (r2 - r1) / npairs or 0 / 0))
