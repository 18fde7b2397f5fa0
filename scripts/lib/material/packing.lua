-- SPDX-License-Identifier: MIT
-- material/packing.lua: a packing (a genesis' result, a plain table) written to and read from a
-- Lua file, exactly (17 significant digits), so calibration loops reuse one genesis.
local raise = require("talus_util.errors").raise
local P = {}

local function ser(v, ind)
    if type(v) == "number" then
        if math.type(v) == "integer" then return tostring(v) end
        -- a relaxation without a force-carrying contact records the ratio math.huge
        if v ~= v then return "(0/0)" end
        if v == math.huge then return "(1/0)" end
        if v == -math.huge then return "(-1/0)" end
        return string.format("%.17g", v)
    elseif type(v) == "string" then return string.format("%q", v)
    elseif type(v) == "boolean" then return tostring(v)
    elseif type(v) == "table" then
        local parts = {}
        local n = #v
        for i = 1, n do parts[#parts + 1] = ser(v[i], ind) end
        local keys = {}
        for k in pairs(v) do
            if not (math.type(k) == "integer" and k >= 1 and k <= n) then keys[#keys + 1] = k end
        end
        table.sort(keys, function(a, b) return tostring(a) < tostring(b) end)
        for _, k in ipairs(keys) do parts[#parts + 1] = "[" .. ser(k) .. "]=" .. ser(v[k], ind) end
        return "{" .. table.concat(parts, ",") .. "}"
    end
    raise("material.save_packing: cannot write a " .. type(v))
end

--- Writes a packing as a Lua file (exact: 17 significant digits); an error naming the file when
--- it cannot be written.
function P.save(pk, file)
    local text = "return " .. ser(pk) .. "\n"
    local f, err = io.open(file, "w")
    local ok, why = f and f:write(text)
    local closed, cwhy = true, nil
    if f then closed, cwhy = f:close() end
    if not (f and ok and closed) then
        raise("material.save_packing: cannot write '%s': %s", file, tostring(err or why or cwhy))
    end
end

function P.load(file)
    local chunk, err = loadfile(file, "t", {})
    if not chunk then raise("material.load_packing: " .. err) end
    return chunk()
end

return P
