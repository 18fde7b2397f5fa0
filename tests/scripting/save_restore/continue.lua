-- SPDX-License-Identifier: MIT
-- Bit-identical continuation: `talus run continue.lua SCENE PHASE DIR`.
--   PHASE = "straight": build SCENE, run 2N steps, dump the state to DIR/SCENE_straight.txt
--   PHASE = "first":    build SCENE, run N steps, m:save(DIR/SCENE.talus)
--   PHASE = "second":   talus.restore(DIR/SCENE.talus) in this fresh process, run N steps,
--                       dump to DIR/SCENE_restored.txt
-- save_restore.cmake runs the three and requires the two dumps, and the two CSV histories
-- (the restored run appends to the saving run's file), to be equal byte for byte. Every number
-- is dumped with %a (exact), so any lost bit of state shows. The automatic step is on in all
-- scenes; energy tracing with group books is on, so the energy accumulators are compared too.
local scene, phase, dir = ...
assert(scene and phase and dir, "usage: continue.lua SCENE straight|first|second DIR")

-- A small deterministic generator (the scenes must not depend on Lua's math.random).
local seed = 12345
local function rand()
    seed = (seed * 1103515245 + 12345) % 2147483648
    return seed / 2147483648
end

local N = { dense = 1500, bonded = 1500, pbond = 1500, rockfall = 2000, servo = 1500,
            mbond = 1500, fjoint = 1500 }

local scenes = {}

-- A dense pack settling under gravity in a box: contacts form, slide and end all the time.
function scenes.dense(m)
    m:gravity({0, -9.81})
    m:contact_model("linear", { kn = 2e6, ks = 1e6, fric = 0.4, dp_nratio = 0.2 })
    m:wall{ points = {{0, 2}, {0, 0}, {1.2, 0}, {1.2, 2}} }
    m:damping{ damp = 0.05 }
    for i = 0, 11 do
        for j = 0, 19 do
            m:ball{ pos = {0.06 + 0.098 * i + 0.005 * rand(), 0.05 + 0.095 * j},
                    radius = 0.035 + 0.012 * rand(), density = 2600,
                    vel = {rand() - 0.5, rand() - 0.5},
                    group = (i < 6) and "left" or "right" }
        end
    end
end

-- A bonded specimen (cbond, bonded by a rule with cb_bond = 1) crushed by a moving wall: the
-- bonds break in tension and shear in both halves of the run.
function scenes.bonded(m)
    m:gravity({0, -9.81})
    m:contact_model("linear", { kn = 1e8, ks = 5e7, fric = 0.5, dp_nratio = 0.1 })
    m:contact_model("cbond", { kn = 1e8, ks = 5e7, fric = 0.5, cb_tenf = 2e3, cb_shearf = 3e3,
                               cb_bond = 1, cb_gap = 1e-6 }, { groups = {"rock", "rock"} })
    m:wall{ points = {{-1, 0}, {2, 0}} }
    for i = 0, 11 do
        for j = 0, 7 do
            local x = 0.05 + 0.1 * i + ((j % 2 == 1) and 0.05 or 0)
            local y = 0.05 + 0.0866025403784 * j
            m:ball{ pos = {x, y}, radius = 0.05, density = 2600, group = "rock" }
        end
    end
    m:wall{ points = {{2, 0.75}, {-1, 0.75}}, vel = {0, -0.5} }
end

-- The same specimen with parallel bonds (pbond, bonded by a rule with bonded = 1): the balls
-- overlap by a hair so that the rule's contacts exist (activity distance 0).
function scenes.pbond(m)
    m:gravity({0, -9.81})
    m:contact_model("linear", { kn = 1e8, ks = 5e7, fric = 0.5, dp_nratio = 0.1 })
    m:contact_model("pbond", { emod = 1e8, kratio = 2.0, fric = 0.5, pb_emod = 1e8,
                               pb_kratio = 2.0, pb_ten = 3e4, pb_coh = 4e4, pb_fa = 30,
                               pb_mcf = 1, pb_rmul = 1, dp_nratio = 0.1, bonded = 1 },
                    { groups = {"rock", "rock"} })
    m:wall{ points = {{-1, 0}, {2, 0}} }
    for i = 0, 11 do
        for j = 0, 7 do
            local x = 0.05 + 0.0999 * i + ((j % 2 == 1) and 0.04995 or 0)
            local y = 0.05 + 0.0865159 * j
            m:ball{ pos = {x, y}, radius = 0.05, density = 2600, group = "rock" }
        end
    end
    m:wall{ points = {{2, 0.7}, {-1, 0.7}}, vel = {0, -0.5} }
end

-- A pack compressed by a servo-controlled top wall (PFC wall servo): the servo's gain follows
-- the wall's contacts, so its state and the wall's velocity must survive the restore.
function scenes.servo(m)
    m:contact_model("linear", { kn = 1e7, ks = 5e6, fric = 0.3, dp_nratio = 0.2 })
    m:wall{ points = {{0, 1.4}, {0, 0}, {1.0, 0}, {1.0, 1.4}} }
    for i = 0, 8 do
        for j = 0, 9 do
            m:ball{ pos = {0.07 + 0.107 * i, 0.07 + 0.11 * j}, radius = 0.04 + 0.012 * rand(),
                    density = 2600, vel = {rand() - 0.5, rand() - 0.5}, group = "left" }
        end
    end
    local top = m:wall{ points = {{-0.1, 1.15}, {1.1, 1.15}} }
    top:servo{ stress = 2e5, vmax = 0.5 }
end

-- Bonds installed by m:bond (pbond, drawn strengths, stress-free start) on a specimen whose
-- contacts the linear rule made; broken pairs are remembered (never re-bonded).
function scenes.mbond(m)
    m:gravity({0, -9.81})
    m:contact_model("linear", { kn = 1e8, ks = 5e7, fric = 0.5, dp_nratio = 0.1 })
    m:wall{ points = {{-1, 0}, {2, 0}} }
    for i = 0, 11 do
        for j = 0, 7 do
            local x = 0.05 + 0.0999 * i + ((j % 2 == 1) and 0.04995 or 0)
            m:ball{ pos = {x, 0.05 + 0.0865159 * j}, radius = 0.05, density = 2600,
                    group = "rock" }
        end
    end
    m:cycle(1)
    m:bond{ model = "pbond", group = "rock", reset = true, seed = 7,
            props = { emod = 1e8, kratio = 2.0, pb_emod = 1e8, pb_kratio = 2.0,
                      pb_ten = { mean = 3e4, sd = 1e4, dist = "normal" }, pb_coh = 4e4,
                      pb_fa = 30 } }
    m:wall{ points = {{2, 0.7}, {-1, 0.7}}, vel = {0, -0.5} }
end

-- A rockfall: clump rocks (a template, scaled and turned) and loose balls down a slope of
-- segments, rolling resistance (rrlinear) and dashpots.
-- The same specimen with flat joints (fjoint) installed by m:bond: elements break one by one,
-- unbonded elements slide; the interfaces' element states and shear forces must come back.
function scenes.fjoint(m)
    m:gravity({0, -9.81})
    m:contact_model("linear", { kn = 1e8, ks = 5e7, fric = 0.5, dp_nratio = 0.1 })
    m:wall{ points = {{-1, 0}, {2, 0}} }
    for i = 0, 11 do
        for j = 0, 7 do
            local x = 0.05 + 0.0999 * i + ((j % 2 == 1) and 0.04995 or 0)
            m:ball{ pos = {x, 0.05 + 0.0865159 * j}, radius = 0.05, density = 2600,
                    group = "rock" }
        end
    end
    m:cycle(1)
    m:bond{ model = "fjoint", group = "rock", reset = true, seed = 7,
            props = { fj_emod = 1e8, fj_kratio = 2.0, fj_nr = 3, fj_fric = 0.5, fj_fa = 30,
                      fj_ten = { mean = 3e4, sd = 1e4, dist = "normal" }, fj_coh = 4e4 } }
    m:wall{ points = {{2, 0.7}, {-1, 0.7}}, vel = {0, -0.5} }
end

function scenes.rockfall(m)
    m:gravity({0, -9.81})
    m:contact_model("rrlinear", { kn = 1e8, ks = 5e7, fric = 0.6, rr_fric = 0.1,
                                  dp_nratio = 0.3, dp_sratio = 0.3 })
    m:wall{ points = {{0, 10}, {3, 8}, {5, 6.5}, {8, 4.8}, {11, 2}, {15, 1.2}, {30, 0.5}} }
    local t = m:clump_template{ pebbles = {{0, 0, 0.2}, {0.25, 0.05, 0.15}, {-0.2, 0.1, 0.12},
                                           {0.05, -0.2, 0.1}} }
    for k = 1, 6 do
        m:clump{ template = t, pos = {0.6 + 0.55 * k, 10.5 - 0.6 * k + 1.0},
                 angle = 6.28 * rand(), scale = 0.8 + 0.4 * rand(), vel = {1 + rand(), 0},
                 spin = rand() - 0.5, density = 2600, group = "rocks" }
    end
    for k = 1, 5 do
        m:ball{ pos = {5.5 + 0.5 * k, 7.5 - 0.4 * k}, radius = 0.08 + 0.04 * rand(),
                density = 2600, group = "pebbles" }
    end
end

local function setup(m)
    m:energy{ on = true }
end

local T = require("testlib")
local fmt, sortedKeys = T.hex, T.sorted_keys

local function dump(m, path)
    local out = {}
    local function line(...) out[#out + 1] = table.concat({...}, " ") end
    local dt, rule = m:dt()
    line("time", fmt(m:time()), "step", m:step(), "dt", fmt(dt), rule)
    for b in m:balls() do
        line("ball", b.id, fmt(b.pos), fmt(b.vel), fmt(b.spin), fmt(b.angle), fmt(b.force),
             fmt(b.moment))
    end
    for w in m:walls() do
        local pts = {}
        for _, p in ipairs(w.points) do pts[#pts + 1] = fmt(p) end
        line("wall", w.id, fmt(w.vel), table.concat(pts, " "))
        local sv = w:servo()
        if sv then line("servo", w.id, fmt(sv.force), fmt(sv.stress), fmt(sv.vel), fmt(sv.gain)) end
    end
    for c in m:clumps() do
        line("clump", c.id, fmt(c.pos), fmt(c.vel), fmt(c.spin), fmt(c.angle))
    end
    for c in m:contacts{ active = false } do
        local props = c:props()
        local p = {}
        for _, k in ipairs(sortedKeys(props)) do p[#p + 1] = k .. "=" .. fmt(props[k]) end
        line("contact", c.key, tostring(c.active), fmt(c.normal_force), fmt(c.shear_force),
             fmt(c.moment), fmt(c.overlap), tostring(c.sliding), table.concat(p, " "))
    end
    local function energies(tag, e)
        local p = {}
        for _, k in ipairs(sortedKeys(e)) do p[#p + 1] = k .. "=" .. fmt(e[k]) end
        line(tag, table.concat(p, " "))
    end
    energies("energy", m:energies())
    for _, g in ipairs({"left", "right", "rock", "rocks", "pebbles"}) do
        local ok, e = pcall(m.energies, m, g)
        if ok then energies("energy@" .. g, e) end
    end
    local f = assert(io.open(path, "w"))
    f:write(table.concat(out, "\n"), "\n")
    f:close()
end

local function history(m, name)
    local cols = { "step", "time", "dt", "kinetic", "strain", "balance_error" }
    if scene == "dense" then cols[#cols + 1] = "kinetic@left" end
    return m:history{ file = dir .. "/" .. scene .. "_" .. name .. ".csv", every = 50,
                      columns = cols }
end

local save = dir .. "/" .. scene .. ".talus"
if phase == "straight" or phase == "first" then
    local m = talus.model{}
    scenes[scene](m)
    setup(m)
    history(m, phase == "straight" and "straight" or "split")
    if phase == "straight" then
        m:cycle(2 * N[scene])
        dump(m, dir .. "/" .. scene .. "_straight.txt")
    else
        m:cycle(N[scene])
        m:save(save)
    end
elseif phase == "second" then
    local m, notes = talus.restore(save)
    assert(#notes >= 1 and notes[1]:match("continues"), "the history continues: " ..
           tostring(notes[1]))
    m:cycle(N[scene])
    m:close_history()
    dump(m, dir .. "/" .. scene .. "_restored.txt")
else
    error("unknown phase " .. phase)
end
print("continue.lua " .. scene .. " " .. phase .. " done")
