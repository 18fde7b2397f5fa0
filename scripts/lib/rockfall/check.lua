-- SPDX-License-Identifier: MIT
-- rockfall/check.lua: input checks. Input errors are raised as tables by `fail` and turned into
-- ordinary messages, "rockfall.<entry>: ...", at the line of the user's script that called the
-- entry point (`api`, talus_util.errors); unknown option names get the engine's did-you-mean.
local Err = require("talus_util.errors")
local Opt = require("talus_util.options")

local K = {}

K.fail = Err.fail
local fail = K.fail

--- A public entry point `rockfall.<name>`.
function K.api(name, fn) return Err.entry("rockfall." .. name, fn) end

function K.sorted_keys(t)
    local k = {}
    for key in pairs(t) do k[#k + 1] = tostring(key) end
    table.sort(k)
    return k
end

K.hint = Opt.hint

--- Refuses unknown option names (a typo is never ignored, as in the engine's API).
function K.check_keys(t, known, where)
    if type(t) ~= "table" then fail("%s must be a table (got %s)", where, type(t)) end
    local msg = Opt.unknown(t, known, where)
    if msg then fail("%s", msg) end
end

function K.num(v, where, lo, hi)
    if type(v) ~= "number" or v ~= v then fail("%s must be a number (got %s)", where, tostring(v)) end
    if lo and v < lo then fail("%s must be >= %g (got %g)", where, lo, v) end
    if hi and v > hi then fail("%s must be <= %g (got %g)", where, hi, v) end
    return v
end

function K.point(v, where)
    if type(v) ~= "table" or type(v[1]) ~= "number" or type(v[2]) ~= "number" or v[1] ~= v[1]
        or v[2] ~= v[2] then
        fail("%s must be a point {x, y} (got %s)", where, tostring(v))
    end
    return { v[1], v[2] }
end

function K.need_analysis(an)
    if type(an) ~= "table" or not an.is_analysis then
        fail("the first argument must be an analysis from rockfall.analysis{} (got %s)", tostring(an))
    end
end

--- A hook option (on_model, on_end) is a function or absent.
function K.check_hook(opts, name, where)
    if opts[name] ~= nil and type(opts[name]) ~= "function" then
        fail("%s.%s must be a function (got %s)", where, name, type(opts[name]))
    end
end

return K
