-- SPDX-License-Identifier: MIT
-- The CLI: arguments in `arg` and `...`, talus preloaded and requirable, the version.
local T = require("testlib")
local expected_version = select(1, ...)
T.check(arg[0]:match("cli_args%.lua$"), "arg[0] is the script")
T.check(arg[1] == expected_version and arg[2] == "two words", "arg[1], arg[2]")
local a, b = ...
T.check(a == arg[1] and b == arg[2], "... holds the arguments")
T.check(require("talus") == talus, "require('talus') returns the preloaded module")
T.check(talus.version == expected_version, "talus.version = project version")
T.check(type(talus.models()) == "table", "talus.models()")
-- Every argument arrives in `...`, however many (lua.cli_many_args passes 300 more).
T.check(select("#", ...) == #arg, "... holds all " .. #arg .. " arguments")
T.check(select(#arg, ...) == arg[#arg], "the last argument")
T.done("cli_args")
