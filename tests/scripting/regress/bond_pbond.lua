-- SPDX-License-Identifier: MIT
-- m:bond with the parallel bond (pbond): a loaded packing bonded with and without reset; the
-- stiffnesses of the bond (kbn = pb_kn 2R, kbr = pb_kn 2R^3/3) enter the next step at once.
local T = require("testlib")

local KN, KS = 1e7, 5e6
local src = io.open((T.script():gsub("bond_pbond", "bond_install"))):read("a")
local packed = load("local T = ...\nlocal KN, KS = 1e7, 5e6\n" ..
    src:match("(local function packed%(%).-\nend\n)") .. "\nreturn packed")(T)

local PB = { pb_kn = 1e9, pb_ks = 5e8, pb_ten = 1e7, pb_coh = 1e7, pb_rmul = 1 }

-- 1. Without reset the linear part keeps its forces (kn, ks, fric carry over from linear);
-- the bond part starts at zero.
do
    local m = packed()
    local before = {}
    for c in m:contacts{} do before[c.key] = c.normal_force end
    local n = m:bond{ model = "pbond", props = PB, walls = true }
    T.check(n == m:contact_count{}, "every contact bonded")
    for c in m:contacts{} do
        T.check(c.model == "pbond" and c:prop("bonded") == 1 and c:prop("pb_state") == 3, "bonded")
        T.check(c:prop("kn") == KN and c:prop("ks") == KS and c:prop("fric") == 0.5, "carried over")
        T.near(c.normal_force, before[c.key], 1e-12, "normal force kept")
        T.check(c:prop("pb_fn") == 0 and c:prop("pb_m") == 0, "the bond starts at zero")
    end
    -- The next step's stability limit holds the bond: per ball, safety sqrt(m / sum(kn + ks
    -- + kbn + kbs)) with kbn = pb_kn 2R, the smallest ball (r >= 0.0485) with at most 6
    -- contacts bounds it from below; the linear contacts alone allowed ~8 times more.
    m:cycle(1)
    local r = 0.0485
    local kb = (PB.pb_kn + PB.pb_ks) * 2 * r
    local bound = 0.8 * math.sqrt(2600 * math.pi * r * r / (6 * (KN + KS + kb)))
    T.check(m:dt() <= 0.8 * math.sqrt(2600 * math.pi * 0.0515 ^ 2 / (KN + KS + kb)),
        "the step follows the bond's stiffness at once: " .. m:dt())
    T.check(m:dt() >= 0.2 * bound, "and is not absurdly small: " .. m:dt())
end

-- 2. reset = true: lin_mode = 1, zero forces, the specimen at rest stays so, and the strain
-- energy the linear contacts held is released (the balance closes; see bond_install.lua).
do
    local m = packed()
    for b in m:balls{} do
        b.vel = {0, 0}
        b.spin = 0
    end
    m:energy{ on = true }
    m:cycle(2)
    local e0 = m:energies()
    local n = m:bond{ model = "pbond", props = PB, walls = true, reset = true, seed = 3 }
    T.check(n == m:contact_count{}, "every contact bonded")
    for c in m:contacts{} do
        T.check(c.normal_force == 0 and c.shear_force == 0 and c.moment == 0, "zero forces")
        T.check(c:prop("lin_mode") == 1, "incremental normal force")
    end
    m:cycle(1)
    local e1 = m:energies()
    -- (the packing's one-step change of strain: bound as in bond_install.lua, section 3)
    T.near(e1.released - e0.released, e0.strain, 5e-6, "the linear strain energy is released")
    m:cycle(300)
    local e2 = m:energies()
    local vmax = 0
    for b in m:balls{} do vmax = math.max(vmax, math.sqrt(b.vel[1] ^ 2 + b.vel[2] ^ 2)) end
    -- At rest: no force is left to move it (a kick from a force not released would be
    -- F/m dt ~ 4e3 N / 20 kg * 1e-4 s = 0.02 m/s); what moves is the residual motion of the
    -- unsettled packing at the install (~1e-4 m/s), whose energy does not grow: the mechanical
    -- energy after is at most what it was at the install (~4e-5 J, 1.6e-7 of the released).
    local mech = function(e) return e.kinetic + e.strain + e.bond end
    T.check(vmax < 1e-3, "the stress-free specimen stays at rest, vmax " .. vmax)
    T.check(mech(e1) < 1e-6 * e0.strain and mech(e2) <= mech(e1) + 1e-9 * e0.strain,
        "no energy appears: " .. mech(e1) .. " J at the install, " .. mech(e2) .. " J after")
    T.check(math.abs(e2.balance_error) < 5e-8 * e0.strain,
        "balance closes: " .. e2.balance_error .. " J of " .. e0.strain .. " J released")
    -- unbond: all bonds go, silently.
    T.check(m:unbond{ model = "pbond" } == n, "unbond all")
    for c in m:contacts{} do T.check(c:prop("bonded") == 0, "unbonded") end
end

T.done("bond_pbond")
