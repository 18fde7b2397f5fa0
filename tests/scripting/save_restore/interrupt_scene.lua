-- SPDX-License-Identifier: MIT
-- `talus run --save-on-interrupt FILE` (docs/output.md, "Ctrl-C"), driven by
-- interrupt_save.py:
--   talus run --save-on-interrupt DIR/int.talus interrupt_scene.lua run DIR
--       an endless m:cycle with a history and a ParaView series; after step 300 it writes
--       DIR/marker (the test then sends SIGINT)
--   talus run --save-on-interrupt DIR/solve.talus interrupt_scene.lua run_solve DIR
--       the same with an endless m:solve, which returns "interrupted" (the save is taken
--       before it returns); the script prints the step and ends
--   talus run interrupt_scene.lua resume DIR S K [FILE]
--       talus.restore(DIR/FILE or DIR/int.talus): it must be at step S; runs K more steps
--   talus run interrupt_scene.lua straight DIR S K
--       the same scene without an interrupt: S steps, then K more
-- Both write DIR/PHASE_start.txt (time and step where the second part starts) and
-- DIR/PHASE.txt (the state after it, every number with %a), and the test requires them, the
-- CSV histories and the .pvd collections to be equal byte for byte.
local phase, dir, S, K, file = ...
assert(phase and dir, "usage: interrupt_scene.lua run|resume|straight DIR [S K]")
S, K = tonumber(S), tonumber(K)

-- A small deterministic generator (the scene must not depend on Lua's math.random).
local seed = 4711
local function rand()
    seed = (seed * 1103515245 + 12345) % 2147483648
    return seed / 2147483648
end

local function scene(tag)
    local m = talus.model{ gravity = {0, -9.81} }
    m:contact_model("linear", { kn = 2e6, ks = 1e6, fric = 0.4, dp_nratio = 0.2 })
    m:wall{ points = {{0, 2}, {0, 0}, {1.2, 0}, {1.2, 2}} }
    m:damping{ damp = 0.05 }
    for i = 0, 9 do
        for j = 0, 9 do
            m:ball{ pos = {0.07 + 0.11 * i + 0.005 * rand(), 0.06 + 0.11 * j},
                    radius = 0.035 + 0.015 * rand(), density = 2600,
                    vel = {rand() - 0.5, rand() - 0.5} }
        end
    end
    m:energy{ on = true }
    m:history{ file = dir .. "/" .. tag .. ".csv", every = 10,
               columns = { "step", "time", "kinetic", "strain", "balance_error" } }
    m:vtk{ dir = dir .. "/vtk_" .. tag, every = 50 }
    return m
end

local T = require("testlib")
local fmt, sortedKeys = T.hex, T.sorted_keys

local function write(path, text)
    local f = assert(io.open(path, "w"))
    f:write(text)
    f:close()
end

local function start(m, tag)
    write(dir .. "/" .. tag .. "_start.txt", fmt(m:time()) .. " " .. m:step() .. "\n")
end

local function dump(m, tag)
    local out = {}
    local dt = m:dt()
    out[#out + 1] = table.concat({ "time", fmt(m:time()), "step", m:step(), "dt", fmt(dt) }, " ")
    for b in m:balls() do
        out[#out + 1] = table.concat({ "ball", b.id, fmt(b.pos), fmt(b.vel), fmt(b.spin),
                                       fmt(b.force), fmt(b.moment) }, " ")
    end
    for c in m:contacts{ active = false } do
        out[#out + 1] = table.concat({ "contact", c.key, tostring(c.active),
                                       fmt(c.normal_force), fmt(c.shear_force),
                                       fmt(c.overlap) }, " ")
    end
    local e = m:energies()
    for _, k in ipairs(sortedKeys(e)) do out[#out + 1] = "energy " .. k .. " " .. fmt(e[k]) end
    write(dir .. "/" .. tag .. ".txt", table.concat(out, "\n") .. "\n")
end

if phase == "run" or phase == "run_solve" then
    local solve = phase == "run_solve"
    local m = scene(solve and "solve" or "split")
    -- The marker says "under way" to the test; an on_cycle callback only reads the model.
    m:on_cycle(function(_, step)
        if step == 300 then write(dir .. "/marker", "300\n") end
    end, 10)
    if solve then
        local why = m:solve{ ["until"] = function() return false end }
        print(string.format("solve returned %s at step %d", why, m:step()))
        return
    end
    m:cycle(2000000000)
    error("the cycle ended without an interrupt")
elseif phase == "resume" then
    local m, notes = talus.restore(dir .. "/" .. (file or "int.talus"), { quiet = true })
    local tag = file and "solve" or "split"
    local text = table.concat(notes, "\n")
    assert(text:find("history '" .. dir .. "/" .. tag .. ".csv' continues", 1, true), text)
    assert(text:find("vtk series '" .. dir .. "/vtk_" .. tag .. "/talus.pvd' continues", 1,
                     true), text)
    assert(m:step() == S, "restored at step " .. m:step() .. ", stopped at " .. S)
    start(m, "resumed" .. (file and "_solve" or ""))
    m:cycle(K)
    m:close_history()
    dump(m, "resumed" .. (file and "_solve" or ""))
elseif phase == "straight" then
    local m = scene("straight")
    m:cycle(S)
    start(m, "straight")
    m:cycle(K)
    m:close_history()
    dump(m, "straight")
else
    error("unknown phase " .. phase)
end
