-- SPDX-License-Identifier: MIT
-- A ball by its id (PFC's `ball.find`): m:ball_by_id(id) returns the live ball with that id,
-- nil when there is none (deleted, never made, a clump's pebble); an id freed by a deletion
-- goes to the next ball made, as b.id says. Indexing the iterator m:balls() (a habit from
-- lists) is an error that says what to use; the iterator still works in a for loop and when
-- called directly.
local T = require("testlib")
local S = T.script()

local m = talus.model{}
local made = {}
for i = 1, 5 do made[i] = m:ball{ pos = { 3 * i, 0 }, radius = 1, density = 1000 } end
for i, b in ipairs(made) do
    local found = m:ball_by_id(b.id)
    T.check(found == b, "ball_by_id(" .. b.id .. ") is the ball made " .. i .. "th")
    T.check(found.pos[1] == 3 * i, "... at its place")
end
T.check(m:ball_by_id(99) == nil, "no ball 99")
T.check(m:ball_by_id(0) == nil and m:ball_by_id(-1) == nil, "ids start at 1")

-- Deleted: gone; its id goes to the next ball made.
local id3 = made[3].id
made[3]:delete()
T.check(m:ball_by_id(id3) == nil, "a deleted ball is not found")
local new = m:ball{ pos = { 100, 0 }, radius = 1, density = 1000 }
T.check(new.id == id3 and m:ball_by_id(id3) == new and m:ball_by_id(id3).pos[1] == 100,
    "the freed id belongs to the new ball")
T.check(m:ball_by_id(made[4].id) == made[4], "the others are unchanged")

-- Pebbles are not balls to the API (m:balls() skips them): not found either.
local c = m:clump{ pebbles = { { -0.5, 0, 0.5 }, { 0.5, 0, 0.5 } }, pos = { 50, 50 }, density = 1000 }
local n = 0
for _ in m:balls() do n = n + 1 end
T.check(n == 5, "m:balls() counts 5 balls beside the clump (got " .. n .. ")")
for id = 1, 20 do
    local b = m:ball_by_id(id)
    T.check(b == nil or (b.pos[2] == 0), "ball_by_id never returns a pebble (id " .. id .. ")")
end
T.check(c.alive, "the clump is there")

-- The iterator: in a for loop, called directly, but not indexed.
local it = m:balls()
T.check(it() ~= nil, "the iterator can be called directly")
local line = T.line() + 1
local err = T.fails(function() return m:balls()[3] end,
    { S .. ":" .. line .. ":", "balls(): m:balls() is an iterator for a for loop",
        "m:ball_by_id(id)", "m:ball_count()" }, "indexing m:balls()")
T.fails(function() return #m:balls() end, { "not a list" }, "the length of m:balls()")
T.fails(function() return m:walls()[1] end, { "walls(): m:walls() is an iterator", "m:wall_count()" },
    "indexing m:walls()")
T.fails(function() return m:contacts().x end, { "contacts(): m:contacts() is an iterator" },
    "indexing m:contacts()")
T.fails(function() return m:ball_by_id("one") end, { "ball_by_id: id" }, "a non-integer id")
T.check(err:find("for b in m:balls() do", 1, true), err)

T.done("ball_by_id")
