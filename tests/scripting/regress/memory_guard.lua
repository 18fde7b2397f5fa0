-- SPDX-License-Identifier: MIT
-- A model too big for memory stops with an error that says what it needs and what there is,
-- before it is allocated (docs/physics/guard.md, "Memory"). The bytes per ball and per contact
-- pair are measured in docs/results/memory.md (scripts/bench/memory_per_ball.lua); here a
-- user-set limit stands for the machine's MemAvailable. Before: 1e7 balls ran the machine out of
-- memory at the first cycle and the kernel killed the process with no message.
local T = require("testlib")

local ball_line = T.line() + 3 -- the m:ball line below, where a refusal points
local function pack(m, n)
    for i = 0, n - 1 do
        m:ball{ pos = { (i % 200) * 0.0199, (i // 200) * 0.0199 }, radius = 0.01, density = 1000 }
    end
end

-- 1. Creating balls: refused where the ball arrays grow, with the estimate and the limit; the
-- balls made before are kept, and the model runs once the limit allows it.
do
    local m = talus.model{}
    m:placement_warning(false)
    m:contact_model("linear", { kn = 1e6 })
    m:guard{ memory_limit = 20e6 }
    local err = T.fails(function() pack(m, 100000) end,
        { "regress/memory_guard.lua:" .. ball_line .. ":" }, "ball creation refused")
    T.check(err:find("ball: the model would need about 26.7 MB (8193 balls at about 530 B each, "
        .. "with about 3 contact pairs each at 908 B), 26.7 MB more than it holds now, and "
        .. "m:guard{memory_limit =} allows 20 MB in all", 1, true), err)
    T.check(m:ball_count() == 8192, "the balls made before are kept: " .. m:ball_count())
    m:guard{ memory_limit = 30e6 }
    m:cycle(1)
    T.check(m:contact_count{ active = false } > 3 * 8192 * 0.9, "it runs when the memory is there")
    T.check(m:guard().memory_limit == 30e6, "m:guard returns the limit")
end

-- 2. Running: the pairs of balls not yet run are counted at the cycle (and at a solve), and the
-- cycle is refused before it allocates them; nothing ran.
do
    local m = talus.model{}
    m:placement_warning(false)
    m:contact_model("linear", { kn = 1e6 })
    pack(m, 6000)
    m:guard{ memory_limit = 10e6 }
    local l = T.line(); T.fails(function() m:cycle(10) end,
        { "regress/memory_guard.lua:" .. l .. ": cycle: the model would need about 19.5 MB (6000 balls",
          "allows 10 MB in all" }, "cycle refused")
    T.fails(function() m:solve{ steps = 10 } end, { "solve: the model would need about 19.5 MB" }, "solve refused")
    T.check(m:step() == 0, "no step was taken")
    -- a contact model with a larger object raises the estimate (pbond: 480 B against 208 B)
    local p = talus.model{}
    p:contact_model("pbond", { kn = 1e6, ks = 1e6 })
    pack(p, 6000)
    p:guard{ memory_limit = 10e6 }
    T.fails(function() p:cycle(1) end, { "each at 1.18 kB" }, "the model object counts")
end

-- 3. A run of a model that fits is not touched, nor is its result: no limit, no check below 64 MiB
-- of growth.
do
    local m = talus.model{}
    m:contact_model("linear", { kn = 1e6 })
    m:ball{ pos = { 0, 0 }, radius = 0.1, density = 1000 }
    m:cycle(5)
    T.check(m:step() == 5, "runs")
end
T.done("memory_guard")
