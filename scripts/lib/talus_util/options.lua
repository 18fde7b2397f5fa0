-- SPDX-License-Identifier: MIT
-- talus_util/options.lua: option tables checked as the engine checks its own: an unknown name is
-- never ignored, and the message suggests the nearest known name, worded as the engine's errors
-- ("unknown option 'ratoi'; did you mean 'ratio'? (known: ...)").
local O = {}

--- A set {name = true} from a list of names; a set is returned as it is.
function O.set_of(names)
    if names[1] == nil and next(names) ~= nil then return names end
    local s = {}
    for _, v in ipairs(names) do s[v] = true end
    return s
end

local function sorted_names(set)
    local k = {}
    for name in pairs(set) do k[#k + 1] = tostring(name) end
    table.sort(k)
    return k
end

--- "; did you mean 'x'?" for an unknown name among the list `known`, or "".
function O.hint(name, known)
    if type(name) ~= "string" or not (talus and talus.did_you_mean) then return "" end
    return talus.did_you_mean(name, known)
end

--- The message for the first (in sorted order) key of opts that is not in `known` (a list or a
--- set of names), or nil when every key is known. `where` (optional) names the table
--- ("analysis.seeders[2]"): "unknown option 'x' in analysis.seeders[2]; did you mean ...".
function O.unknown(opts, known, where)
    local set = O.set_of(known)
    local bad
    for k in pairs(opts) do
        if not set[k] and (bad == nil or tostring(k) < tostring(bad)) then bad = k end
    end
    if bad == nil then return nil end
    local names = sorted_names(set)
    return string.format("unknown option '%s'%s%s (known: %s)", tostring(bad),
        where and (" in " .. where) or "", O.hint(bad, names), table.concat(names, ", "))
end

--- Raises (with `raise`, default talus_util.errors' raise at the user's line; `prefix` put in
--- front, "material.genesis: ") when opts has an unknown key; see O.unknown.
function O.check(opts, known, where, prefix, raise)
    local msg = O.unknown(opts, known, where)
    if msg then (raise or require("talus_util.errors").raise)((prefix or "") .. msg) end
end

--- A new table with the entries of each argument in turn (later ones win; nil arguments are
--- skipped): a copy with some entries changed, the tables given left as they are.
function O.merged(...)
    local o = {}
    for i = 1, select("#", ...) do
        for k, v in pairs(select(i, ...) or {}) do o[k] = v end
    end
    return o
end

return O
