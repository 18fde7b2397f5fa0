-- SPDX-License-Identifier: MIT
-- talus_util/errors.lua: errors raised inside the shipped libraries point at the user's script.
-- `raise` gives the position of the first Lua function on the stack that is not a library file
-- (one below the folder this file's folder is in: scripts/lib, or its installed copy), the line
-- of the user's script that called the library, however deep inside the library the error was
-- found. `entry` wraps a library's public function so that every error inside it does the same.
local E = {}

local root = debug.getinfo(1, "S").source:match("^@(.*[/\\])talus_util[/\\]errors%.lua$")

--- Whether a chunk (debug.getinfo's `source`) is one of the shipped library files.
function E.in_library(source)
    return root ~= nil and source:sub(1, #root + 1) == "@" .. root
end

--- The stack level, counted from the function that called user_level, of the first Lua
--- function outside the libraries (2 when there is none).
local function user_level()
    local level = 3
    while true do
        local info = debug.getinfo(level, "S")
        if not info then return 2 end
        if info.what ~= "C" and not E.in_library(info.source) then return level - 1 end
        level = level + 1
    end
end

--- Raises msg (formatted with the further arguments, if any) at the user's line.
function E.raise(msg, ...)
    if select("#", ...) > 0 then msg = string.format(msg, ...) end
    error(msg, user_level())
end

--- An input error found inside a library: raised as a table that `entry` turns into
--- "<entry's name>: <message>" at the user's line.
function E.fail(fmt, ...)
    error({ talus_library_error = true, msg = string.format(fmt, ...) }, 0)
end

-- xpcall's handler: a library error (a table of E.fail, or a message whose position is a library
-- line: an engine call's error, say) becomes {msg = the message without that position}; an error
-- positioned in the user's code (a callback) stays as it is.
local function classify(e)
    if type(e) == "table" and e.talus_library_error then return e end
    if type(e) ~= "string" then return e end
    local level = 2
    while true do
        local info = debug.getinfo(level, "Sl")
        if not info then return e end
        if info.what ~= "C" then
            local at = info.short_src .. ":" .. tostring(info.currentline) .. ": "
            if e:sub(1, #at) == at then
                if not E.in_library(info.source) then return e end
                return { talus_library_error = true, msg = e:sub(#at + 1) }
            end
        end
        level = level + 1
    end
end

--- fn wrapped as a library entry point called `name` ("rockfall.analysis"): its errors are
--- raised at the user's line as "name: message".
function E.entry(name, fn)
    return function(...)
        local res = table.pack(xpcall(fn, classify, ...))
        if res[1] then return table.unpack(res, 2, res.n) end
        local e = res[2]
        if type(e) == "table" and e.talus_library_error then E.raise(name .. ": " .. e.msg) end
        error(e, 0)
    end
end

return E
