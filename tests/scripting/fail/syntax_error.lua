-- SPDX-License-Identifier: MIT
local m = talus.model{ gravity = {0, -9.81} }
m:ball{ pos = {0, 1}, radius = 0.1 density = 2600 }
