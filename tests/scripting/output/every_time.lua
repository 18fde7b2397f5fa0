-- SPDX-License-Identifier: MIT
-- ParaView frames at fixed simulated times (m:vtk{every_time =}): how many frames a known run
-- writes and when, read back from the .pvd. With a fixed step dt that does not divide the frame
-- interval, frame k must be the end of the step nearest k * every_time: step n = round(k T / dt),
-- so |t_k - k T| <= dt / 2.
-- usage: talus run every_time.lua OUTDIR
local T = require("testlib")
local out = assert(arg[1], "usage: every_time.lua OUTDIR")
talus.mkdir(out)

--- The frames of a .pvd as {time =, file =}, in file order.
local function pvd_frames(path)
    local f = assert(io.open(path))
    local text = f:read("a")
    f:close()
    local frames = {}
    for t, file in text:gmatch('timestep="([^"]+)"[^>]-file="([^"]+)"') do
        frames[#frames + 1] = { time = tonumber(t), file = file }
    end
    return frames
end

local function scene(dt)
    local m = talus.model{ gravity = {0, -9.81} }
    m:contact_model("linear", { kn = 1e6, ks = 5e5, fric = 0.5, dp_nratio = 0.2 })
    m:wall{ points = {{-1, 0}, {1, 0}} }
    m:ball{ pos = {0, 0.3}, radius = 0.05, density = 2600 }
    m:timestep{ fixed = dt }
    return m
end

-- 1. every_time = 0.01 s with dt = 3e-4 s over 0.1 s: frames at t = 0 and near 0.01 ... 0.10
-- (0.1 / 3e-4 = 333.3 steps).
local period, dt = 0.01, 3e-4
local m = scene(dt)
local v = m:vtk{ dir = out .. "/every_time", every_time = period, contacts = false }
T.check(v.frames == 1, "the first frame is the state at creation")
m:solve{ time = 0.1 }
local frames = pvd_frames(v.file)
T.check(#frames == 11 and v.frames == 11,
    "11 frames (t = 0 and 10 multiples of 0.01 s), got " .. #frames .. " / " .. v.frames)
for k, f in ipairs(frames) do
    local target = (k - 1) * period
    local n = math.floor(target / dt + 0.5)
    -- The step nearest the target: its end n dt (the clock sums dt: a few ulps of t). The last
    -- frame is at 333 dt = 0.0999 s, the frame being due within half a step; solve's
    -- shortened last step, which then lands on 0.1 s, writes none.
    T.near(f.time, n * dt, 1e-12, "frame " .. (k - 1) .. " time")
    T.check(math.abs(f.time - target) <= 0.5 * dt * (1 + 1e-9),
        string.format("frame %d within dt/2 of %g s: %.9g", k - 1, target, f.time))
end

-- 2. Frames follow the simulated clock, not the steps: with dt 10 times smaller the same
-- number of frames, at times closer to the multiples.
local m2 = scene(3e-5)
local v2 = m2:vtk{ dir = out .. "/every_time_fine", every_time = period, contacts = false }
m2:solve{ time = 0.1 }
local fine = pvd_frames(v2.file)
T.check(#fine == 11, "11 frames with dt = 3e-5 s too, got " .. #fine)
for k, f in ipairs(fine) do
    T.check(math.abs(f.time - (k - 1) * period) <= 1.5e-5 * (1 + 1e-9),
        "fine frame " .. (k - 1) .. " at " .. f.time)
end

-- 3. A step longer than every_time: one frame per step, never two of the same time.
local m3 = scene(3e-4)
local v3 = m3:vtk{ dir = out .. "/every_time_short", every_time = 1e-4, contacts = false }
m3:cycle(5)
local short = pvd_frames(v3.file)
T.check(#short == 6, "one frame per step when steps are longer than every_time: " .. #short)
for k = 2, #short do T.check(short[k].time > short[k - 1].time, "frame times increase") end

-- 4. A series started at t = 0.037 s: its next frames at the multiples of the clock, 0.04, ...
local m4 = scene(1e-4)
m4:solve{ time = 0.037 }
local v4 = m4:vtk{ dir = out .. "/every_time_late", every_time = period, contacts = false }
m4:solve{ time = 0.023 }
local late = pvd_frames(v4.file)
T.check(#late == 4, "frames at 0.037, 0.04, 0.05 and 0.06 s, got " .. #late)
T.near(late[2].time, 0.04, 1e-9, "the next multiple of the clock")
T.near(late[3].time, 0.05, 1e-9, "then every 0.01 s")
T.near(late[4].time, 0.06, 1e-9, "to the end")

-- 5. A save does not continue such a series; the restore says so and how to go on with it.
local m6 = scene(1e-4)
m6:vtk{ dir = out .. "/every_time_saved", every_time = period, contacts = false }
m6:cycle(10)
m6:save(out .. "/every_time.sav")
local _, notes = talus.restore(out .. "/every_time.sav", { quiet = true })
local said = false
for _, n in ipairs(notes) do
    if n:find("every_time", 1, true) and n:find("append = true", 1, true) then said = true end
end
T.check(said, "the restore's note names every_time and append: " .. table.concat(notes, " | "))

-- 6. Bad input.
local m5 = scene(1e-4)
T.fails(function() m5:vtk{ dir = out .. "/x", every_time = 0 } end,
    { "every_time", "must be a time > 0" }, "every_time = 0")
T.fails(function() m5:vtk{ dir = out .. "/x", every_time = -1 } end,
    { "every_time", "must be a time > 0" }, "every_time < 0")
T.fails(function() m5:vtk{ dir = out .. "/x", every = 10, every_time = 0.01 } end,
    { "'every'", "'every_time'", "not both" }, "every and every_time")
print(T.checks .. " checks passed")
