-- m:contact_model("linear") with no properties has
-- kn = 0 and the ball fell through the floor with no word. The first contact of such a rule now
-- warns once, naming the model and its zero stiffnesses.
local T = require("testlib")
local m = talus.model{ gravity = {0, -9.81} }
local warnings = {}
m:on_warning(function(text) warnings[#warnings + 1] = text end)
m:contact_model("linear")
m:wall{ points = {{-1, 0}, {1, 0}} }
m:ball{ pos = {0, 0.2}, radius = 0.05, density = 2600 }
m:ball{ pos = {0.5, 0.2}, radius = 0.05, density = 2600 }
m:solve{ time = 1 }
local found = 0
for _, w in ipairs(warnings) do
    if w:find("contact model 'linear' has no normal stiffness", 1, true) then
        found = found + 1
        T.check(w:find("kn = 0", 1, true), "the warning names kn: " .. w)
        T.check(w:find("pass through", 1, true), "the warning says what happens: " .. w)
    end
end
T.check(found == 1, "one warning for the rule (two balls went through), got " .. found)

-- A stiffness from the bodies is enough: no warning then.
local m2 = talus.model{ gravity = {0, -9.81} }
local w2 = {}
m2:on_warning(function(text) w2[#w2 + 1] = text end)
m2:contact_model("linear")
m2:wall{ points = {{-1, 0}, {1, 0}}, kn = 1e6 }
local b = m2:ball{ pos = {0, 0.2}, radius = 0.05, density = 2600 }
m2:solve{ time = 1 }
for _, w in ipairs(w2) do T.check(not w:find("no normal stiffness", 1, true), w) end
T.check(b.pos[2] > 0.045, "the ball stands on the wall whose kn it inherits")
T.done("input_nomodelprops")
