-- SPDX-License-Identifier: MIT
--
-- pbond_kernel.lua: a UCS test of the Lac du Bonnet example (the micro-properties of Potyondy &
-- Cundall 2004; scripts/examples/ldb_pbond.lua) with m:kernels(on) or off: the same specimen
-- compressed for a fixed number of steps on one thread. Prints the CPU time of the compression
-- phase, the engine's profile line of the kernels and the peak stress, which must not depend on
-- the setting. It measured a host kernel of pbond's steady step against pbond's FDlaw
-- (docs/results/benchmarks-history.md, "Kernels: pbond"); the engine has none since, so for pbond
-- both settings run FDlaw.
--
--   talus run scripts/bench/pbond_kernel.lua [on|off] [scale] [steps] [material]
--
-- scale shrinks the specimen as in ldb_pbond.lua (0.25: about 250 balls); steps: compression
-- steps (default 3000); material: pbond (default, Potyondy & Cundall's micro-properties) or fjoint
-- (the calibrated flat joints of ldb_flatjoint.lua, on the same packing). For instruction counts run it under valgrind --tool=callgrind: genesis and
-- bonding are the same in both settings, so the difference is the compression phase's.
local M = require("material")
local kernels = (arg[1] or "on") == "on"
local scale = tonumber(arg[2] or "0.25")
local steps = tonumber(arg[3] or "3000")
local kind = arg[4] or "pbond"
local mat, genesis
if kind == "pbond" then
    mat, genesis = M.lac_du_bonnet()
else
    mat, genesis = M.lac_du_bonnet(kind, M.ldb_calibrated[kind])
end
local pk = genesis(0.0317 * scale, 0.0634 * scale, 1)
local m = {}
for k, v in pairs(mat) do m[k] = v end
m.seed = 1
local sp = M.specimen(pk, m)
sp.model:threads(1)
sp.model:kernels(kernels)
local c0 = os.clock()
local r = M.compress(sp, { max_steps = steps, post_peak = 0.8 })
local c1 = os.clock()
print(string.format("kernels %s: %d balls, %d bonds, %d steps, compression %.2f s CPU; stop %s, "
                    .. "peak %.6g Pa", kernels and "on" or "off", #pk.balls, sp.bonds, r.steps,
                    c1 - c0, r.stop, r.ucs))
print(sp.model:profile():match("kernel steps %d+ %(declined %d+%)"))
