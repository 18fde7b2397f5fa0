-- SPDX-License-Identifier: MIT
-- A friction angle typed where a friction coefficient goes (RocFall and most rock-mechanics
-- tables give angles: `fric = 30` is a coefficient of 30, contacts that never slip) is accepted,
-- but with one warning per call through the model's warning channel naming tan(phi). Plausible
-- coefficients (up to 2, a friction angle of 63 degrees) give no warning.
local T = require("testlib")

local m = talus.model{ gravity = { 0, -9.81 } }
local warnings = {}
m:on_warning(function(text)
    -- only the friction warnings (the engine may have others to say about the scene)
    if text:find("friction coefficient", 1, true) then warnings[#warnings + 1] = text end
end)
local function expect(n, what)
    T.check(#warnings == n, string.format("%s: %d warning(s) expected, got %d:\n%s", what, n,
        #warnings, table.concat(warnings, "\n")))
end

m:contact_model("linear", { kn = 1e8, ks = 5e7, fric = 0.6 })
expect(0, "fric = 0.6")
m:contact_model("linear", { kn = 1e8, ks = 5e7, fric = 2 })
expect(0, "fric = 2 (63 degrees): plausible")

m:contact_model("linear", { kn = 1e8, ks = 5e7, fric = 30 })
expect(1, "fric = 30")
local w = warnings[1]
T.check(w:find("fric = 30 is a friction coefficient", 1, true), w)
T.check(w:find("for a friction angle of 30\u{b0} use fric = tan(30\u{b0}) = 0.577", 1, true), w)
T.check(w:find("contact_model 'linear'", 1, true), "the warning names the call: " .. w)

-- One warning for one call, naming every implausible coefficient (rrlinear's rolling one too).
warnings = {}
m:contact_model("rrlinear", { kn = 1e8, ks = 5e7, fric = 35, rr_fric = 10 }, { groups = { "a", "b" } })
expect(1, "two implausible coefficients in one call")
T.check(warnings[1]:find("fric = 35", 1, true) and warnings[1]:find("rr_fric = 10", 1, true),
    warnings[1])

-- Bodies: the constructor and the setter.
warnings = {}
local wall = m:wall{ points = { { -5, 0 }, { 5, 0 } }, fric = 0.5 }
local b = m:ball{ pos = { 0, 0.1 }, radius = 0.1, density = 2600, fric = 25 }
expect(1, "m:ball{fric = 25}")
b.fric = 0.4
expect(1, "b.fric = 0.4: plausible")
b.fric = 40
expect(2, "b.fric = 40")
wall.fric = 45
expect(3, "wall.fric = 45")
T.check(warnings[3]:find("tan(45\u{b0}) = 1", 1, true), warnings[3])
local c = m:clump{ pebbles = { { -0.1, 0, 0.1 }, { 0.1, 0, 0.1 } }, pos = { 3, 1 }, density = 2600,
    fric = 33 }
expect(4, "m:clump{fric = 33}")
c.fric = 0.5
expect(4, "c.fric = 0.5")

-- A contact's own property.
m:contact_model("linear", { kn = 1e8, ks = 5e7, fric = 0.5 })
m:cycle(20)
local contact
for k in m:contacts() do contact = k end
T.check(contact ~= nil, "the ball touches the wall")
contact:set_prop("fric", 28)
expect(5, "c:set_prop(\"fric\", 28)")
-- Not an angle either: a huge value is named implausible, without an angle to convert.
contact:set_prop("fric", 500)
expect(6, "fric = 500")
T.check(warnings[6]:find("not plausible", 1, true), warnings[6])

-- The rockfall module says it once, when the analysis is built (a RocFall user's first try),
-- and each rock's record keeps the engine's warning instead of one stderr line per rock.
local rockfall = require("rockfall")
local said = {}
local stderr = io.stderr
io.stderr = { write = function(_, text) said[#said + 1] = text end }
local ok, an = pcall(rockfall.analysis, {
    profile = { { 0, 10 }, { 10, 0 }, { 30, 0 } },
    materials = { slope = { model = "linear", props = { kn = 1e7, ks = 5e6, fric = 30 } } },
    seeders = { { kind = "point", at = { 0.5, 10.6 }, rock = { shape = "ball", radius = 0.3 } } },
    t_max = 0.05,
})
io.stderr = stderr
T.check(ok, tostring(an))
T.check(#said == 1 and said[1]:find("materials.slope: fric = 30 is a friction coefficient", 1, true)
    and said[1]:find("tan(30\u{b0}) = 0.577", 1, true), "rockfall.analysis warns once: " .. table.concat(said))
local rec = rockfall.run_rock(an, 1)
T.check(rec.warnings and rec.warnings[1]:find("fric = 30 is a friction coefficient", 1, true),
    "the rock's record holds the engine's warning")

T.done("input_friction_angle")
