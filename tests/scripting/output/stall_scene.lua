-- SPDX-License-Identifier: MIT
-- A scene that never settles, for the progress lines and the watch on solve{ratio =}
-- (tests/scripting/output/progress_log.py): two balls held together by an unbreakable contact
-- bond, spinning about their common centre with no gravity and no damping. Each ball's only
-- force is the bond's, so the unbalanced force equals the contact force: the ratio stays at 1
-- for ever, however long the solve runs (and the pair stays where it is).
--   talus run stall_scene.lua MAX_TIME [handler]
-- `handler`: the script collects the model's warnings with m:on_warning and prints how many
-- said "not getting closer" (so stderr has none of them).
local max_time = tonumber(arg[1]) or 2
local m = talus.model{}
m:contact_model("cbond", { kn = 1e7, ks = 5e6, cb_tenf = math.huge, cb_shearf = math.huge,
    cb_bond = 1, cb_gap = 1e-6 })
m:ball{ pos = { -0.1, 0 }, radius = 0.1, density = 2600, vel = { 0, -1 } }
m:ball{ pos = { 0.1, 0 }, radius = 0.1, density = 2600, vel = { 0, 1 } }
local notices = 0
if arg[2] == "handler" then
    m:on_warning(function(text)
        if text:find("not getting closer", 1, true) then notices = notices + 1 end
    end)
end
local stop = m:solve{ ratio = 1e-5, max_time = max_time }
print(string.format("stall_scene: solve ended by %s after %d steps; notices to the handler: %d",
    stop, m:step(), notices))
