-- SPDX-License-Identifier: MIT
-- A barrier (m:barrier) takes its capacity E from a body crossing it the first time, or stops a
-- body with less, and books what it took as the energy item `barrier`, so that the balance check
-- stays on (docs/rockfall.md, "Barriers"). Closed form: a disk in free flight without gravity
-- crosses with KE; after it KE - E (or 0), `barrier` = E (or KE), the balance closes to
-- round-off, whole model and group.
-- Before: the barrier was a Lua handler that scaled the velocity and had to switch the balance
-- check off.
local T = require("testlib")

local DT = 1e-4
local ROUND = 1e-12

-- A disk of radius 0.1 m at x = 0 moving at (vx, vy) with spin w toward a vertical barrier at
-- x = 0.5 from y = -1 to y = top; the balance check is an error.
local function scene(opts)
    local m = talus.model{ gravity = opts.gravity or { 0, 0 } }
    m:contact_model("linear", { kn = 1e7 })
    m:timestep{ fixed = DT }
    m:guard{ balance = "error", balance_tolerance = 1e-9 }
    local b = m:ball{ pos = { 0, opts.y or 0 }, radius = 0.1, density = 2650, vel = opts.vel,
                      spin = opts.spin or 0, group = "rock" }
    local id = m:barrier{ name = "fence", from = { 0.5, -1 }, to = { 0.5, opts.top or 1 },
                          energy = opts.energy }
    m:energy{ on = true }
    return m, b, id
end

local function ke(b)
    local v = b.vel
    return 0.5 * b.mass * (v[1] * v[1] + v[2] * v[2]) + 0.5 * b.inertia * b.spin * b.spin
end

local function balanced(m, what)
    for _, g in ipairs({ nil, "rock" }) do
        local e = g and m:energies(g) or m:energies()
        T.check(math.abs(e.balance_error) <= ROUND * e.input,
            string.format("%s (%s): balance_error %.3g J of input %.6g J", what, g or "model",
                e.balance_error, e.input))
    end
end

-- A fast disk: passes with KE - E; barrier = E; its direction and the ratio v/w unchanged.
do
    local m, b = scene{ vel = { 10, 1 }, spin = 20, energy = 1000 }
    local ke0 = ke(b)
    m:cycle(1000) -- crosses x = 0.5 after 0.05 s = 500 steps
    local e, eg = m:energies(), m:energies("rock")
    T.near(ke(b), ke0 - 1000, ROUND * ke0, "fast disk: KE after = KE - E")
    T.near(e.barrier, 1000, ROUND * ke0, "fast disk: barrier item = E")
    T.near(eg.barrier, 1000, ROUND * ke0, "fast disk: group rock's barrier item = E")
    T.near(e.kinetic, ke0 - 1000, ROUND * ke0, "fast disk: kinetic item = KE - E")
    local f = math.sqrt((ke0 - 1000) / ke0)
    T.near(b.vel[1], 10 * f, 1e-12, "fast disk: vx scaled by sqrt((KE - E) / KE)")
    T.near(b.vel[2], 1 * f, 1e-12, "fast disk: vy scaled likewise")
    T.near(b.spin, 20 * f, 1e-12, "fast disk: spin scaled likewise")
    T.check(e.script == 0, "fast disk: nothing booked as script (" .. e.script .. " J)")
    balanced(m, "fast disk")
    local info = m:barriers()[1]
    T.check(info.passed == 1 and info.stopped == 0, "fast disk: one passed, none stopped")
    T.near(info.absorbed, 1000, 1e-9, "fast disk: the barrier's absorbed = E")
    -- Back across it: a barrier catches a body once.
    b.vel = { -10, 0 }
    m:cycle(1000)
    T.check(m:barriers()[1].passed == 1, "fast disk: not caught again on the way back")
    T.near(m:energies().barrier, 1000, ROUND * ke0, "fast disk: barrier item unchanged")
    balanced(m, "fast disk, back")
end

