-- SPDX-License-Identifier: MIT
-- A small flat-jointed specimen crushed in a UCS test (the material library's genesis, specimen and
-- compress): it loads elastically, its interfaces crack element by element, and it fails with a
-- post-peak drop, at a modulus and a strength of the order its micro-properties give.
-- M.specimen installs `mat.model` with m:bond and the bond's properties (the material's kn, ks and
-- fric only go to a model that has them: fjoint has no linear part). The rest is the library's:
-- platens, the linear rule for contacts made later (as in PFC's flat-jointed material),
-- relaxation, loading, E and nu.
local T = require("testlib")
local M = require("material")

local pk, mat, E_MICRO = T.small_fjoint(3)
local sp = M.specimen(pk, mat)
T.check(sp.bonds > #pk.balls, "interfaces " .. sp.bonds .. " for " .. #pk.balls .. " balls")
local nbond0 = 0
for c in sp.model:contacts{ model = "fjoint" } do nbond0 = nbond0 + c:prop("fj_nbond") end
T.check(nbond0 == 2 * sp.bonds, "every interface bonded with two elements")

local r = M.compress(sp, { post_peak = 0.8, strain_per_crossing = 2e-5 })
local nbond, partial = 0, 0
for c in sp.model:contacts{ model = "fjoint" } do
    local k = c:prop("fj_nbond")
    nbond = nbond + k
    if k == 1 then partial = partial + 1 end
end
local e = sp.model:energies()
print(string.format("fjoint_ucs: %d balls, %d interfaces; UCS %.1f MPa, E %.1f GPa, nu %.3f, "
                    .. "peak strain %.3g; element breaks: %d tension, %d shear (events), %d of "
                    .. "%d elements still bonded, %d interfaces half broken; %d steps, %.1f s; "
                    .. "balance error %.2e of the boundary work",
                    #pk.balls, sp.bonds, r.ucs / 1e6, r.E / 1e9, r.nu, r.peak_strain,
                    r.breaks.tension, r.breaks.shear, nbond, nbond0, partial, r.steps, r.time,
                    math.abs(e.balance_error) / e.boundary))
T.check(r.stop == "post_peak", "stopped by " .. r.stop)
T.check(r.ipeak > 5 and r.ipeak < #r.rows, "the peak is inside the curve")
T.check(r.rows[#r.rows].sa < 0.8 * r.ucs, "post-peak drop")
T.check(r.breaks.tension > 0 and r.breaks.shear > 0, "elements broke in tension and in shear")
T.check(partial > 0, "some interfaces lost one element of two (partial damage)")
-- The order of magnitude: a bonded disk assembly's modulus is a fraction of the bonds' modulus
-- (0.2-0.6 kn for the contact-bonded specimen of material_ucs.lua; the flat joints add their
-- stiffness to no linear part here), and its strength a few times the bonds' tensile strength
-- (the parallel-bonded Lac du Bonnet material: UCS 178 MPa from pb_ten 157 MPa).
T.check(r.E > 0.2 * E_MICRO and r.E < 1.5 * E_MICRO, "E " .. r.E)
T.check(r.ucs > 2e7 and r.ucs < 2e9, "UCS " .. r.ucs)
T.check(r.nu > 0 and r.nu < 1, "nu " .. r.nu)
-- The books close while the specimen cracks (the guard's run-level check is at 1e-2).
T.check(math.abs(e.balance_error) < 1e-2 * e.boundary, "energy balance " .. e.balance_error)
T.done("fjoint_ucs")
