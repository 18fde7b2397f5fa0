// SPDX-License-Identifier: MIT
// Wall userdata: a chain of segments moved by prescribed velocity and spin (PFC walls).
#include <cmath>

#include "field_accessors.hpp"
#include "lua_bindings.hpp"

namespace talus::lua {

namespace {

struct WallRef {
    LuaModel* lm;
    WallId id;
};

using namespace fields;
using W = WallRef;

void pushPoints(lua_State* L, void* self) {
    const std::vector<Vec2> pts = model<W>(self).wallPoints(id<W>(self));
    lua_createtable(L, static_cast<int>(pts.size()), 0);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        pushVec(L, pts[i]);
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
}

void setCenter(lua_State* L, void* self, int value, const std::string& what) {
    const Vec2 c = toVec(L, value, what);
    if (!std::isfinite(c.x()) || !std::isfinite(c.y()))
        throw ScriptError("wall: 'center' must be finite");
    model<W>(self).setWallCenter(id<W>(self), c);
}

const Field kWallFields[] = {
    {"id", "integer", "the wall's handle number", getIndex<W, &Model::wallVel>},
    {"points", "talus.Vec[]", "the chain's current vertices [m]", pushPoints},
    {"vel", "talus.Vec", "translational velocity [m/s]", get<W, &Model::wallVel>,
     set<W, &Model::setWallVel>},
    {"spin", "number", "angular velocity about the centre [rad/s]", get<W, &Model::wallSpin>,
     set<W, &Model::setWallSpin>},
    {"center", "talus.Vec", "centre of rotation [m]", get<W, &Model::wallCenter>, setCenter},
    {"force", "talus.Vec", "total force the balls exert on the wall in the last step [N]",
     get<W, &Model::wallForce>},
    {"kn", "number?", "own normal stiffness [N/m]; nil: not set",
     getProp<W, &Model::wallContactProp, kKn>, setProp<W, &Model::setWallContactProp, kKn>},
    {"ks", "number?", "own shear stiffness [N/m]; nil: not set",
     getProp<W, &Model::wallContactProp, kKs>, setProp<W, &Model::setWallContactProp, kKs>},
    {"fric", "number?", "own friction coefficient; nil: not set",
     getProp<W, &Model::wallContactProp, kFric>, setProp<W, &Model::setWallContactProp, kFric>},
    {"groups", "string[]", "the wall's group names", get<W, &Model::wallGroups>},
};

int w_servo(lua_State* L);

const Method kWallMethods[] = {
    {"set", objectSet, "writes several fields at once, in sorted name order",
     "fields: talus.WallFields", ""},
    {"add_group", addGroup<W, &Model::addWallGroup>, "adds the wall to a group", "name: string",
     ""},
    {"servo", w_servo,
     "sets the wall's servo (PFC's wall servo) and returns its state; w:servo() reads it",
     "options?: talus.ServoOptions", "table?"},
};

void describe(lua_State* L, void* self) {
    lua_pushfstring(L, "wall %d", static_cast<int>(id<W>(self).index));
}

const ObjectType kWallObject = {
    kWallType,   "wall",
    "w",         "a wall: a chain of segments moved by prescribed velocity and spin",
    kWallFields, kWallMethods,
    describe,
};

int w_servo(lua_State* L) {
    return catchexcept(L, [&] {
        WallRef& w = checkObject<WallRef>(L, 1, kWallObject, "servo");
        return servoWall(L, *w.lm, w.id);  // wrap_servo.cpp
    });
}

const ObjectType* const kTypes[] = {&kWallObject};

}  // namespace

extern const Binding kWallBinding = {"wall", {}, {}, kTypes, {}, {}};

void pushWall(lua_State* L, int model_index, WallId id) {
    newObject<WallRef>(L, model_index, kWallObject)->id = id;
}

}  // namespace talus::lua
