-- SPDX-License-Identifier: MIT
-- talus.map's checkpoint against damaged files (scripting/map_checkpoint.hpp): a rerun meets a
-- checkpoint whose item file had one bit flipped at every byte position in turn, or was cut
-- short at several lengths, and must take the whole items, run the damaged one again with a
-- note naming its file, and return results equal, bit for bit, to those of the undamaged run.
-- Items of the format before the checksum are still taken. Each rerun is its own `talus run`
-- of this script (mode "child"), so that its notes on stderr can be read.
-- Arguments: the talus command, an output directory.
local talus_cmd, out, mode = arg[1], arg[2], arg[3]
local N, KEY = 4, "damage test"
local dir = out .. "/map_checkpoint"

local function item(i)
    -- A value of every kind the format carries: integers, floats with exact bits, strings, nesting.
    return { i, i / 3, -0.0, "rock " .. i, { ok = i % 2 == 0 } }
end

local function run_map()
    return talus.map(N, item, { jobs = 1, checkpoint = dir, key = KEY })
end

if mode == "child" then
    local T = require("testlib")
    print("DIGEST " .. T.digest(run_map()))
    return
end

local T = require("testlib")
talus.mkdir(dir)
for i = 1, N do os.remove(dir .. "/item_" .. i .. ".tmv") end
local expected = T.digest(run_map())
-- The same values as fn computes them: the checkpoint stores exactly what the map returns.
local direct = {}
for i = 1, N do direct[i] = item(i) end
T.check(T.digest(direct) == expected, "the map's results are fn's values")

local function read(path)
    local f = assert(io.open(path, "rb"))
    local s = f:read("a")
    f:close()
    return s
end
local function write(path, s)
    local f = assert(io.open(path, "wb"))
    f:write(s)
    f:close()
end
local function quote(s) return "'" .. s:gsub("'", "'\\''") .. "'" end

local DAMAGED = 2
local path = dir .. "/item_" .. DAMAGED .. ".tmv"
local whole = read(path)
T.check(whole:sub(1, 17) == "talus.map item 2\n", "an item begins with its format line")

--- Reruns the map in a fresh process; returns its stderr and stdout together.
local function rerun()
    local cmd = quote(talus_cmd) .. " run " .. quote(arg[0]) .. " " .. quote(talus_cmd) .. " "
        .. quote(out) .. " child 2>&1"
    local p = assert(io.popen(cmd))
    local text = p:read("a")
    p:close()
    return text
end

--- A damaged item file: the rerun names it, runs its item again and returns the same results;
--- the file is whole again afterwards.
local function check_damaged(bytes, what)
    write(path, bytes)
    local text = rerun()
    T.check(text:find("DIGEST " .. expected, 1, true) ~= nil, what .. ": the results of the undamaged run: " .. text)
    T.check(text:find("the checkpoint file '" .. path .. "' is damaged", 1, true) ~= nil,
        what .. ": a note names the file: " .. text)
    T.check(text:find("fn(" .. DAMAGED .. ") runs again", 1, true) ~= nil, what .. ": the item runs again")
    T.check(text:find((N - 1) .. " of " .. N .. " items taken from the checkpoint", 1, true) ~= nil,
        what .. ": the whole items are taken: " .. text)
    T.check(read(path) == whole, what .. ": the item is stored again, whole")
end

-- One bit flipped at every byte position (the bit changes with the position).
for pos = 1, #whole do
    local b = whole:byte(pos) ~ (1 << ((pos - 1) % 8))
    check_damaged(whole:sub(1, pos - 1) .. string.char(b) .. whole:sub(pos + 1),
        string.format("bit %d of byte %d flipped", (pos - 1) % 8, pos))
end
-- Cut short: empty, inside the format line, the checksum, the key and the value, one byte short.
for _, len in ipairs { 0, 5, 20, 30, 40, #whole // 2, #whole - 1 } do
    check_damaged(whole:sub(1, len), "cut to " .. len .. " bytes")
end
-- One byte too many.
check_damaged(whole .. "\0", "a byte appended")

-- An item of the format before the checksum, whole, is still taken (and left as it is).
local body = whole:sub(18 + 8)
write(path, "talus.map item\n" .. body)
local text = rerun()
T.check(text:find("DIGEST " .. expected, 1, true) ~= nil, "an older item is taken: " .. text)
T.check(text:find(N .. " of " .. N .. " items taken", 1, true) ~= nil, "all items taken: " .. text)
T.check(not text:find("damaged", 1, true), "no note for a whole older item: " .. text)
-- ... and one whose value is cut short is damaged.
check_damaged("talus.map item\n" .. body:sub(1, #body - 3), "an older item cut short")

print(string.format("map_checkpoint: %d damaged variants of a %d-byte item, each run again", #whole + 9,
    #whole))
T.done("map_checkpoint")