-- A slow disk: stopped, fixed where it is; barrier = KE.
do
    local m, b = scene{ vel = { 2, 0 }, spin = 5, energy = 1e6 }
    local ke0 = ke(b)
    m:cycle(3000) -- crosses after 0.25 s = 2500 steps
    local e = m:energies()
    T.check(b.vel[1] == 0 and b.vel[2] == 0 and b.spin == 0, "slow disk: stopped")
    T.check(type(b.fix) == "table" and #b.fix == 3, "slow disk: fixed in x, y and spin")
    T.check(b.pos[1] >= 0.5 and b.pos[1] < 0.5 + 2 * DT * 2, "slow disk: held at the barrier, x = " .. b.pos[1])
    T.near(e.barrier, ke0, ROUND * ke0, "slow disk: barrier item = KE")
    T.near(m:energies("rock").barrier, ke0, ROUND * ke0, "slow disk: group's barrier item = KE")
    T.check(math.abs(e.kinetic) <= ROUND * ke0, "slow disk: no kinetic energy left")
    balanced(m, "slow disk")
    local info = m:barriers()[1]
    T.check(info.stopped == 1 and info.passed == 0, "slow disk: one stopped")
    T.near(info.absorbed, ke0, ROUND * ke0, "slow disk: absorbed = KE")
end

-- Over the top: a disk whose centre crosses more than its radius above the top flies over; one
-- within its radius of it is caught.
do
    local m, b = scene{ vel = { 10, 0 }, y = 1.11, energy = 100 }
    m:cycle(1000)
    T.check(m:barriers()[1].passed == 0 and m:energies().barrier == 0, "over the top: not caught")
    local m2 = scene{ vel = { 10, 0 }, y = 1.09, energy = 100 }
    m2:cycle(1000)
    T.check(m2:barriers()[1].passed == 1, "within its radius of the top: caught")
end

-- Under gravity, in flight: what the barrier took is the change of what the snapshot books (close
-- to E: within the work of gravity over a step), and the balance closes.
do
    local m, b = scene{ gravity = { 0, -9.81 }, vel = { 10, 3 }, energy = 500, top = 5 }
    local v0 = 10
    m:cycle(1000)
    local e = m:energies()
    T.check(math.abs(e.barrier - 500) <= b.mass * 9.81 * 4 * DT * v0,
        string.format("under gravity: barrier %.9g J, E = 500 J", e.barrier))
    balanced(m, "under gravity")
end

-- A clump, with a tracker whose line is the barrier: the tracker's crossing is the state the
-- barrier saw (KE before it), the clump goes on with KE - E.
do
    local m = talus.model{ gravity = { 0, 0 } }
    m:contact_model("linear", { kn = 1e7 })
    m:timestep{ fixed = DT }
    m:guard{ balance = "error", balance_tolerance = 1e-9 }
    local c = m:clump{ pebbles = { { -0.05, 0, 0.06 }, { 0.05, 0, 0.06 } }, pos = { 0, 0 }, density = 2650,
                       vel = { 8, 0 }, spin = 4 }
    m:barrier{ from = { 0.5, -1 }, to = { 0.5, 1 }, energy = 200 }
    m:energy{ on = true }
    local seen
    local tr = m:track(c, { lines = { { from = { 0.5, -1 }, to = { 0.5, 1 }, event = true } },
        on_event = function(_, ev) if ev.kind == "crossing" then seen = ev.crossing end end })
    local ke0 = 0.5 * c.mass * 64 + 0.5 * c.inertia * 16
    m:cycle(1000)
    T.check(seen ~= nil, "clump: the tracker reported the crossing")
    if seen then T.near(seen.ke_trans + seen.ke_rot, ke0, ROUND * ke0, "clump: the crossing's KE is before the barrier") end
    local v = c.vel
    T.near(0.5 * c.mass * (v[1] * v[1] + v[2] * v[2]) + 0.5 * c.inertia * c.spin * c.spin, ke0 - 200,
        ROUND * ke0, "clump: KE after = KE - E")
    T.near(m:energies().barrier, 200, ROUND * ke0, "clump: barrier item = E")
    balanced(m, "clump")
    tr:stop()
end

-- Bad input: a clear error naming the field.
do
    local m = talus.model{}
    T.fails(function() m:barrier{ from = { 0, 0 }, to = { 0, 0 }, energy = 1 } end, { "zero length" }, "zero length")
    T.fails(function() m:barrier{ from = { 0, 0 }, to = { 0, 1 }, energy = -1 } end, { "energy", ">= 0" }, "negative")
    T.fails(function() m:barrier{ from = { 0, 0 }, to = { 0, 1 } } end, { "energy", "required" }, "missing")
    T.fails(function() m:barrier{ from = { 0, 0 }, to = { 0, 1 }, energy = 1, heigth = 2 } end, { "heigth" }, "typo")
end

-- A rockfall run with barriers keeps the balance check on: a rock that passes one fence and is
-- stopped by the next; the barrier item is E_cap of the first plus the stopped rock's KE, to 1%:
-- the item is what the whole-step snapshot loses, and the rock hits the net while bouncing, so
-- the KE at the crossing and at the whole step differ by the work of that step's contact force
-- (0.45% here). The balance closes within the guard's tolerance.
do
    local rf = require("rockfall")
    local lin = { model = "linear", props = { kn = 1e7, ks = 5e6, fric = 0.5, dp_nratio = rf.dp_nratio(0.5) } }
    local an = rf.analysis{
        profile = { { 0, 8 }, { 6, 2 }, { 9, 0 }, { 24, 0 } },
        materials = { hard = lin }, zones = { { material = "hard", x_from = 0, x_to = 24 } },
        seeders = { { kind = "point", at = { 0.5, 8.9 }, vx = 3, spin = 0,
            rock = { { shape = "ball", radius = 0.3 } } } },
        barriers = { { name = "fence", x = 12, energy = 2000, height = 1 },
                     { name = "net", x = 14, energy = 1e6, height = 1 } },
        t_max = 10, seed = 3, n = 1,
    }
    local balance, barrier, bal_err, input
    local rec = rf.run_rock(an, 1, { on_end = function(m)
        balance = m:guard{}.balance
        local e = m:energies()
        barrier, bal_err, input = e.barrier, e.balance_error, e.input
    end })
    T.check(balance ~= "off", "rockfall: the balance check stays on (" .. tostring(balance) .. ")")
    T.check(rec.stop == "barrier" and #rec.barrier == 2 and not rec.barrier[1].stopped and rec.barrier[2].stopped,
        "rockfall: passes the fence, stopped by the net (stop " .. tostring(rec.stop) .. ")")
    if #rec.barrier == 2 then
        local expect = 2000 + rec.barrier[2].energy
        T.check(math.abs(barrier - expect) <= 1e-2 * expect,
            string.format("rockfall: barrier item %.6g J, E_cap + the stopped rock's KE %.6g J", barrier, expect))
    end
    T.check(rec.barrier_absorbed == 2000, "rockfall: the record's barrier_absorbed is the fence's E_cap")
    T.check(math.abs(bal_err) <= 0.01 * input,
        string.format("rockfall: balance_error %.3g J of input %.6g J", bal_err, input))
end

T.done("barrier_energy")
