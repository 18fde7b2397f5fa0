-- SPDX-License-Identifier: MIT
-- rockfall/random.lua: the random streams of a rock: every draw of rock i comes from a splitmix64
-- generator (talus_util.random) seeded by (analysis seed, i, purpose), so a rock does not depend
-- on how many rocks the analysis has, on their order, or on how they are shared among workers.
local R = require("talus_util.random")
local K = require("rockfall.check")
local fail = K.fail
local mix, GOLDEN = R.mix, R.GOLDEN

--- A generator with its own stream (splitmix64): r:uniform() in [0, 1), r:normal(), r:range(a, b).
local function rng(seed)
    local s = R.integer_seed(seed)
    if not s then fail("a seed must be an integer (got %s)", tostring(seed)) end
    return R.splitmix64(s)
end

-- The purposes of a rock's streams: changing how one quantity is drawn never shifts another.
local STREAMS = {
    seeder = 1, position = 2, shape = 3, size = 4, density = 5, angle = 6, vx = 7, vy = 8,
    spin = 9, roughness = 10,
}

--- The integer seed of rock i in an analysis with seed s: a hash of (s, i) only.
local function rock_seed(s, i)
    return mix(mix(s) + i * GOLDEN)
end

--- The generator of one purpose of one rock (or of the analysis when rock_seed is its seed).
local function stream(rock_seed, purpose)
    local id = STREAMS[purpose] or fail("unknown random stream '%s'", tostring(purpose))
    return rng(mix(rock_seed ~ (id * 0x632BE59BD9B4E019)))
end

return { rng = rng, rock_seed = rock_seed, stream = stream, STREAMS = STREAMS }
