-- Ctrl-C (docs/output.md, "Ctrl-C"): a long cycle that interrupt_test.py stops with SIGINT.
-- usage: talus run interrupt_scene.lua OUTDIR MODE
--   MODE "plain": one endless cycle; the interrupt ends the script (exit 130).
--   MODE "catch": the script catches the error, checks it, and finds that a later run call
--   stops at once; then it ends normally (talus still exits 130).
--   MODE "solve": an endless m:solve, which returns "interrupted" (the script goes on, and its
--   next run call raises "before step N").
local out, mode = assert(arg[1]), arg[2] or "plain"
local m = talus.model{ gravity = {0, -9.81} }
m:contact_model("linear", { kn = 1e6, ks = 1e6, fric = 0.3, dp_nratio = 0.2 })
m:wall{ points = {{0, 1}, {0, 0}, {1, 0}, {1, 1}} }
for i = 0, 9 do
    for j = 0, 9 do
        m:ball{ pos = {0.05 + 0.1 * i, 0.05 + 0.1 * j}, radius = 0.045, density = 2600 }
    end
end
m:history{ file = out .. "/interrupt_" .. mode .. ".csv", every = 10,
           columns = {"step", "time", {"y", function() return m:balls()().pos[2] end}} }
print("cycling")
io.stdout:flush()
if mode == "plain" then
    m:cycle(2000000000)
    error("the cycle ended without an interrupt")
end
if mode == "solve" then
    local why = m:solve{ ["until"] = function() return false end }
    assert(why == "interrupted", "m:solve returned " .. tostring(why))
    local step = m:step()
    print(string.format("solve returned %s at step %d", why, step))
    local ok, err = pcall(function() m:solve{ steps = 5 } end)
    assert(not ok and tostring(err):find("before step " .. (step + 1), 1, true), tostring(err))
    assert(m:step() == step, "no step after the interrupt")
    return
end
local ok, err = pcall(function() m:cycle(2000000000) end)
assert(not ok and tostring(err):find("interrupted (Ctrl-C) at step", 1, true), tostring(err))
local step = m:step()
local ok2, err2 = pcall(function() m:cycle(5) end)
assert(not ok2 and tostring(err2):find("before step " .. (step + 1), 1, true), tostring(err2))
assert(m:step() == step, "no step after the interrupt")
print("caught: " .. tostring(err))
