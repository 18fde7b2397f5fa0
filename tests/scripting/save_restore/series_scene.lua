-- SPDX-License-Identifier: MIT
-- Output series through save and restore (docs/save-format.md, HOST), driven by
-- series_continue.py:  talus run series_scene.lua PHASE DIR
--   PHASE = "straight": 2N steps with the series below, in DIR
--   PHASE = "first":    N steps, m:save(DIR/series.talus)
--   PHASE = "second":   talus.restore in a fresh process, N more steps
-- Series: "talus" (every 20, built-in fields), "slow" (every 70, no walls), "fn" (a Lua
-- function field: not continued by the restore, the script goes on with it through
-- m:vtk{append = true}; every 35, so that its last frame is at the save and append writes none
-- now), and numbered pictures every 50 (when talus has cairo). N = 140 is a
-- frame step of both continued series: the restored run must not write that frame again.
local phase, dir = ...
assert(phase and dir, "usage: series_scene.lua straight|first|second DIR")
local N = 140

local function height(b) return b.pos[2] end

local function scene()
    local m = talus.model{ gravity = {0, -9.81} }
    m:contact_model("linear", { kn = 1e6, ks = 5e5, fric = 0.5, dp_nratio = 0.1 })
    m:wall{ points = {{-1, 1}, {-1, 0}, {1, 0}, {1, 1}} }
    for i = 0, 8 do
        for j = 0, 3 do
            m:ball{ pos = {-0.8 + 0.2 * i, 0.1 + 0.2 * j}, radius = 0.06 + 0.004 * ((i + j) % 5),
                    density = 2600, vel = {0.1 * ((i * 7 + j) % 3 - 1), 0},
                    group = (i % 2 == 0) and "even" or "odd" }
        end
    end
    m:clump{ pebbles = {{-0.03, 0, 0.03}, {0.03, 0, 0.03}}, pos = {0.1, 0.9}, density = 2600,
             spin = 1, group = "rock" }
    return m
end

local function outputs(m)
    m:vtk{ dir = dir, every = 20, fields = {"force", "mass", "speed"} }
    m:vtk{ dir = dir, name = "slow", every = 70, walls = false }
    m:vtk{ dir = dir, name = "fn", every = 35, fields = { height = height } }
    -- pcall: a talus built without cairo has no pictures (the test then skips that part)
    local ok, err = pcall(m.picture, m, { file = dir .. "/pic/f.png", every = 50,
                                          size = {240, 160}, color = "speed",
                                          range = {0, 2}, contacts = "force" })
    if not ok then
        assert(tostring(err):find("without cairo", 1, true), tostring(err))
        print("no cairo: no pictures")
    end
end

local save = dir .. "/series.talus"
if phase == "straight" or phase == "first" then
    local m = scene()
    outputs(m)
    m:cycle(phase == "straight" and 2 * N or N)
    if phase == "first" then m:save(save) end
elseif phase == "second" then
    local m, notes = talus.restore(save, { quiet = true })
    local text = table.concat(notes, "\n")
    for _, want in ipairs({ "vtk series '" .. dir .. "/talus.pvd' continues (frame 8 next)",
                            "vtk series '" .. dir .. "/slow.pvd' continues (frame 3 next)",
                            "vtk series '" .. dir .. "/fn.pvd' is not continued" }) do
        assert(text:find(want, 1, true), "note '" .. want .. "' missing in:\n" .. text)
    end
    local fn = m:vtk{ dir = dir, name = "fn", every = 35, append = true,
                      fields = { height = height } }
    assert(fn.frames == 5, "fn: the frames up to the save are kept (" .. fn.frames .. ")")
    m:cycle(N)
else
    error("unknown phase " .. phase)
end
print("series_scene.lua " .. phase .. " done")
