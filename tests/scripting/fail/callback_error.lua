-- SPDX-License-Identifier: MIT
local m = talus.model{}
m:ball{ pos = {0, 0}, radius = 0.1, density = 1 }
m:on_cycle(function(model, step)
    local t = nil
    return t.x  -- line 6: indexing nil inside the callback
end)
m:cycle(5)
