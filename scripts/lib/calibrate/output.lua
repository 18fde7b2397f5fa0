-- SPDX-License-Identifier: MIT
-- calibrate/output.lua: a fit's rows as a Markdown table or a CSV file.
local Csv = require("talus_util.csv")
local raise = require("talus_util.errors").raise

local C = {}


local function fmt(x)
    if x == nil then return "-" end
    if type(x) == "number" then
        if x == math.floor(x) and math.abs(x) < 1e6 then return string.format("%d", x) end
        return string.format("%.5g", x)
    end
    return tostring(x)
end

--- Prints rows as a Markdown table with the given columns ({key, ...} or {{key, title}, ...}).
function C.print_table(rows, cols, out)
    out = out or io.write
    local keys, titles = {}, {}
    for i, c in ipairs(cols) do
        keys[i] = type(c) == "table" and c[1] or c
        titles[i] = type(c) == "table" and c[2] or c
    end
    out("| " .. table.concat(titles, " | ") .. " |\n")
    out(string.rep("|---", #cols) .. "|\n")
    for _, r in ipairs(rows) do
        local cells = {}
        for i, k in ipairs(keys) do cells[i] = fmt(r[k]) end
        out("| " .. table.concat(cells, " | ") .. " |\n")
    end
end

--- Writes rows as CSV (talus_util.csv: numbers at full precision unless `number_format`, "%.<n>g",
--- asks for n digits; strings quoted where they must be; missing values empty). An error naming
--- the file when it cannot be written.
function C.write_csv(file, rows, cols, number_format)
    local digits = number_format and tonumber(tostring(number_format):match("^%%%.(%d+)g$"))
    if number_format and not digits then
        raise("calibrate.write_csv: number_format must be \"%%.<digits>g\" (got %s)", tostring(number_format))
    end
    local ok, why = Csv.write_records(file, rows, cols, { digits = digits })
    if not ok then raise("calibrate.write_csv: " .. why) end
end

return C
