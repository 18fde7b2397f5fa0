-- SPDX-License-Identifier: MIT
local m = talus.model{}
talus.load_plugin("build/plugins/libtalus_not_there.so")
