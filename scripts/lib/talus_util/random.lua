-- SPDX-License-Identifier: MIT
-- talus_util/random.lua: seeded random numbers, the same on every platform and independent of
-- Lua's math.random, on Lua 5.4's 64-bit integers (multiplication and addition wrap modulo 2^64
-- and `>>` is a logical shift, which is what both algorithms need).
--
-- splitmix64 (Steele, Lea & Flood 2014) is the generator: one integer of state, passes BigCrush,
-- and its output function `mix` doubles as the hash that derives independent seeds. The
-- rockfall Monte Carlo draws every rock from it.
-- xorshift64* (Vigna 2016) stays for one reason: the material library's packings (genesis,
-- grains, bond fractions) were made with it, and a given seed must give the same specimen as
-- before; new code uses splitmix64.
local R = {}

local GOLDEN = 0x9E3779B97F4A7C15
R.GOLDEN = GOLDEN

--- splitmix64's output function (a bijective 64-bit mix); also the seed hash.
function R.mix(z)
    z = (z ~ (z >> 30)) * 0xBF58476D1CE4E5B9
    z = (z ~ (z >> 27)) * 0x94D049BB133111EB
    return z ~ (z >> 31)
end
local mix = R.mix

-- What both generators share: the draws built on next() (a 64-bit integer).
local Generator = {}
Generator.__index = Generator

--- Uniform in [0, 1): 53 random bits, every value equally likely.
function Generator:uniform()
    return (self:next() >> 11) * (1.0 / 9007199254740992.0)
end

--- Uniform in (0, 1): the midpoints of the 2^53 cells (never 0, so log() is safe).
function Generator:uniform_open()
    return ((self:next() >> 11) + 0.5) / 9007199254740992.0
end

function Generator:range(a, b) return a + (b - a) * self:uniform() end

--- A standard normal draw: Box-Muller with one of the pair, two uniforms per draw, so the
--- number of draws never depends on earlier values (keeps streams aligned); 1 - u avoids log(0).
function Generator:normal()
    local u1, u2 = 1.0 - self:uniform(), self:uniform()
    return math.sqrt(-2.0 * math.log(u1)) * math.cos(2.0 * math.pi * u2)
end

local SplitMix64 = setmetatable({}, { __index = Generator })
SplitMix64.__index = SplitMix64
function SplitMix64:next()
    self.state = self.state + GOLDEN
    return mix(self.state)
end

local XorShift64Star = setmetatable({}, { __index = Generator })
XorShift64Star.__index = XorShift64Star
function XorShift64Star:next()
    local s = self.state
    s = s ~ (s >> 12); s = s ~ (s << 25); s = s ~ (s >> 27)
    self.state = s
    return s * 0x2545F4914F6CDD1D
end

--- An integer seed from a number (an integral float is accepted); nil when it is not one.
function R.integer_seed(seed)
    if math.type(seed) == "integer" then return seed end
    if type(seed) == "number" and seed == math.floor(seed) and math.abs(seed) < 2 ^ 63 then
        return math.tointeger(seed)
    end
    return nil
end

--- A splitmix64 generator whose state starts at `seed` (an integer).
function R.splitmix64(seed)
    return setmetatable({ state = seed }, SplitMix64)
end

--- An xorshift64* generator whose state starts at `state` (a non-zero integer).
function R.xorshift64star(state)
    if state == 0 then error("xorshift64*: the state must not be 0", 2) end
    return setmetatable({ state = state }, XorShift64Star)
end

--- FNV-1a (Fowler, Noll & Vo), 64 bits, of a text, as 16 hex digits: a short key for a long
--- description (a checkpoint's key; Lua integers wrap modulo 2^64 as the hash needs).
function R.fnv1a(text)
    local h = -3750763034362895579 -- 0xcbf29ce484222325, the offset basis
    for i = 1, #text do h = (h ~ text:byte(i)) * 0x100000001b3 end
    return string.format("%016x", h)
end

return R
