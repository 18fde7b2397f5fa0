-- SPDX-License-Identifier: MIT
-- talus_util/csv.lua: the one CSV writer of the libraries. One cell format everywhere: integers
-- exact (%d), other numbers with `digits` significant digits (%.<digits>g; 17, the default,
-- reads back to the same double), NaN as nan, infinities as inf and -inf, booleans as 1 and 0,
-- nil as an empty cell, strings quoted only when they hold a comma, a quote or a line break
-- (RFC 4180). Every write is checked: a full disk or a missing directory is an error naming the
-- file, never a short file.
local C = {}

C.DIGITS = 17

--- One cell's text.
function C.cell(v, digits)
    local t = type(v)
    if t == "number" then
        if math.type(v) == "integer" then return string.format("%d", v) end
        if v ~= v then return "nan" end
        if v == math.huge then return "inf" end
        if v == -math.huge then return "-inf" end
        return string.format("%." .. (digits or C.DIGITS) .. "g", v)
    elseif t == "nil" then
        return ""
    elseif t == "boolean" then
        return v and "1" or "0"
    end
    local s = tostring(v)
    if s:find('[,"\r\n]') then s = '"' .. s:gsub('"', '""') .. '"' end
    return s
end

local function line(cells, n, digits)
    local out = {}
    for k = 1, n do out[k] = C.cell(cells[k], digits) end
    return table.concat(out, ",") .. "\n"
end

--- Writes `header` (a list of names) and `rows` (lists of cells, one per header name) to
--- `file`. opts.digits: significant digits of non-integer numbers (default 17). Returns true,
--- or nil and "cannot write '<file>': <reason>".
function C.write(file, header, rows, opts)
    local digits = opts and opts.digits
    local f, err = io.open(file, "w")
    if not f then return nil, string.format("cannot write '%s': %s", file, tostring(err)) end
    local ok, why = f:write(line(header, #header, digits))
    for _, row in ipairs(rows) do
        if not ok then break end
        ok, why = f:write(line(row, #header, digits))
    end
    local closed, cwhy = f:close()
    if not ok or not closed then
        return nil, string.format("cannot write '%s': %s", file, tostring(why or cwhy))
    end
    return true
end

--- Rows given as tables with named fields: the columns `cols` (names) in that order.
function C.write_records(file, records, cols, opts)
    local rows = {}
    for i, r in ipairs(records) do
        local row = {}
        for k, name in ipairs(cols) do row[k] = r[name] end
        rows[i] = row
    end
    return C.write(file, cols, rows, opts)
end

return C
